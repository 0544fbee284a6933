`default_nettype none
// Linear interpolator after USSR patent SU 1571551 (diagonal + axial steps).
//   inputs 22-26 (|X|, |Y|, L, S, L - S) ... axis_order u_order; trigger 15's input x_is_long
//   counters 1, 2 ......... updown_counter u_ctr1, u_ctr2
//   node 19 (adder 3, mux 12) faithful: accum_addsub u_adder + mux2 u_mux;
//                             exact: adder 3 as f_q plus look-ahead copies
//                             (carry_select_add u_add_axial/u_add_diagonal), mux2 u_mux
//   node 18 (AND 5, 6) .... sign_analysis u_sign; generator 4 is `tick`
//   node 20 (AND 7, 8, OR 10, 11) increment_former u_route; trigger 15 is x_is_long_q
//   node 21 (AND 9, OR 13, trigger 14) start_stop u_run; AND 9 is `at_end_q`
// F is held doubled (one extra LSB carries the patent's 0.5).
//
// Timing: `start` in an idle cycle loads the counters, F and trigger 15 from
// X, Y (the patent's inputs 22-26); the next cycle is the "start of frame"
// pulse, which sets trigger 14 and takes 1 from counter 2 (OR 13); from then
// on every cycle with `tick` high makes one step, shown on the registered
// step_x/step_y strobes one cycle later.  `done` is a one-cycle strobe after
// the last step.  `start` while busy is ignored.
//
// Speed.  Counters, F and the outputs hold the same values in every cycle as
// the plain circuit (the cycle model is the patent's); what is added are
// registers formed a cycle ahead:
// - AND 9, `busy` and the run enable of node 18 are registers; AND 9 comes
//   from two counters of the steps left (less 1, less 2), whose sign bits
//   say "none left" / "at most one left" after this edge, so no wide compare
//   is in the loop.  The patent's counters then feed only benches and traces
//   and synthesis drops them.
// - Exact mode: the sign decision is retimed onto look-ahead registers,
//   F + A and F + D (the two values the next step can give F), with the
//   operand of the coming step (mux 12) in a register; every adder is
//   register + register (carry select) into a register.  F itself is kept
//   for benches and traces (synthesis drops it).
// - Registers only the running core reads take their start values in every
//   idle cycle (the last one is the load), so their enables skip `start`;
//   they have no reset.
// The formal block proves the added registers equal to what they stand for.
module su1571551 #(
    parameter integer WIDTH = 32,   // width of the signed X, Y inputs (>= 2)
    parameter integer EXACT = 1,    // 0: faithful (the patent's live counters, expression (5))
                                    // 1: exact (operands held in registers, expression (1))
    parameter integer CARRY_SELECT = 1  // 1: adders in the step loop cut in two (carry select,
                                    // for slow carry chains: iCE40); 0: one chain each (ECP5)
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
        if (EXACT != 0 && EXACT != 1) $error("%m: EXACT must be 0 or 1");
        if (CARRY_SELECT != 0 && CARRY_SELECT != 1) $error("%m: CARRY_SELECT must be 0 or 1");
    end

    localparam integer CW = WIDTH + 1;  // counters: 0 .. 2^(WIDTH-1), and -1 for counter 2
    localparam integer FW = WIDTH + 2;  // doubled F: |2F| <= 2^WIDTH

    // ---- load values (the patent's external constants) ----
    wire             x_is_long;
    wire [CW-1:0]    long_len, short_len, axial_count;                // L, S, counter 1: L - S
    axis_order #(.WIDTH(WIDTH)) u_order (
        .x(x), .y(y), .x_is_long(x_is_long), .long_len(long_len), .short_len(short_len),
        .difference(axial_count)
    );
    wire [FW-1:0]    f_initial = {1'b0, long_len} - {short_len, 1'b0};  // 2 * (L/2 - S)

    // ---- node 21: start-stop ----
    // AND 9 (`at_end_q`), `busy_q` and `active_q` (= run & ~AND 9, the
    // enable of node 18) are registers formed a cycle ahead, so the step
    // enable and the loads are one gate from a register.
    wire run, accept, finish;   // finish = at_end_q (AND 9 is only set while running)
    reg  frame_q;           // "start of frame" pulse, the cycle after the load
    reg  x_is_long_q;       // trigger 15
    reg  busy_q, active_q, at_end_q;
    wire load = start & ~busy_q;
    // Registers that only the running core reads take their start values in
    // every idle cycle (the last one is the load), so their enables do not
    // depend on `start`.
    wire idle = ~busy_q;
    start_stop u_run (
        .clk(clk), .rst(rst), .start(frame_q), .stop(at_end_q),
        .run(run), .accept(accept), .finish(finish)
    );
    assign busy = busy_q;

    // ---- node 18: sign analysis ----
    wire f_negative, f_non_negative, axial, diagonal;
    sign_analysis u_sign (
        .tick(tick), .enable(active_q), .negative(f_negative),
        .pulse_pos(axial), .pulse_neg(diagonal)
    );

    // ---- counters 1, 2 ----
    wire [CW-1:0] ctr1, ctr1_n, ctr2, ctr2_n;
    wire          ctr2_dec = diagonal | frame_q;   // OR 13
    updown_counter #(.WIDTH(CW)) u_ctr1 (
        .clk(clk), .rst(rst), .load(load), .load_value(axial_count),     // 0 again at the end
        .inc(1'b0), .dec(axial), .dec2(1'b0), .q(ctr1), .q_n(ctr1_n)
    );
    updown_counter #(.WIDTH(CW)) u_ctr2 (
        .clk(clk), .rst(rst), .load(load | finish), .load_value(load ? short_len : {CW{1'b0}}),
        .inc(1'b0), .dec(ctr2_dec), .dec2(1'b0), .q(ctr2), .q_n(ctr2_n)
    );
    // AND 9 (counter 1 = 0 and counter 2 = -1: the L steps are made) is
    // formed a cycle ahead from two down-counters of the steps left, less 1
    // and less 2, whose sign bits say "none left" and "at most one left"; so
    // the end test reads two register bits, not a wide compare.  During a
    // move, steps left = counter 1 + counter 2 + 1 (the formal block proves
    // the flags equal to AND 9).  The patent's counters then feed nothing but
    // the benches and traces, and synthesis drops them.
    // Like F's look-ahead sums, the two counters are cleared while idle (to
    // 0 and -1) and take their start value through their adder, in the frame
    // cycle, from an operand register that holds L - 1 while idle and -1
    // after: every adder output goes straight into its register, with no
    // load multiplexer behind the carry chain.  In the frame cycle the
    // operand's sign says "none left" (L = 0).
    localparam integer CLO = CW * 2 / 5, CHI = CW - CLO;
    reg  [CW-1:0]  left1, left2;                        // steps left - 1, - 2
    reg  [CW-1:0]  left_op;                             // L - 1, then -1
    reg  [CHI-1:0] left_op_hi1;                         // its high part + 1
    wire [CW-1:0]  left1_sum, left2_sum;
    wire           step = axial | diagonal;
    // The step loop's registers advance on every tick while stepping and in
    // every cycle while not: idle (start values), the frame cycle (set-up of
    // the first step) and the last cycle (an update nobody reads; idle
    // reloads them).  So their enable is one gate of a register and `tick`.
    wire           advance = tick | ~active_q;
    carry_select_add #(.WIDTH(CW), .LOW(CLO), .SPLIT(CARRY_SELECT)) u_left1_add (
        .a(left1), .b(left_op), .b_high_plus1(left_op_hi1), .sum(left1_sum));
    carry_select_add #(.WIDTH(CW), .LOW(CLO), .SPLIT(CARRY_SELECT)) u_left2_add (
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

    // ---- node 19: mux 12 + adder 3 ----
    wire [FW-1:0] f;
    generate
        if (EXACT != 0) begin : g_exact
            // Expression (1): L - S and -S held for the whole move (doubled:
            // d2 and a2).  The sign decision is retimed.  Besides F (adder
            // 3's register, kept for the benches and traces; nothing reads
            // it, so synthesis drops it) the core keeps in registers the two
            // values the next step can give F, F + a2 and F + d2, and the
            // operand of the coming step (mux 12's output).  A step adds that
            // operand to all of them, so every adder is register + register
            // (carry select) straight into a register, and the sign of the
            // new F is a 2:1 choice between the two look-ahead signs.
            // Load: the look-ahead sums are 0 while idle; the operand
            // registers hold their start values (taken in every idle cycle,
            // so at the load too), the frame cycle adds them, and mux 12
            // then selects the first step's operand.
            // Carry select cuts the adders at LO.  A plain chain does not
            // read the high-part registers, but the kept mux hierarchy below
            // would keep them: so one bit there, not HI.
            localparam integer LO = CARRY_SELECT != 0 ? FW * 2 / 5 : FW - 1, HI = FW - LO;
            localparam [HI-1:0] HI_ONE = 1;
            reg  [CW-1:0] diagonal_q, axial_q;          // L - S, -S
            reg  [HI-1:0] diagonal_hi1_q, axial_hi1_q;  // high halves of d2, a2, plus one
            reg  [FW-1:0] f_q;
            reg  [FW-1:0] f_axial_q, f_diagonal_q;      // F + a2, F + d2
            reg  [FW-1:0] op_axial_q, op_diagonal_q;    // what the next update adds to each
            reg  [HI-1:0] op_axial_hi1_q, op_diagonal_hi1_q;
            reg           negative_q;                   // sign of F
            wire [FW-1:0] a2 = {axial_q, 1'b0};
            wire [FW-1:0] d2 = {diagonal_q, 1'b0};

            // start values, from the inputs
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

            // mux 12: the operand of the coming step, by the sign of the F
            // that step will see (the frame cycle makes no step: F stays).
            // One mux per operand register, the idle load folded into its
            // inputs (both inputs are the start value while idle), so the
            // decision is the last select before the register.
            wire negative_next = frame_q ? negative_q
                               : negative_q ? f_diagonal_q[FW-1] : f_axial_q[FW-1];
            // With fast carry chains (CARRY_SELECT = 0: ECP5) this path
            // is critical, so the muxes keep their hierarchy: otherwise ABC
            // merges the idle select into the decision and puts three LUTs
            // on it.  Where the adders are cut in two (iCE40) the merged form
            // is as fast and smaller.
            wire [FW+HI-1:0] axial_start    = {f_axial_init, f_axial_init[FW-1:LO] + HI_ONE};
            wire [FW+HI-1:0] diagonal_start = {f_diagonal_init, f_diagonal_init[FW-1:LO] + HI_ONE};
            wire [FW+HI-1:0] a2_op = {a2, axial_hi1_q}, d2_op = {d2, diagonal_hi1_q};
            wire [FW+HI-1:0] axial_in0    = idle ? axial_start : a2_op;
            wire [FW+HI-1:0] axial_in1    = idle ? axial_start : d2_op;
            wire [FW+HI-1:0] diagonal_in0 = idle ? diagonal_start : a2_op;
            wire [FW+HI-1:0] diagonal_in1 = idle ? diagonal_start : d2_op;
            wire [FW+HI-1:0] op_axial_next, op_diagonal_next;
            if (CARRY_SELECT == 0) begin : g_mux_kept
                (* keep_hierarchy *) mux2 #(.WIDTH(FW + HI)) u_mux (
                    .sel(negative_next), .in0(axial_in0), .in1(axial_in1), .out(op_axial_next));
                (* keep_hierarchy *) mux2 #(.WIDTH(FW + HI)) u_mux_copy (
                    .sel(negative_next), .in0(diagonal_in0), .in1(diagonal_in1), .out(op_diagonal_next));
            end else begin : g_mux_merged
                mux2 #(.WIDTH(FW + HI)) u_mux (
                    .sel(negative_next), .in0(axial_in0), .in1(axial_in1), .out(op_axial_next));
                mux2 #(.WIDTH(FW + HI)) u_mux_copy (
                    .sel(negative_next), .in0(diagonal_in0), .in1(diagonal_in1), .out(op_diagonal_next));
            end

            // adder 3 and its two look-ahead copies
            wire [FW-1:0] f_axial_sum, f_diagonal_sum;
            carry_select_add #(.WIDTH(FW), .LOW(LO), .SPLIT(CARRY_SELECT)) u_add_axial (
                .a(f_axial_q), .b(op_axial_q), .b_high_plus1(op_axial_hi1_q), .sum(f_axial_sum));
            carry_select_add #(.WIDTH(FW), .LOW(LO), .SPLIT(CARRY_SELECT)) u_add_diagonal (
                .a(f_diagonal_q), .b(op_diagonal_q), .b_high_plus1(op_diagonal_hi1_q), .sum(f_diagonal_sum));
            // F: the patent's register, cleared at the end of a move.
            always @(posedge clk) begin
                if (rst | finish)
                    f_q <= {FW{1'b0}};
                else if (load)
                    f_q <= f_initial;
                else if (axial | diagonal)
                    f_q <= f_q + op_axial_q;
            end
            // The look-ahead registers are cleared while idle (not by rst or
            // the end of a move): fewer terms in their enables.
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
                    {op_axial_q, op_axial_hi1_q}       <= op_axial_next;
                    {op_diagonal_q, op_diagonal_hi1_q} <= op_diagonal_next;
                    negative_q <= idle ? f_initial[FW-1] : negative_next;
                end
            end
            assign f              = f_q;
            assign f_negative     = negative_q;
            assign f_non_negative = ~negative_q;
        end else begin : g_faithful
            // Expression (5): counter 1 direct, counter 2 inverted (= -S while
            // counter 2 holds S - 1), live as they count down.
            wire [CW-1:0] operand;
            mux2 #(.WIDTH(CW)) u_mux (.sel(diagonal), .in0(ctr2_n), .in1(ctr1), .out(operand));
            accum_addsub #(.WIDTH(FW)) u_adder (
                .clk(clk), .rst(rst), .clear(finish), .load(load), .load_value(f_initial),
                .add(axial | diagonal), .operand({operand, 1'b0}), .cin(1'b0),
                .f(f), .negative(f_negative), .non_negative(f_non_negative)
            );
        end
    endgenerate

    // ---- node 20: increment former and registered outputs ----
    wire inc_x, inc_y;
    increment_former u_route (
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

    // Not every output is used in both modes; f is kept for benches and waves.
    wire unused = &{1'b0, run, accept, f_non_negative, ctr1, ctr1_n, ctr2, ctr2_n, f};

`ifdef FORMAL
    // Properties for SymbiYosys (formal/su1571551.sby).  After a start the
    // core emits exactly |X| steps on X and |Y| on Y, then `done`; no step
    // while idle; every step is caused by a tick.  The invariants below tie
    // the counters and F to the steps already emitted, so k-induction closes.
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
        assert (!(frame_q && run));
        if (busy) assert (x_is_long_q == (f_len_x >= f_len_y) && f_s <= f_l);
        if (frame_q) assert (ctr1 == f_l - f_s && ctr2 == f_s && !step_x && !step_y
                             && f == {1'b0, f_l} - {f_s, 1'b0});
        if (run) assert (ctr1 == f_l - f_s - f_axial && ctr2 == f_s - f_diag - 1'b1
                         && f_diag <= f_s && f_axial <= f_l - f_s);
        // AND 9 and the run enable, formed a cycle ahead from the steps left
        if (busy) assert (left2 == left1 - 1'b1 && left_op_hi1 == left_op[CW-1:CLO] + 1'b1);
        if (frame_q) assert (left1 == {CW{1'b0}} && left_op == ctr1 + ctr2 - 1'b1);
        if (run) assert (left1 == ctr1 + ctr2 && &left_op);
        assert (busy_q == (frame_q | run) && finish == at_end_q
                && at_end_q == (run && ctr1 == {CW{1'b0}} && &ctr2)
                && active_q == (run && !(ctr1 == {CW{1'b0}} && &ctr2)));
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
            always @(posedge clk) if (f_past_valid && !rst && !$past(rst) && run)
                assert ({{(PW-FW){f[FW-1]}}, f} == f_expect && g_exact.diagonal_q == f_l - f_s && g_exact.axial_q == -f_s
                        // the midpoint bounds: -2S <= 2F < 2(L - S) (or L = 0)
                        && $signed(f) >= -$signed({1'b0, f_s, 1'b0})
                        && ($signed(f) < $signed({1'b0, f_l - f_s, 1'b0}) || f_l == {CW{1'b0}}));
            // the retimed decision: look-ahead sums, operands and sign
            localparam integer LO = CARRY_SELECT != 0 ? FW * 2 / 5 : FW - 1;
            wire [FW-1:0] f_a2 = {g_exact.axial_q, 1'b0}, f_d2 = {g_exact.diagonal_q, 1'b0};
            wire [FW-1:0] f_op = g_exact.negative_q ? f_d2 : f_a2;
            always @(posedge clk) if (f_past_valid && !rst && !$past(rst) && busy) begin
                assert (g_exact.axial_hi1_q == f_a2[FW-1:LO] + 1'b1
                        && g_exact.diagonal_hi1_q == f_d2[FW-1:LO] + 1'b1
                        && g_exact.negative_q == f[FW-1]);
                if (frame_q)
                    assert (g_exact.f_axial_q == {FW{1'b0}} && g_exact.f_diagonal_q == {FW{1'b0}}
                            && g_exact.op_axial_q == f + f_a2 && g_exact.op_diagonal_q == f + f_d2);
                else
                    assert (g_exact.f_axial_q == f + f_a2 && g_exact.f_diagonal_q == f + f_d2
                            && g_exact.op_axial_q == f_op && g_exact.op_diagonal_q == f_op);
                assert (g_exact.op_axial_hi1_q == g_exact.op_axial_q[FW-1:LO] + 1'b1
                        && g_exact.op_diagonal_hi1_q == g_exact.op_diagonal_q[FW-1:LO] + 1'b1);
            end
        end
    endgenerate
`endif
endmodule
`default_nettype wire
