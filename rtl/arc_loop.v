// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// The midpoint decision loop of circ_arc's run loop (arc_stepper): the midpoint choice
// of the patent SU 1665343, carried to all eight octants of the lecture's accelerated
// circular interpolator, as counters.
//
// In an octant the leading step a and the minor step b are fixed; with p = P.a, q = P.b
// (P relative to the centre) and E = u^2 + v^2 - R^2:
//   T = E + 2p + q + 1 (F at the midpoint P + a + b/2),  diagonal a + b <=> (T < 0) == (q > 0);
//   axial:    E += 2p + 1,       T += 2p + 3,       p += 1;
//   diagonal: E += 2p + 2q + 2,  T += 2p + 2q + 5,  p += 1, q += 1;
// so T moves by {p + 1, 1} or {p + q + 2, 1}, and the loop holds only T, p + 1 and
// p + q + 2, each with one adder (mux_add) whose operand the decision picks.  While
// q < 0 the registers hold complements (~(x + {y, 1}) = ~x + {~y, 1}), so that the
// decision (T < 0) == (q > 0) is T's top bit, and p + 1 and p + q + 2 count down.
//
// The octant ends when the next point has p >= 0 (q > 0) or p + q >= 0 (q < 0): the signs
// of p + 1, and of p + q + 2 after a diagonal step or of p + q + 1 after an axial one;
// p + q + 1 < 0 is p + q + 2 <= 0, whose zero flag is registered: p + q + 2 grows by 1
// or 2 per step, so flags of its values 0, -1, -2 registered with the step give it.
//
// Reload.  The step into a new octant starts six reload cycles without a step: the
// load values are found in cycles 1 to 4 (arc_reload); cycle 4 clears T and p + q + 2,
// cycle 5 loads p + 1 with T's high bits and p + q + 2 with its value (0 + its adder's
// operand), cycle 6 loads T (0 + {p + 1, its low bit}: T = 0 picks p + 1's operand) and
// p + 1 with its value.  So the loads pass through the loop's own adders, with no load
// select in the loop.  Not running, T and p + q + 2 stay clear and p + 1 holds T's value,
// so a start is cycles 4 to 6.  `run` and the enables' terms are registered, so each
// enable is one LUT; a clear wins over an enable (the flip-flops' reset input).
module arc_loop #(
    parameter integer WIDTH = 32            // circ_arc's coordinate width (>= 6)
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             run,            // 1: step, 0: load, from the next cycle on (registered)
    input  wire             tick,           // step enable
    input  wire             step_token,     // a step was decided a cycle ago
    input  wire             diagonal_token, // and it was diagonal
    input  wire [WIDTH:0]   p_plus_1_load,  // arc_reload's load values
    input  wire [WIDTH:0]   axial_increment,
    input  wire             t_low_operand,
    input  wire             new_q_negative,
    output wire             go,             // a step is decided in this cycle
    output wire             diagonal,       // and it is diagonal
    output reg              idle,           // not running (registered)
    output reg  [5:1]       reload_cycle,   // reload cycles 1 .. 5
    output reg  [WIDTH+1:0] t_value,        // T (-T - 1 when q < 0)
    output reg  [WIDTH:0]   p_plus_1,       // p + 1 (complemented when q < 0)
    output reg  [WIDTH:0]   p_plus_q_plus_2,// p + q + 2 (complemented when q < 0)
    output reg              q_positive,     // q > 0
    output wire [WIDTH+1:0] e_next          // E after the step decided in this cycle
);
    initial begin
        if (WIDTH < 6) $error("%m: WIDTH must be at least 6");
    end

    localparam integer UW = WIDTH + 1;      // p, q and their sums
    localparam integer NW = WIDTH + 2;      // E and T
    localparam [UW-1:0] ZERO = {UW{1'b0}}, ONE = {{(UW-1){1'b0}}, 1'b1}, TWO = {{(UW-2){1'b0}}, 2'b10};
    localparam [NW-1:0] E_OFFSET = {{(NW-2){1'b0}}, 2'b10};   // E = T - (p + 1) - (p + q + 2) + 2

    reg            load_t;                  // reload cycle 6: T loads
    reg            reloading;               // reload cycles 1 .. 5, or not running
    reg            running;                 // `run`, registered
    reg            may_step;                // running and no reload cycle
    reg            clear;                   // T and p + q + 2 clear (reload cycle 4, not running)
    reg            load_p;                  // p + 1 loads (reload cycles 5, 6, not running)
    reg  [UW-1:0]  diagonal_increment;      // p + q + 2's diagonal step: +2 (-2 when q < 0)
    reg  [UW-1:0]  p_increment;             // p + 1's step: +1 (-1 when q < 0)
    reg            pq_is_0, pq_is_minus_1, pq_is_minus_2;  // p + q + 2 = 0, -1, -2 (a cycle ago)

    assign diagonal = t_value[NW-1];        // (T < 0) == (q > 0)
    // `run` is registered (running), and so are the enables' terms: may_step (running, no
    // reload cycle but the first, whose reload_cycle[1] is a term of its own), load_t,
    // load_p and reload_cycle[5], so each enable is one LUT.
    assign go = may_step && !reload_cycle[1] && tick;

    // One adder per register: T + {p + q + 2 or p + 1, 1} by the decision (T's low operand
    // bit is its load value's in cycle 6), p + 1 + its step or its load value (LOAD),
    // p + q + 2 + its diagonal or axial step by the decision.
    wire [NW-1:0] t_next;
    wire [UW-1:0] p_plus_1_next, p_plus_q_plus_2_next;
    mux_add #(.WIDTH(NW)) u_t_add (
        .a(t_value), .sel(diagonal), .c({p_plus_q_plus_2, 1'b1}), .d({p_plus_1, t_low_operand}), .sum(t_next));
    mux_add #(.WIDTH(UW), .LOAD(1)) u_p_add (
        .a(p_plus_1), .sel(load_p), .c(p_plus_1_load), .d(p_increment), .sum(p_plus_1_next));
    mux_add #(.WIDTH(UW)) u_pq_add (
        .a(p_plus_q_plus_2), .sel(diagonal), .c(diagonal_increment), .d(axial_increment), .sum(p_plus_q_plus_2_next));

    // The octant ends: p + 1 >= 0 (q > 0); p + q + 2 >= 0 after a diagonal step, p + q + 1 >= 0
    // after an axial one (q < 0).
    wire          q_negative = !q_positive;
    wire [UW-1:0] p1_true = p_plus_1 ^ {UW{q_negative}}, pq_true = p_plus_q_plus_2 ^ {UW{q_negative}};
    wire          pq_zero = step_token ? (diagonal_token ? pq_is_minus_2 : pq_is_minus_1) : pq_is_0;
    wire          pq1_negative = pq_true[UW-1] || pq_zero;             // p + q + 1 < 0
    wire          octant_end = q_positive ? !p1_true[UW-1] : diagonal ? !pq_true[UW-1] : !pq1_negative;
    // E = T - (p + 1) - (p + q + 2) + 2 (for the benches: the step stage shows it).
    assign e_next = (t_value ^ {NW{q_negative}}) - {p1_true[UW-1], p1_true} - {pq_true[UW-1], pq_true} + E_OFFSET;

    always @(posedge clk) begin
        if (rst) begin
            running      <= 1'b0;
            clear        <= 1'b1;
            load_p       <= 1'b1;
            load_t       <= 1'b0;
            idle         <= 1'b1;
            reload_cycle <= 5'd0;
            reloading    <= 1'b1;
            may_step     <= 1'b0;
        end else begin
            reload_cycle[1] <= go && octant_end;
            reload_cycle[2] <= reload_cycle[1];
            reload_cycle[3] <= reload_cycle[2];
            reload_cycle[4] <= reload_cycle[3] || (run && !running);   // a start begins here
            reload_cycle[5] <= reload_cycle[4];
            load_t       <= reload_cycle[5];
            reloading    <= (go && octant_end) || |reload_cycle[4:1] || !run || !running;
            running      <= run;
            clear        <= !run || reload_cycle[3];
            load_p       <= !running || reload_cycle[4] || reload_cycle[5];
            idle         <= !run;
            may_step     <= run && !reloading;
        end
    end
    always @(posedge clk) begin
        pq_is_0       <= pq_true == ZERO;
        pq_is_minus_1 <= pq_true == ~ZERO;
        pq_is_minus_2 <= pq_true == ~ONE;
        if (clear) t_value <= {NW{1'b0}};
        else if (load_t || go) t_value <= t_next;
        if (load_p || go) p_plus_1 <= p_plus_1_next;
        if (clear) p_plus_q_plus_2 <= ZERO;
        else if (reload_cycle[5] || go) p_plus_q_plus_2 <= p_plus_q_plus_2_next;
        if (reload_cycle[5]) begin
            q_positive         <= !new_q_negative;
            diagonal_increment <= new_q_negative ? ~ONE : TWO;
            p_increment        <= new_q_negative ? ~ZERO : ONE;
        end
    end
endmodule
`default_nettype wire
