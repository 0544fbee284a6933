// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Linear interpolator after USSR patent SU 1571551 (diagonal + axial steps).
// The patent's circuit, element by element, to read with the patent in hand.
//   inputs 22-24 (L - S, S, 0.5 L - S) and 25 (trigger 15's set), from X, Y:
//                                  axis_order u_inputs
//   counters 1, 2 ................ updown_counter u_counter1, u_counter2
//   node 18: generator 4, AND 5, 6  `tick`, sign_analysis u_node18 (axial = AND 5,
//                                  diagonal = AND 6: its outputs 16, 17)
//   node 19: adder 3, mux 12 ..... accum_addsub u_adder3, mux2 u_mux12
//   node 20: AND 7, 8, OR 10, 11 . increment_former u_node20
//   node 21: AND 9, OR 13, trigger 14  `and9`, `or13`, start_stop u_trigger14
//   trigger 15 (|X| >= |Y|) ...... x_is_long_q
//   input 26 ("start of frame") .. frame_q
// F is held doubled (one extra LSB carries the patent's 0.5).
//
// Two modes (EXACT), both the patent's:
//   0, faithful: expression (5), the circuit as drawn: mux 12 passes counter
//      1's direct outputs (diagonal step, F += C1) or counter 2's inverted
//      outputs (axial step, F -= C2), live as the counters count down;
//   1, exact: expression (1): mux 12 passes L - S and -S, held in two
//      registers for the whole move (the patent's own F, deviation <= 0.5).
// rtl/lin_exact.v is the exact mode retimed for speed (the production core);
// formal/lin_exact.sby proves it equal to this module with EXACT = 1.
//
// Timing: `start` in an idle cycle loads the counters, adder 3 and trigger 15
// from X, Y (inputs 22-25); the next cycle is the "start of frame" pulse
// (input 26), which sets trigger 14 and takes 1 from counter 2 through OR 13,
// so that its inverted outputs give -S.  From then on every cycle with `tick`
// high makes one step, shown on the registered step_x/step_y strobes one
// cycle later.  AND 9 (counter 1 = 0, counter 2 = -1: the L steps are made)
// resets trigger 14 and clears the counters, adder 3 and trigger 15; `done`
// is a one-cycle strobe after it.  `start` while busy is ignored.
module su1571551 #(
    parameter integer WIDTH = 32,   // width of the signed X, Y inputs (>= 2)
    parameter integer EXACT = 1     // 0: faithful (the patent's live counters, expression (5))
                                    // 1: exact (operands held in registers, expression (1))
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             start,
    input  wire             tick,   // generator 4
    input  wire [WIDTH-1:0] x,      // signed X increment
    input  wire [WIDTH-1:0] y,      // signed Y increment
    output reg              step_x,
    output reg              step_y,
    output reg              dir_x,  // 1 = negative direction
    output reg              dir_y,
    output wire             busy,
    output reg              done
);
    initial begin
        if (WIDTH < 2) $error("%m: WIDTH must be at least 2");
        if (EXACT != 0 && EXACT != 1) $error("%m: EXACT must be 0 or 1");
    end

    localparam integer CW = WIDTH + 1;  // counters: 0 .. 2^(WIDTH-1), and -1 for counter 2
    localparam integer FW = WIDTH + 2;  // doubled F: |2F| <= 2^WIDTH

    // ---- inputs 22-25: the patent's external constants, from X and Y ----
    wire             x_is_long;                                       // input 25
    wire [CW-1:0]    long_len, short_len, axial_count;                // L, S (input 23), L - S (22)
    axis_order #(.WIDTH(WIDTH)) u_inputs (
        .x(x), .y(y), .x_is_long(x_is_long), .long_len(long_len), .short_len(short_len),
        .difference(axial_count)
    );
    wire [FW-1:0]    f_initial = {1'b0, long_len} - {short_len, 1'b0};  // input 24: 2 * (L/2 - S)

    // ---- node 21: trigger 14, AND 9, OR 13 ----
    reg  frame_q;           // input 26: the "start of frame" pulse, the cycle after the load
    reg  x_is_long_q;       // trigger 15
    wire run, accept, finish;
    wire load = start & ~busy;
    wire [CW-1:0] ctr1, ctr1_n, ctr2, ctr2_n;
    // AND 9: counter 1's inverted outputs and counter 2's direct ones all high
    wire and9 = &{ctr1_n, ctr2};
    start_stop u_trigger14 (
        .clk(clk), .rst(rst), .start(frame_q), .stop(and9),
        .run(run), .accept(accept), .finish(finish)
    );
    assign busy = frame_q | run;

    // ---- node 18: AND 5 (F >= 0: axial), AND 6 (F < 0: diagonal) ----
    // The patent's AND 9 resets trigger 14 at once; here trigger 14 is a
    // register, so node 18 is also closed in the cycle AND 9 is high.
    wire f_negative, f_non_negative, axial, diagonal;
    sign_analysis u_node18 (
        .tick(tick), .enable(run & ~and9), .negative(f_negative),
        .pulse_pos(axial), .pulse_neg(diagonal)
    );

    // ---- counters 1 (L - S, less 1 per axial step), 2 (S, less 1 per diagonal step) ----
    wire or13 = diagonal | frame_q;     // OR 13
    updown_counter #(.WIDTH(CW)) u_counter1 (
        .clk(clk), .rst(rst), .load(load | finish), .load_value(load ? axial_count : {CW{1'b0}}),
        .inc(1'b0), .dec(axial), .dec2(1'b0), .q(ctr1), .q_n(ctr1_n)
    );
    updown_counter #(.WIDTH(CW)) u_counter2 (
        .clk(clk), .rst(rst), .load(load | finish), .load_value(load ? short_len : {CW{1'b0}}),
        .inc(1'b0), .dec(or13), .dec2(1'b0), .q(ctr2), .q_n(ctr2_n)
    );

    // ---- node 19: mux 12 + adder 3 ----
    // Mux 12's inputs: the operand of an axial step (in0) and of a diagonal one (in1).
    wire [CW-1:0] axial_operand, diagonal_operand, operand;
    generate
        if (EXACT != 0) begin : g_exact
            // Expression (1): -S and L - S held for the whole move, taken
            // in every idle cycle (the last one is the load).
            reg [CW-1:0] axial_q, diagonal_q;
            always @(posedge clk) begin
                if (!busy) begin
                    axial_q    <= -short_len;
                    diagonal_q <= axial_count;
                end
            end
            assign axial_operand    = axial_q;
            assign diagonal_operand = diagonal_q;
        end else begin : g_faithful
            // Expression (5): counter 2 inverted (= -C2 while it holds C2 - 1),
            // counter 1 direct, live as they count down.
            assign axial_operand    = ctr2_n;
            assign diagonal_operand = ctr1;
        end
    endgenerate
    mux2 #(.WIDTH(CW)) u_mux12 (
        .sel(diagonal), .in0(axial_operand), .in1(diagonal_operand), .out(operand));
    wire [FW-1:0] f;        // 2F
    accum_addsub #(.WIDTH(FW)) u_adder3 (
        .clk(clk), .rst(rst), .clear(finish), .load(load), .load_value(f_initial),
        .add(axial | diagonal), .operand({operand, 1'b0}), .cin(1'b0),
        .f(f), .negative(f_negative), .non_negative(f_non_negative)
    );

    // ---- node 20: AND 7, 8, OR 10, 11, and the registered outputs ----
    wire inc_x, inc_y;
    increment_former u_node20 (
        .axial(axial), .diagonal(diagonal), .x_is_long(x_is_long_q),
        .inc_x(inc_x), .inc_y(inc_y)
    );

    always @(posedge clk) begin
        if (rst) begin
            frame_q     <= 1'b0;
            x_is_long_q <= 1'b0;
            dir_x       <= 1'b0;
            dir_y       <= 1'b0;
            step_x      <= 1'b0;
            step_y      <= 1'b0;
            done        <= 1'b0;
        end else begin
            frame_q <= load;
            if (load) begin
                x_is_long_q <= x_is_long;
                dir_x       <= x[WIDTH-1];
                dir_y       <= y[WIDTH-1];
            end else if (finish) begin
                x_is_long_q <= 1'b0;
            end
            step_x <= inc_x;
            step_y <= inc_y;
            done   <= finish;
        end
    end

    // Not every output is read in both modes; f (2F) is kept for benches and waves.
    wire unused = &{1'b0, accept, f_non_negative, ctr1, ctr2_n, f};

`ifdef FORMAL
    // Properties for SymbiYosys (formal/su1571551.sby).  After a start the
    // core emits exactly |X| steps on X and |Y| on Y, then `done`; no step
    // while idle; every step is caused by a tick.  The invariants tie the
    // counters and F to the steps already emitted, so k-induction closes.
    reg f_past_valid = 1'b0;
    always @(posedge clk) f_past_valid <= 1'b1;
    always @(*) if (!f_past_valid) assume (rst);

    reg  [CW-1:0] f_len_x, f_len_y, f_cnt_x, f_cnt_y;  // |X|, |Y| of the move; steps seen
    wire [WIDTH-1:0] abs_x = x[WIDTH-1] ? -x : x;
    wire [WIDTH-1:0] abs_y = y[WIDTH-1] ? -y : y;
    always @(posedge clk) begin
        if (rst) begin
            f_len_x <= {CW{1'b0}}; f_len_y <= {CW{1'b0}};
            f_cnt_x <= {CW{1'b0}}; f_cnt_y <= {CW{1'b0}};
        end else if (load) begin
            f_len_x <= {1'b0, abs_x}; f_len_y <= {1'b0, abs_y};
            f_cnt_x <= {CW{1'b0}};    f_cnt_y <= {CW{1'b0}};
        end else begin
            f_cnt_x <= f_cnt_x + {{(CW-1){1'b0}}, step_x};
            f_cnt_y <= f_cnt_y + {{(CW-1){1'b0}}, step_y};
        end
    end
    // Steps taken so far, counting the strobes on the outputs right now.
    wire [CW-1:0] f_done_x = f_cnt_x + {{(CW-1){1'b0}}, step_x};
    wire [CW-1:0] f_done_y = f_cnt_y + {{(CW-1){1'b0}}, step_y};
    wire [CW-1:0] f_l = x_is_long_q ? f_len_x : f_len_y;
    wire [CW-1:0] f_s = x_is_long_q ? f_len_y : f_len_x;
    wire [CW-1:0] f_diag = x_is_long_q ? f_done_y : f_done_x;    // diagonal steps
    wire [CW-1:0] f_axial = (x_is_long_q ? f_done_x : f_done_y) - f_diag;
    always @(posedge clk) if (f_past_valid && !rst && !$past(rst)) begin
        // the step count: never beyond |X|, |Y|; exactly |X|, |Y| at done
        assert (f_cnt_x <= f_len_x && f_cnt_y <= f_len_y);
        assert (f_len_x <= {2'b01, {(CW-2){1'b0}}} && f_len_y <= {2'b01, {(CW-2){1'b0}}});
        if (done) assert (f_cnt_x == f_len_x && f_cnt_y == f_len_y);
        // no step while idle, so none after done; a step needs a tick
        if (step_x || step_y) assert (busy && $past(tick));
        if (!busy) assert (ctr1 == {CW{1'b0}} && ctr2 == {CW{1'b0}} && f == {FW{1'b0}}
                           && !x_is_long_q && !step_x && !step_y);
        // invariants of a move
        assert (!(frame_q && run) && (finish == and9));
        if (busy) assert (x_is_long_q == (f_len_x >= f_len_y) && f_s <= f_l);
        if (frame_q) assert (ctr1 == f_l - f_s && ctr2 == f_s && !step_x && !step_y
                             && f == {1'b0, f_l} - {f_s, 1'b0});
        if (run) assert (ctr1 == f_l - f_s - f_axial && ctr2 == f_s - f_diag - 1'b1
                         && f_diag <= f_s && f_axial <= f_l - f_s);
    end
    generate
        if (EXACT != 0) begin : g_formal_exact
            // Expression (1) in closed form, wide enough not to wrap:
            // 2F = L - 2S - 2aS + 2d(L - S) for a axial and d diagonal steps.
            localparam integer PW = 2 * CW + 4;
            wire [PW-1:0] f_l_w = {{(PW-CW){1'b0}}, f_l};
            wire [PW-1:0] f_s_w = {{(PW-CW){1'b0}}, f_s};
            wire [PW-1:0] f_expect = f_l_w - 2 * f_s_w - 2 * {{(PW-CW){1'b0}}, f_axial} * f_s_w
                                   + 2 * {{(PW-CW){1'b0}}, f_diag} * (f_l_w - f_s_w);
            always @(posedge clk) if (f_past_valid && !rst && !$past(rst) && busy)
                assert (g_exact.diagonal_q == f_l - f_s && g_exact.axial_q == -f_s);
            always @(posedge clk) if (f_past_valid && !rst && !$past(rst) && run)
                assert ({{(PW-FW){f[FW-1]}}, f} == f_expect
                        // the midpoint bounds: -2S <= 2F < 2(L - S) (or L = 0)
                        && $signed(f) >= -$signed({1'b0, f_s, 1'b0})
                        && ($signed(f) < $signed({1'b0, f_l - f_s, 1'b0}) || f_l == {CW{1'b0}}));
        end
    endgenerate
`endif
endmodule
`default_nettype wire
