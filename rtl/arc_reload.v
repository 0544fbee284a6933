// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// The load values of the midpoint loop (arc_stepper, circ_arc's run loop; the lecture's
// accelerated circular interpolator, its octant change): T, p + 1 and p + q + 2 for the
// start point and for each new octant.
//
// After the step into a new octant p' = (p + 1) - 1 and q' = (p + q + 2) - (p + 1) - 1,
// and the new octant's T = E + 2p + q + 1 changes by -2p' - q' + 2p_new + q_new.  The
// four kinds of load:
//   TURN (q > 0: b turns; p_new = p', q_new = -q'):  T - 2q', p + 1, 2(p + 1) - (p + q + 2) + 2;
//   SWAP (q < 0: a and b swap; p_new = q', q_new = p'):  T - p' + q', q' + 1, p + q + 2;
//   SWAP_TURN (q < 0 and q' = 0; p_new = 0, q_new = -p'):  T - 3p', 1, 2 - p';
//   LOAD (the start point, E = 0):  2p + q + 1, p + 1, p + q + 2.
// Each value is a + b + c + k (k a constant), complemented for q_new < 0
// (~x = ~a + ~b + ~c + 2 - k), because the loop's registers hold complements while q < 0.
//
// Cycle 1 of a reload finds the kind (SWAP_TURN: q = -1 before a diagonal step; with q < 0
// the registers hold complements, so q + 1 = (p + 1) - (p + q + 2) in them, and q = -1
// when the two registers are equal); cycle 2 registers the operands, complemented as the
// kind says; cycle 3 sums them with k in carry-save form; cycle 4 resolves the sums with
// one adder each (p + 1's adder first resolves T's high bits); cycles 5 and 6 load them
// through the loop's own adders (arc_loop).  While idle the kind is LOAD and the values
// follow the start point.
module arc_reload #(
    parameter integer WIDTH = 32            // circ_arc's coordinate width (>= 6)
) (
    input  wire             clk,
    input  wire             idle,           // not running (registered): LOAD, follow the inputs
    input  wire             reload_cycle_1, // the kind is found (held through the reload)
    input  wire             reload_cycle_3,
    input  wire             reload_cycle_4,
    input  wire             reload_cycle_5,
    input  wire             diagonal_token, // the step just taken was diagonal
    input  wire             q_positive,     // the loop's q > 0 (its registers hold complements if not)
    input  wire [WIDTH+1:0] t_value,        // the loop's registers, as they hold them
    input  wire [WIDTH:0]   p_plus_1,
    input  wire [WIDTH:0]   p_plus_q_plus_2,
    input  wire [WIDTH:0]   start_p,        // LOAD: P.a, P.b of the start point
    input  wire [WIDTH:0]   start_q,
    input  wire             start_q_negative,   // a cycle before start_q
    output reg  [WIDTH:0]   p_plus_1_load,  // T's high bits in cycle 5, p + 1's value in cycle 6
    output reg  [WIDTH:0]   axial_increment,// p + q + 2's value in cycle 5, then +1 (-1 for q < 0)
    output reg              t_low_operand,  // T's value's low bit in cycle 6, else 1
    output wire             new_q_negative, // q_new < 0 (from cycle 2 on)
    output reg              kind_swap_turn  // the reload is a SWAP_TURN
);
    initial begin
        if (WIDTH < 6) $error("%m: WIDTH must be at least 6");
    end

    localparam integer UW = WIDTH + 1;      // p, q and their sums
    localparam integer NW = WIDTH + 2;      // T
    // The constants k per kind (LOAD with q > 0, with q < 0; TURN; SWAP; SWAP_TURN): k, or
    // 2 - k for a complemented value, less 1 for each zero operand left out of a complement
    // (it would be ~0 = -1).
    localparam integer T_LOAD = 1, T_LOAD_NEGATIVE = 1, T_TURN = -1, T_SWAP = 1, T_SWAP_TURN = -3;
    localparam integer P_LOAD = 1, P_LOAD_NEGATIVE = 0, P_TURN = 1, P_SWAP = 1, P_SWAP_TURN = 0;
    localparam integer PQ_LOAD = 2, PQ_LOAD_NEGATIVE = -1, PQ_TURN = -2, PQ_SWAP = 0, PQ_SWAP_TURN = -3;
    localparam integer GROUPS = (UW + 3) / 4;

    reg               kind_load, kind_turn, kind_swap;   // the kind, one-hot (with kind_swap_turn)
    reg               load_q_negative;                   // LOAD: q < 0
    reg  [GROUPS-1:0] q_minus_1_groups;                  // 4-bit groups of p + 1 = p + q + 2 (a cycle old)
    reg  [NW-1:0]     t_operand_a, t_operand_b, t_operand_c;         // cycle 2: the operands
    reg  [NW-1:0]     t_constant, p_constant, pq_constant;           // and the constants
    reg  [UW-1:0]     p_operand_a, p_operand_b, pq_operand_a, pq_operand_b;
    reg  [UW-1:0]     p_load_sum, p_load_carries;        // cycle 4: T's high bits, then p + 1, carry-save
    reg  [UW-1:0]     pq_load_sum, pq_load_carries;      // p + q + 2, then its step (+1 or -1)

    function automatic [GROUPS-1:0] equal_groups(input [UW-1:0] a, b);
        integer i;
        reg [4*GROUPS-1:0] x;
        begin
            x = {{(4*GROUPS-UW){1'b0}}, a ^ b};
            for (i = 0; i < GROUPS; i = i + 1) equal_groups[i] = x[4*i +: 4] == 4'd0;
        end
    endfunction
    function automatic [NW-1:0] extend(input [UW-1:0] x);          // sign-extended
        extend = {x[UW-1], x};
    endfunction
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [NW-1:0] constant(input integer k);          // -8 .. 7, NW bits
        constant = {{(NW-4){k[3]}}, k[3:0]};
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    // One-hot select of the four kinds' operands {SWAP_TURN, SWAP, TURN, LOAD}.
    function automatic [NW-1:0] pick(input [3:0] kind, input [NW-1:0] load_v, turn_v, swap_v, swap_turn_v);
        pick = ({NW{kind[0]}} & load_v) | ({NW{kind[1]}} & turn_v) | ({NW{kind[2]}} & swap_v) |
               ({NW{kind[3]}} & swap_turn_v);
    endfunction
    function automatic [NW-1:0] pick_constant(input [3:0] kind, input negative,
                                              input integer k_load, k_load_negative, k_turn, k_swap, k_swap_turn);
        pick_constant = pick(kind, negative ? constant(k_load_negative) : constant(k_load), constant(k_turn),
                             constant(k_swap), constant(k_swap_turn));
    endfunction
    /* verilator lint_off UNUSEDSIGNAL */        // the carries' top bits
    function automatic [2*NW-1:0] carry_save(input [NW-1:0] a, b, c);   // {carries, sum} of a + b + c
        reg [NW-1:0] m;
        begin
            m = (a & b) | (a & c) | (b & c);
            carry_save = {m[NW-2:0], 1'b0, a ^ b ^ c};
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */

    // SWAP_TURN: with q < 0 the step just taken (diagonal) made q' = 0.
    wire swap_turn_w = &q_minus_1_groups && diagonal_token;
    // The kind's next value and constants (registered with the kind, from its inputs: no
    // logic shared with the operands' selects behind the kind's registers).
    wire [3:0] kind_w = {!idle && !q_positive && swap_turn_w, !idle && !q_positive && !swap_turn_w,
                         !idle && q_positive, idle};
    wire [3:0] kind = {kind_swap_turn, kind_swap, kind_turn, kind_load};
    assign new_q_negative = kind_load ? load_q_negative : !kind_swap;

    // The operands, complemented where q_new < 0; TURN: q > 0, q_new < 0; SWAP: q < 0, q_new > 0;
    // SWAP_TURN: q < 0, q_new < 0.
    wire [NW-1:0] zero = {NW{1'b0}}, load_mask = {NW{load_q_negative}};
    wire [NW-1:0] p_twice = {start_p, 1'b0}, p1_twice = {p_plus_1, 1'b0};
    wire [NW-1:0] p1_extended = extend(p_plus_1), pq_extended = extend(p_plus_q_plus_2);
    wire [NW-1:0] t_a = pick(kind, p_twice ^ load_mask, ~t_value, ~t_value, t_value);
    wire [NW-1:0] t_b = pick(kind, extend(start_q) ^ load_mask, {p_plus_q_plus_2, 1'b0}, ~pq_extended, ~p1_extended);
    wire [NW-1:0] t_c = pick(kind, load_mask, ~p1_twice, {p_plus_1, 1'b1}, {~p_plus_1, 1'b0});
    /* verilator lint_off UNUSEDSIGNAL */        // p + 1 and p + q + 2 are one bit narrower
    wire [NW-1:0] p_a = pick(kind, extend(start_p) ^ load_mask, ~p1_extended, ~pq_extended, ~zero);
    wire [NW-1:0] p_b = pick(kind, load_mask, ~zero, p1_extended, ~zero);
    wire [NW-1:0] pq_a = pick(kind, extend(start_p) ^ load_mask, ~p1_twice, ~pq_extended, ~p1_extended);
    wire [NW-1:0] pq_b = pick(kind, extend(start_q) ^ load_mask, pq_extended, zero, ~zero);
    wire [2*NW-1:0] t_sum_1 = carry_save(t_operand_a, t_operand_b, t_operand_c);
    wire [2*NW-1:0] t_sum   = carry_save(t_sum_1[NW-1:0], t_sum_1[2*NW-1:NW], t_constant);
    wire [2*NW-1:0] p_sum   = carry_save(extend(p_operand_a), extend(p_operand_b), p_constant);
    wire [2*NW-1:0] pq_sum  = carry_save(extend(pq_operand_a), extend(pq_operand_b), pq_constant);
    /* verilator lint_on UNUSEDSIGNAL */
    // Cycle 4 resolves the values: p + q + 2's, and T's high bits for p + 1 (T's low bit
    // needs no sum: the carries' is 0), which takes its own in cycle 5.  One adder for the
    // two, its operands picked as they are registered, so no LUT follows its chain; so
    // also p + q + 2's adder, whose operands are its step (+1 or -1) from cycle 5 on, so
    // that the step register axial_increment holds its load value in cycle 5.
    wire [UW-1:0] p_load_w, pq_load_w;
    wire [1:0]    unused_carries;
    chain_add #(.WIDTH(UW)) u_p_load_add (
        .a(p_load_sum), .b(p_load_carries), .cin(1'b0), .sum(p_load_w), .cout(unused_carries[0]));
    chain_add #(.WIDTH(UW)) u_pq_load_add (
        .a(pq_load_sum), .b(pq_load_carries), .cin(1'b0), .sum(pq_load_w), .cout(unused_carries[1]));

    always @(posedge clk) begin
        // Every cycle: valid in the reload cycles and (from the start point's p and q) while idle.
        q_minus_1_groups <= equal_groups(p_plus_1, p_plus_q_plus_2);
        if (idle || reload_cycle_1) begin         // held through the reload
            {kind_swap_turn, kind_swap, kind_turn, kind_load} <= kind_w;
            t_constant  <= pick_constant(kind_w, start_q_negative, T_LOAD, T_LOAD_NEGATIVE, T_TURN, T_SWAP,
                                         T_SWAP_TURN);
            p_constant  <= pick_constant(kind_w, start_q_negative, P_LOAD, P_LOAD_NEGATIVE, P_TURN, P_SWAP,
                                         P_SWAP_TURN);
            pq_constant <= pick_constant(kind_w, start_q_negative, PQ_LOAD, PQ_LOAD_NEGATIVE, PQ_TURN, PQ_SWAP,
                                         PQ_SWAP_TURN);
        end
        load_q_negative <= start_q_negative;
        t_operand_a  <= t_a;
        t_operand_b  <= t_b;
        t_operand_c  <= t_c;
        p_operand_a  <= p_a[UW-1:0];
        p_operand_b  <= p_b[UW-1:0];
        pq_operand_a <= pq_a[UW-1:0];
        pq_operand_b <= pq_b[UW-1:0];
        t_low_operand   <= !reload_cycle_5 || t_sum[0];
        p_load_sum      <= reload_cycle_4 ? p_sum[UW-1:0] : t_sum[NW-1:1];
        p_load_carries  <= reload_cycle_4 ? p_sum[NW+UW-1:NW] : t_sum[2*NW-1:NW+1];
        pq_load_sum     <= idle || reload_cycle_3 ? pq_sum[UW-1:0] : new_q_negative ? {UW{1'b1}} : {{(UW-1){1'b0}}, 1'b1};
        pq_load_carries <= idle || reload_cycle_3 ? pq_sum[NW+UW-1:NW] : {UW{1'b0}};
        p_plus_1_load   <= p_load_w;
        axial_increment <= pq_load_w;
    end

    wire unused = &{1'b0, unused_carries};
endmodule
`default_nettype wire
