// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Circular interpolator after USSR patent SU 1665343: one quadrant
// counter-clockwise from the start point to (0, R), continuous through 45°,
// two sectors, ones'-complement datapath.
//   adder 1 ................ accum_addsub u_adder1 (ones' complement, end-around carry)
//   AND 2, 3 / AND 10, 11 .. sign_analysis u_and2_3 (sector 1), u_and10_11 (sector 2)
//   trigger 4 (mode) ....... start_stop u_trigger4; input 33 = start, input 32 = rst,
//                            end of work = CT7 negative
//   generator 5 ............ `tick`
//   commutator 6 (elem. 37)  commutator u_commutator6
//   counters 7, 8 .......... updown_counter u_ct7, u_ct8 (ones' complement)
//   OR 9, 15, 17, 18, 20, 21, 27, 28  wires or9 ... or28
//   delay elements 12, 13, 14, 19, 26  delay_line u_delay12 ... u_delay26
//   trigger 16 (sector) .... start_stop u_trigger16 (set by input 34 or AND 22/23)
//   AND 22, 23 ............. sector-switch detectors (CT8 = -1 / -2 in sector 1)
//   pulse expander 25 ...... pulse_expander u_expander25
//   inputs 29, 30, 31, 34 .. the load former below computes F0 (formulas (3)/(4)),
//                            CT7, CT8 and T16 from r, x0, y0
//
// Set-up: `start` (when idle) captures r, x0, y0; the load former (adders only)
// then takes SETUP = 3 WIDTH + 8 cycles with `busy` high and, in cycle SETUP
// after `start`, either loads CT7, CT8, F and T16 and sets trigger 4 (the
// patent's input 33; the first step pulse follows in the next cycle) or gives
// the `error` strobe (in the cycle after).  `tick` does not gate the set-up.
//
// Timing (cycle 0 = the cycle a step pulse leaves AND 2/3/10/11, `tick` high):
//   cycle 0  counters count; step_x/step_y show the step in cycle 1
//   cycle 1  AND 22/23 look at CT8 (sector 1); CT7 negative ends the work
//   cycle 2  the step's transfer: F += commutator (delay 12, 13 or 14)
//   cycle 3  next pulse: 3 cycles per step
// A sector switch (once per arc) adds a correction; expander 25 holds the
// next pulse until cycle 6:
//   case A (AND 22): c1 CT8 += 1, F += {CT7, T16 = 0}, T16 := 1; c2 transfer; c3 CT7 -= 1
//   case B (AND 23): c1 CT8 += 1, T16 := 1; c2 transfer; c3 CT7 -= 1;
//                    c4 F += {CT7, T16}; c5 CT7 -= 1
// Bad input (R = 0, R > 2^(WIDTH-1) - 2, start point not within one step of
// the circle) gives a one-cycle `error` strobe after the set-up instead of a move.
module circ_su1665343 #(
    parameter integer WIDTH = 12    // CT7/CT8 width, ones' complement (4 .. 30); R <= 2^(WIDTH-1) - 2
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             start,  // input 33 (taken when idle)
    input  wire             tick,   // generator 5
    input  wire [WIDTH-1:0] r,      // radius
    input  wire [WIDTH-1:0] x0,     // start point in the first quadrant
    input  wire [WIDTH-1:0] y0,
    output reg              step_x, // output 36
    output reg              step_y, // output 35
    output reg              dir_x,  // 1: X decreases
    output reg              dir_y,
    output wire             busy,
    output reg              done,
    output reg              error   // start refused: bad R or start point
);
    initial if (WIDTH < 4 || WIDTH > 30) $error("%m: WIDTH must be 4 .. 30");

    localparam integer CW = WIDTH;          // counters
    localparam integer FW = WIDTH + 5;      // F: WIDTH + 3 integer bits, 2 fraction bits
    localparam integer PW = 2 * WIDTH + 4;  // load former accumulator: |E| < 2^(2 WIDTH + 1)
    localparam [CW-1:0] RMAX = {1'b0, {(CW-1){1'b1}}} - {{(CW-1){1'b0}}, 1'b1};   // 2^(W-1) - 2

    // ---- load former: inputs 29 (F0), 30 (CT7), 31 (CT8), 34 (Y >= X) ----
    // Sequential, adders only (no multiplier): `start` captures r, x0, y0; one
    // PW-bit accumulator ACC <= (ACC << s) + (op ^ inv) + cin then runs
    //   Horner, MSB first, bit i = WIDTH-1 .. 0, three micro-steps per bit:
    //     SU_R: ACC = 2 ACC + r_i R;  SU_X: ACC -= x_i X;  SU_Y: ACC -= y_i Y
    //   -> ACC = E = R^2 - X^2 - Y^2, and the tail:
    //     SU_A: ACC = E - 2R            (start point check: (R-1)^2 <= X^2 + Y^2 <=> E - 2R < 0)
    //     SU_B: ACC = E + 2R + 1        (X^2 + Y^2 <= (R+1)^2 <=> E + 2R + 1 >= 0)
    //     SU_C: ACC = E
    //     SU_D: ACC += 2X (Y >= X) or X
    //     SU_E: ACC += -Y - 1 or -2Y - 1: k of formula (4) or (3)
    //     SU_F: ACC = 4 k - 1           (4 F0 in two's complement)
    //     SU_G: ACC -= 1 if negative    (to ones' complement)
    //     SU_END: load (or refuse) in this cycle, SETUP cycles after `start`.
    localparam integer TOP_BIT = WIDTH - 1;   // set-up: SETUP = 3 WIDTH + 8 cycles
    localparam [3:0] SU_IDLE = 4'd0, SU_R = 4'd1, SU_X = 4'd2, SU_Y = 4'd3, SU_A = 4'd4, SU_B = 4'd5,
                     SU_C = 4'd6, SU_D = 4'd7, SU_E = 4'd8, SU_F = 4'd9, SU_G = 4'd10, SU_END = 4'd11;
    reg  [3:0]    su_state;
    reg  [4:0]    su_bit;                   // Horner's bit index
    reg  [CW-1:0] rq, xq, yq;               // captured r, x0, y0
    reg  [CW-1:0] rs, xs, ys;               // their copies shifted left once per bit: MSB = bit i
    reg  [PW-1:0] acc;
    reg           below, above, su_ok;      // E - 2R < 0, E + 2R + 1 >= 0, all checks passed
    reg           y_ge_x;                   // input 34
    reg  [CW-1:0] ct7_0, ct8_0;             // inputs 30, 31 (ones' complement)
    wire          setting_up = su_state != SU_IDLE;
    wire [PW-1:0] rr = {{(PW-CW){1'b0}}, rq};
    wire [PW-1:0] xx = {{(PW-CW){1'b0}}, xq};
    wire [PW-1:0] yy = {{(PW-CW){1'b0}}, yq};
    wire          acc_negative = acc[PW-1];
    reg  [PW-1:0] su_op;
    reg           su_inv, su_cin;
    reg  [1:0]    su_shift;
    always @(*) begin
        su_op = {PW{1'b0}};
        su_inv = 1'b0;
        su_cin = 1'b0;
        su_shift = 2'd0;
        case (su_state)
            SU_R: begin su_shift = 2'd1; su_op = rs[CW-1] ? rr : {PW{1'b0}}; end
            SU_X: begin su_op = xs[CW-1] ? xx : {PW{1'b0}}; su_inv = 1'b1; su_cin = 1'b1; end
            SU_Y: begin su_op = ys[CW-1] ? yy : {PW{1'b0}}; su_inv = 1'b1; su_cin = 1'b1; end
            SU_A: begin su_op = rr << 1; su_inv = 1'b1; su_cin = 1'b1; end
            SU_B: begin su_op = rr << 2; su_cin = 1'b1; end
            SU_C: begin su_op = rr << 1; su_inv = 1'b1; end
            SU_D: su_op = y_ge_x ? xx << 1 : xx;
            SU_E: begin su_op = y_ge_x ? yy : yy << 1; su_inv = 1'b1; end
            SU_F: begin su_shift = 2'd2; su_inv = 1'b1; end
            SU_G: su_inv = acc_negative;
            default: ;
        endcase
    end
    wire [PW-1:0] acc_next = (acc << su_shift) + (su_op ^ {PW{su_inv}}) + {{(PW-1){1'b0}}, su_cin};
    wire          r_ok = rq != {CW{1'b0}} && rq <= RMAX;
    wire [FW-1:0] f0 = acc[FW-1:0];
    // CT7 = Y, CT8 = X - Y - 1 in sector 1; CT7 = X - 1, CT8 = X - Y in sector 2.
    wire [CW-1:0] ct7_twos = y_ge_x ? xq - {{(CW-1){1'b0}}, 1'b1} : yq;
    wire [CW-1:0] ct8_twos = y_ge_x ? xq - yq : xq - yq - {{(CW-1){1'b0}}, 1'b1};

    wire idle_start = start & ~busy;
    wire su_end = su_state == SU_END;
    wire load = su_end & su_ok;
    wire refuse = su_end & ~su_ok;
    always @(posedge clk) begin
        if (rst) begin
            su_state <= SU_IDLE;
            su_bit <= 5'd0;
            rq <= {CW{1'b0}};
            xq <= {CW{1'b0}};
            yq <= {CW{1'b0}};
            rs <= {CW{1'b0}};
            xs <= {CW{1'b0}};
            ys <= {CW{1'b0}};
            acc <= {PW{1'b0}};
            below <= 1'b0;
            above <= 1'b0;
            su_ok <= 1'b0;
            y_ge_x <= 1'b0;
            ct7_0 <= {CW{1'b0}};
            ct8_0 <= {CW{1'b0}};
        end else begin
            y_ge_x <= yq >= xq;                 // r, x0, y0 are held from SU_R to SU_END
            ct7_0 <= ct7_twos - {{(CW-1){1'b0}}, ct7_twos[CW-1]};
            ct8_0 <= ct8_twos - {{(CW-1){1'b0}}, ct8_twos[CW-1]};
            if (su_state == SU_IDLE) begin
                if (idle_start) begin
                    rq <= r;
                    xq <= x0;
                    yq <= y0;
                    rs <= r;
                    xs <= x0;
                    ys <= y0;
                    acc <= {PW{1'b0}};
                    su_bit <= TOP_BIT[4:0];
                    su_state <= SU_R;
                end
            end else begin
                acc <= acc_next;
                case (su_state)
                    SU_R: su_state <= SU_X;
                    SU_X: su_state <= SU_Y;
                    SU_Y: begin
                        rs <= rs << 1;
                        xs <= xs << 1;
                        ys <= ys << 1;
                        su_bit <= su_bit - 5'd1;
                        su_state <= su_bit == 5'd0 ? SU_A : SU_R;
                    end
                    SU_END: su_state <= SU_IDLE;
                    default: su_state <= su_state + 4'd1;
                endcase
                if (su_state == SU_B) below <= acc_negative;
                if (su_state == SU_C) above <= ~acc_negative;
                if (su_state == SU_G) su_ok <= r_ok & below & above;
            end
        end
    end

    // ---- trigger 4 (mode) ----
    wire run, finish, t4_accept;
    wire [CW-1:0] ct7, ct7_n, ct8, ct8_n;
    wire ct7_negative = ct7[CW-1];
    start_stop u_trigger4 (
        .clk(clk), .rst(rst), .start(load), .stop(ct7_negative),
        .run(run), .accept(t4_accept), .finish(finish)
    );
    assign busy = run | setting_up;

    // ---- trigger 16 (sector): OR 18 ----
    wire t16, t16_set, t16_clear, and22, and23;
    wire or18 = (load & y_ge_x) | and22 | and23;
    start_stop u_trigger16 (
        .clk(clk), .rst(rst), .start(or18), .stop(finish),
        .run(t16), .accept(t16_set), .finish(t16_clear)
    );

    // ---- sign analysis: AND 2, 3 (sector 1), AND 10, 11 (sector 2) ----
    wire [1:0] d12, d13, d14;
    wire [1:0] d26;
    wire [3:0] d19;
    wire expanding;
    wire settle = (|d12) | (|d13) | (|d14) | expanding;   // a step or correction in flight
    wire enable = run & ~ct7_negative & ~settle;
    wire f_negative, f_non_negative;
    wire and2, and3, and10, and11;
    sign_analysis u_and2_3 (
        .tick(tick), .enable(enable & ~t16), .negative(f_negative),
        .pulse_pos(and3), .pulse_neg(and2)       // F >= 0: Y step; F < 0: diagonal
    );
    sign_analysis u_and10_11 (
        .tick(tick), .enable(enable & t16), .negative(f_negative),
        .pulse_pos(and10), .pulse_neg(and11)     // F >= 0: diagonal; F < 0: X step
    );
    wire or9 = and2 | and10;                     // diagonal

    // ---- delay elements 12, 13, 14: transfer two cycles after the pulse ----
    delay_line #(.LENGTH(2)) u_delay12 (.clk(clk), .rst(rst), .clear(finish), .d(or9),   .taps(d12));
    delay_line #(.LENGTH(2)) u_delay13 (.clk(clk), .rst(rst), .clear(finish), .d(and3),  .taps(d13));
    delay_line #(.LENGTH(2)) u_delay14 (.clk(clk), .rst(rst), .clear(finish), .d(and11), .taps(d14));

    // ---- AND 22, 23: sector switch after a sector-1 step (CT8 = -1 / -2) ----
    assign and22 = (d12[0] | d13[0]) & ~t16 & (ct8_n == {{(CW-1){1'b0}}, 1'b1});
    assign and23 = d12[0] & ~t16 & (ct8_n == {{(CW-2){1'b0}}, 2'b10});
    delay_line #(.LENGTH(2)) u_delay26 (.clk(clk), .rst(rst), .clear(finish), .d(and22), .taps(d26));
    delay_line #(.LENGTH(4)) u_delay19 (.clk(clk), .rst(rst), .clear(finish), .d(and23), .taps(d19));
    pulse_expander #(.LENGTH(4)) u_expander25 (
        .clk(clk), .rst(rst), .clear(finish), .trigger(and22 | and23), .active(expanding)
    );

    // ---- counters 7, 8 ----
    wire corr_ct7 = d19[1] | d19[3] | d26[1];                 // correction: CT7 -= 1
    wire or17 = or9 | and3 | and11 | corr_ct7;                // CT7 counts; T16 is its mode
    wire or20 = and3 | and11;                                 // CT8 -= 1 (axial step)
    wire or21 = and22 | and23;                                // CT8 += 1
    updown_counter #(.WIDTH(CW), .ONES_COMPLEMENT(1)) u_ct7 (
        .clk(clk), .rst(rst), .load(load | finish), .load_value(load ? ct7_0 : {CW{1'b0}}),
        .inc(or17 & ~t16), .dec(or17 & t16), .dec2(1'b0), .q(ct7), .q_n(ct7_n)
    );
    updown_counter #(.WIDTH(CW), .ONES_COMPLEMENT(1)) u_ct8 (
        .clk(clk), .rst(rst), .load(load | finish), .load_value(load ? ct8_0 : {CW{1'b0}}),
        .inc(or21), .dec(or20), .dec2(or9), .q(ct8), .q_n(ct8_n)   // dec2: subtract in bit 1
    );

    // ---- commutator 6 and adder 1 ----
    wire xfer_y = d13[1];                        // A1: {~CT7, 0} = -(2Y + 1)
    wire xfer_diag = d12[1];                     // A2: {CT8, ~T16} = 2(X - Y) - 1
    wire or15 = d14[1] | and22 | d19[2];         // A3: {CT7, T16} = 2X - 1, or the correction
    wire [CW:0] code;
    commutator #(.WIDTH(CW)) u_commutator6 (
        .sel1(xfer_y), .v1(ct7_n), .lsb1(1'b0),
        .sel2(xfer_diag), .v2(ct8), .lsb2(~t16),
        .sel3(or15), .v3(ct7), .lsb3(t16),
        .out(code)
    );
    // Integer codes enter with their sign copied into the two fraction bits.
    wire [FW-1:0] operand = {{(FW-CW-3){code[CW]}}, code, code[CW], code[CW]};
    wire [FW-1:0] f;
    accum_addsub #(.WIDTH(FW), .ONES_COMPLEMENT(1)) u_adder1 (
        .clk(clk), .rst(rst), .clear(finish), .load(load), .load_value(f0),
        .add(xfer_y | xfer_diag | or15), .operand(operand), .cin(1'b0),
        .f(f), .negative(f_negative), .non_negative(f_non_negative)
    );

    // Named for benches and waves: which transfer this cycle is.
    wire xfer_step = xfer_y | xfer_diag | d14[1];
    wire xfer_corr = and22 | d19[2];
    wire corr_end = d26[1] | d19[3];

    // ---- OR 27, 28: outputs 35, 36 ----
    wire or27 = or9 | and3;
    wire or28 = or9 | and11;
    always @(posedge clk) begin
        if (rst) begin
            step_x <= 1'b0;
            step_y <= 1'b0;
            dir_x  <= 1'b0;
            dir_y  <= 1'b0;
            done   <= 1'b0;
            error  <= 1'b0;
        end else begin
            step_x <= or28;
            step_y <= or27;
            if (load) begin
                dir_x <= 1'b1;          // counter-clockwise in the first quadrant
                dir_y <= 1'b0;
            end
            done  <= finish;
            error <= refuse;
        end
    end

    wire unused = &{1'b0, t4_accept, t16_set, t16_clear, f_non_negative, d26[0], d19[0], xfer_step, xfer_corr, corr_end, f};
endmodule
`default_nettype wire
