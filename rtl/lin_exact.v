// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Production linear core: SU 1571551's exact mode (expression (1)), retimed.
// Same ports and, cycle for cycle, the same outputs as su1571551 with EXACT = 1
// (formal/lin_exact.sby proves it); that module is the patent's circuit to read
// with the patent in hand, this one is the form to build.  The patent's
// elements are kept by name:
//   inputs 22-26 (|X|, |Y|, L, S, L - S) ... axis_order u_order; trigger 15 is x_is_long_q
//   counters 1, 2 ......... updown_counter u_counter1, u_counter2 (benches and traces only)
//   node 18 (AND 5, 6) .... sign_analysis u_node18; generator 4 is `tick`
//   node 19 (adder 3, mux 12) adder 3 as f_q plus two look-ahead copies
//                             (carry_select_add u_add_axial, u_add_diagonal), mux 12 as
//                             operand_mux u_mux12 (and its copy u_mux12_copy)
//   node 20 (AND 7, 8, OR 10, 11) increment_former u_node20
//   node 21 (AND 9, OR 13, trigger 14) start_stop u_trigger14; AND 9 is `at_end_q`
// F is held doubled (one extra LSB carries the patent's 0.5).
//
// Timing (as su1571551): `start` in an idle cycle loads the move; the next
// cycle is the "start of frame" pulse (trigger 14 set, counter 2 less 1);
// from then on every cycle with `tick` high makes one step, shown on the
// registered step_x/step_y strobes one cycle later.  `done` is a one-cycle
// strobe after the last step.  `start` while busy is ignored.
//
// What differs from su1571551 is only where the decisions are formed:
// - AND 9, `busy` and the run enable of node 18 are registers formed a cycle
//   ahead from two down-counters of the steps left (less 1, less 2), whose
//   sign bits say "none left" / "at most one left" after this edge: no wide
//   compare in the loop.  Counters 1 and 2 then feed only benches and traces
//   and synthesis drops them.
// - The sign decision is retimed onto look-ahead registers, F + A and F + D
//   (the two values the next step can give F), with the operand of the coming
//   step (mux 12) in a register; every adder is register + register into a
//   register.  F itself is kept for benches and traces (synthesis drops it).
// - Registers only the running core reads take their start values in every
//   idle cycle (the last one is the load), so their enables skip `start`;
//   they have no reset.
// The adders are carry_select_add: rtl/carry_select_add.v is one carry chain
// (ECP5's fast chains), rtl/ice40/carry_select_add.v cuts it in two (carry
// select); the synthesis file list picks the family's form.  The formal block
// proves the added registers equal to what they stand for.
module lin_exact #(
    parameter integer WIDTH = 32    // width of the signed X, Y inputs (>= 2)
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             start,
    input  wire             tick,
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
    end

    localparam integer CW = WIDTH + 1;  // counters: 0 .. 2^(WIDTH-1), and -1 for counter 2
    localparam integer FW = WIDTH + 2;  // doubled F: |2F| <= 2^WIDTH

    // ---- inputs 22-26: load values ----
    wire             x_is_long;
    wire [CW-1:0]    long_len, short_len, axial_count;                // L, S, counter 1: L - S
    axis_order #(.WIDTH(WIDTH)) u_order (
        .x(x), .y(y), .x_is_long(x_is_long), .long_len(long_len), .short_len(short_len),
        .difference(axial_count)
    );
    wire [FW-1:0]    f_initial = {1'b0, long_len} - {short_len, 1'b0};  // 2 * (L/2 - S)

    // ---- node 21: start-stop ----
    wire run, accept, finish;   // finish = at_end_q (AND 9 is only set while running)
    reg  frame_q;           // "start of frame" pulse (input 26), the cycle after the load
    reg  x_is_long_q;       // trigger 15
    reg  busy_q, active_q, at_end_q;
    wire load = start & ~busy_q;
    wire idle = ~busy_q;
    start_stop u_trigger14 (
        .clk(clk), .rst(rst), .start(frame_q), .stop(at_end_q),
        .run(run), .accept(accept), .finish(finish)
    );
    assign busy = busy_q;

    // ---- node 18: sign analysis (AND 5, 6) ----
    wire f_negative, axial, diagonal;
    sign_analysis u_node18 (
        .tick(tick), .enable(active_q), .negative(f_negative),
        .pulse_pos(axial), .pulse_neg(diagonal)
    );

    // ---- counters 1, 2 (benches and traces) ----
    wire [CW-1:0] ctr1, ctr1_n, ctr2, ctr2_n;
    wire          or13 = diagonal | frame_q;   // OR 13
    updown_counter #(.WIDTH(CW)) u_counter1 (
        .clk(clk), .rst(rst), .load(load | finish), .load_value(load ? axial_count : {CW{1'b0}}),
        .inc(1'b0), .dec(axial), .dec2(1'b0), .q(ctr1), .q_n(ctr1_n)
    );
    updown_counter #(.WIDTH(CW)) u_counter2 (
        .clk(clk), .rst(rst), .load(load | finish), .load_value(load ? short_len : {CW{1'b0}}),
        .inc(1'b0), .dec(or13), .dec2(1'b0), .q(ctr2), .q_n(ctr2_n)
    );

    // ---- AND 9 a cycle ahead: steps left ----
    // During a move, steps left = counter 1 + counter 2 + 1.  The two
    // counters are cleared while idle (to 0 and -1) and take their start value
    // through their adder in the frame cycle, from an operand register that
    // holds L - 1 while idle and -1 after: no load multiplexer behind the
    // carry chain.  In the frame cycle the operand's sign says "none left".
    localparam integer CLO = CW * 2 / 5, CHI = CW - CLO;
    reg  [CW-1:0]  left1, left2;                        // steps left - 1, - 2
    reg  [CW-1:0]  left_op;                             // L - 1, then -1
    reg  [CHI-1:0] left_op_hi1;                         // its high part + 1
    wire [CW-1:0]  left1_sum, left2_sum;
    wire           step = axial | diagonal;
    // The step loop's registers advance on every tick while stepping and in
    // every cycle while not (idle, the frame cycle, the last cycle), so their
    // enable is one gate of a register and `tick`.
    wire           advance = tick | ~active_q;
    carry_select_add #(.WIDTH(CW), .LOW(CLO)) u_left1_add (
        .a(left1), .b(left_op), .b_high_plus1(left_op_hi1), .sum(left1_sum));
    carry_select_add #(.WIDTH(CW), .LOW(CLO)) u_left2_add (
        .a(left2), .b(left_op), .b_high_plus1(left_op_hi1), .sum(left2_sum));
    wire [CW-1:0] long_len_less1 = long_len - {{(CW-1){1'b0}}, 1'b1};
    always @(posedge clk) begin     // no reset: loaded while idle, read only while running
        if (idle) begin
            left1       <= {CW{1'b0}};
            left2       <= {CW{1'b1}};
            left_op     <= long_len_less1;
            left_op_hi1 <= long_len_less1[CW-1:CLO] + {{(CHI-1){1'b0}}, 1'b1};
        end else begin
            if (advance) begin
                left1 <= left1_sum;
                left2 <= left2_sum;
            end
            left_op     <= {CW{1'b1}};
            left_op_hi1 <= {CHI{1'b0}};
        end
    end
    wire run_next  = frame_q | active_q;                 // trigger 14 after this edge
    wire none_left = frame_q ? left_op[CW-1]             // after this edge
                   : step ? left2[CW-1] : left1[CW-1];
    always @(posedge clk) begin
        if (rst) begin
            busy_q   <= 1'b0;
            active_q <= 1'b0;
            at_end_q <= 1'b0;
        end else begin
            busy_q   <= load | run_next;
            active_q <= run_next & ~none_left;
            at_end_q <= run_next & none_left;
        end
    end

    // ---- node 19: mux 12 + adder 3, retimed ----
    // L - S and -S held for the whole move (doubled: d2 and a2).  Besides F
    // (adder 3's register) the core keeps the two values the next step can
    // give F, F + a2 and F + d2, and the operand of the coming step (mux 12's
    // output).  A step adds that operand to both, so every adder is register
    // + register straight into a register, and the sign of the new F is a
    // 2:1 choice between the two look-ahead signs.  Load: the look-ahead sums
    // are 0 while idle; the operand registers hold their start values (taken
    // in every idle cycle, so at the load too), the frame cycle adds them, and
    // mux 12 then selects the first step's operand.  Each operand register
    // carries its high part plus one for the carry-select form of the adders
    // (the one-chain form ignores it, and synthesis drops it).
    localparam integer LO = FW * 2 / 5, HI = FW - LO;
    localparam [HI-1:0] HI_ONE = 1;
    reg  [CW-1:0] diagonal_q, axial_q;          // L - S, -S
    reg  [HI-1:0] diagonal_hi1_q, axial_hi1_q;  // high parts of d2, a2, plus one
    reg  [FW-1:0] f_q;
    reg  [FW-1:0] f_axial_q, f_diagonal_q;      // F + a2, F + d2
    reg  [FW-1:0] op_axial_q, op_diagonal_q;    // what the next update adds to each
    reg  [HI-1:0] op_axial_hi1_q, op_diagonal_hi1_q;
    reg           negative_q;                   // sign of F
    wire [FW-1:0] a2 = {axial_q, 1'b0};
    wire [FW-1:0] d2 = {diagonal_q, 1'b0};

    wire [CW-1:0] axial_init      = -short_len;
    wire [FW-1:0] f_axial_init    = f_initial + {axial_init, 1'b0};
    wire [FW-1:0] f_diagonal_init = f_initial + {axial_count, 1'b0};
    always @(posedge clk) begin
        if (idle) begin
            diagonal_q     <= axial_count;
            axial_q        <= axial_init;
            diagonal_hi1_q <= axial_count[CW-1:LO-1] + HI_ONE;
            axial_hi1_q    <= axial_init[CW-1:LO-1] + HI_ONE;
        end
    end

    // mux 12: the operand of the coming step, by the sign of the F that step
    // will see (the frame cycle makes no step: F stays).  One mux per operand
    // register, the idle load folded into its inputs, so the decision is the
    // last select before the register.  The operand muxes are operand_mux:
    // its portable form (ECP5) keeps the mux's hierarchy, otherwise ABC
    // merges the idle select into the decision and puts three LUTs on this
    // path (ECP5's critical one); its iCE40 form lets them merge (smaller, as
    // fast with the adders cut in two).  The high parts (read only by the
    // carry-select adders) have their own muxes, which synthesis drops with
    // the one-chain adders.
    wire negative_next = frame_q ? negative_q
                       : negative_q ? f_diagonal_q[FW-1] : f_axial_q[FW-1];
    wire [FW-1:0] op_axial_next, op_diagonal_next;
    wire [HI-1:0] op_axial_hi1_next, op_diagonal_hi1_next;
    operand_mux #(.WIDTH(FW)) u_mux12 (
        .sel(negative_next), .in0(idle ? f_axial_init : a2), .in1(idle ? f_axial_init : d2),
        .out(op_axial_next));
    operand_mux #(.WIDTH(FW)) u_mux12_copy (
        .sel(negative_next), .in0(idle ? f_diagonal_init : a2), .in1(idle ? f_diagonal_init : d2),
        .out(op_diagonal_next));
    mux2 #(.WIDTH(HI)) u_mux12_hi (
        .sel(negative_next),
        .in0(idle ? f_axial_init[FW-1:LO] + HI_ONE : axial_hi1_q),
        .in1(idle ? f_axial_init[FW-1:LO] + HI_ONE : diagonal_hi1_q),
        .out(op_axial_hi1_next));
    mux2 #(.WIDTH(HI)) u_mux12_copy_hi (
        .sel(negative_next),
        .in0(idle ? f_diagonal_init[FW-1:LO] + HI_ONE : axial_hi1_q),
        .in1(idle ? f_diagonal_init[FW-1:LO] + HI_ONE : diagonal_hi1_q),
        .out(op_diagonal_hi1_next));

    // adder 3's two look-ahead copies
    wire [FW-1:0] f_axial_sum, f_diagonal_sum;
    carry_select_add #(.WIDTH(FW), .LOW(LO)) u_add_axial (
        .a(f_axial_q), .b(op_axial_q), .b_high_plus1(op_axial_hi1_q), .sum(f_axial_sum));
    carry_select_add #(.WIDTH(FW), .LOW(LO)) u_add_diagonal (
        .a(f_diagonal_q), .b(op_diagonal_q), .b_high_plus1(op_diagonal_hi1_q), .sum(f_diagonal_sum));
    // adder 3: F, the patent's register, cleared at the end of a move
    always @(posedge clk) begin
        if (rst | finish)
            f_q <= {FW{1'b0}};
        else if (load)
            f_q <= f_initial;
        else if (step)
            f_q <= f_q + op_axial_q;
    end
    // The look-ahead registers are cleared while idle (not by rst or the end
    // of a move): fewer terms in their enables.
    always @(posedge clk) begin
        if (idle) begin
            f_axial_q    <= {FW{1'b0}};
            f_diagonal_q <= {FW{1'b0}};
        end else if (advance) begin
            f_axial_q    <= f_axial_sum;
            f_diagonal_q <= f_diagonal_sum;
        end
    end
    always @(posedge clk) begin
        if (advance) begin
            op_axial_q        <= op_axial_next;
            op_diagonal_q     <= op_diagonal_next;
            op_axial_hi1_q    <= op_axial_hi1_next;
            op_diagonal_hi1_q <= op_diagonal_hi1_next;
            negative_q        <= idle ? f_initial[FW-1] : negative_next;
        end
    end
    wire [FW-1:0] f = f_q;      // 2F, for benches and traces
    assign f_negative = negative_q;

    // ---- node 20: increment former and registered outputs ----
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

    // Kept for benches and waves only.
    wire unused = &{1'b0, run, accept, ctr1, ctr1_n, ctr2, ctr2_n, f};

`ifdef FORMAL
    `include "lin_exact_properties.vh"
`endif
endmodule
`default_nettype wire
