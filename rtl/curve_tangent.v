// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Interpolator of arbitrary planar curves by the tangent method:
// Bulatnikov & Bulatnikova, "Digital interpolators of curve trajectories" (2011),
// the integer algorithm, points 1-9.
//   point 1 (E0) ............... e0 at `load`
//   point 2 (step choice) ...... move_x / move_y from the sign of E and the major axis
//   point 3 (new node) ......... x_q, y_q
//   point 4 (new ΔX, ΔY) ....... gradient_unit u_dx, u_dy (adders only)
//   points 5 + 6 merged (7) .... e_next, literal mode
//   point 8 (major axis change)  folded into e_next
//   point 9 (end of curve) ..... at_end
// The projections are affine: ΔX = p0 + dp_dx·(x-x0) + dp_dy·(y-y0), ΔY the
// same with q0, dq_dx, dq_dy, which covers the paper's exponent, logarithm,
// hyperbola and square root and every line, circle, ellipse and parabola.
//
// Merged formula (L, S = |major|, |minor| projection before the step, L', S'
// after it, both in the orientation before the step; d = 1 when E < 0):
//   literal:  E' = E + L' - 4S' - L + 2S + 2L'·d;   major axis changes: E' += 3S' - 3L'
//   improved: E' = E + L' - 3S' - L +  S + 2L'·d;   major axis changes: E' := -E' - L' - S'
// (improved: trapezoid slope, and the deviation changes sign with the axis; docs/algorithms.md).
//
// Ports beyond the standard ones (all sampled with `start` while idle):
//   x0, y0        start node (signed WIDTH)
//   p0, q0        ΔX = φ(x0, y0), ΔY = ψ(x0, y0) at the start node (signed PW)
//   dp_dx, dp_dy  change of ΔX per +1 step on x, on y (signed PW)
//   dq_dx, dq_dy  change of ΔY per +1 step on x, on y (signed PW)
//   reverse       1: travel against the tangent (every step negated)
//   count         number of steps (end_sel = 0), or step budget (end_sel = 1, 2)
//   end_sel       0: stop after `count` steps; 1: stop when x = end_coord;
//                 2: stop when y = end_coord (or after `count` steps); 3: illegal
//   end_coord     end coordinate for end_sel 1, 2 (signed WIDTH)
//   improved      0: the paper's algorithm; 1: improved mode
//   e_load, e_init  1: E starts at e_init (signed PW+4) instead of E0 (re-anchoring)
// Timing: `start` in an idle cycle loads everything; from the next cycle on,
// each cycle with `tick` high makes one step, shown on the registered
// step_x/step_y (dir_x/dir_y valid with them and held after) one cycle later.
// `done` is a one-cycle strobe when the move ends (no step in that cycle).
// Defined stops: end_sel = 3, both projections zero (no tangent), a step that
// would take x, y, ΔX, ΔY or E out of its width: `done` and `error` together,
// the offending step is not made.  `start` while busy is ignored.
module curve_tangent #(
    parameter integer WIDTH = 16,   // signed width of the coordinates x, y (>= 3)
    parameter integer PW = 24,      // signed width of the projections ΔX, ΔY and their coefficients (>= 3)
    parameter integer CW = 24       // width of the step counter (>= 1)
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             start,
    input  wire             tick,
    input  wire [WIDTH-1:0] x0,
    input  wire [WIDTH-1:0] y0,
    input  wire [PW-1:0]    p0,
    input  wire [PW-1:0]    q0,
    input  wire [PW-1:0]    dp_dx,
    input  wire [PW-1:0]    dp_dy,
    input  wire [PW-1:0]    dq_dx,
    input  wire [PW-1:0]    dq_dy,
    input  wire             reverse,
    input  wire [CW-1:0]    count,
    input  wire [1:0]       end_sel,
    input  wire [WIDTH-1:0] end_coord,
    input  wire             improved,
    input  wire             e_load,
    input  wire [PW+3:0]    e_init,
    output reg              step_x,
    output reg              step_y,
    output reg              dir_x,      // 1 = negative direction
    output reg              dir_y,
    output wire             busy,
    output reg              done,
    output reg              error       // with `done`: the move stopped on bad input
);
    initial begin
        if (WIDTH < 3) $error("%m: WIDTH must be at least 3");
        if (PW < 3) $error("%m: PW must be at least 3");
        if (CW < 1) $error("%m: CW must be at least 1");
    end

    localparam integer EW = PW + 4;     // E: |E| <= a few |projection|
    localparam integer TW = PW + 7;     // room for E + 5 projection terms

    reg              run_q;
    reg [WIDTH-1:0]  x_q, y_q, end_coord_q;
    reg [EW-1:0]     e_q;
    reg [CW-1:0]     cnt_q;
    reg [1:0]        end_sel_q;
    reg              reverse_q, improved_q;

    wire load = start & ~run_q;
    assign busy = run_q;

    // ---- point 4: the projections, kept by two gradient units ----
    wire [PW-1:0] p, q, p_next, q_next;            // p, q: ΔX, ΔY (for benches and waves)
    wire [PW-1:0] abs_p, abs_q, abs_p2, abs_q2;     // |ΔX|, |ΔY| now and after the step
    wire          p_ovf, q_ovf;
    reg           move_x, move_y, neg_x, neg_y;
    wire          do_step;
    gradient_unit #(.WIDTH(PW)) u_dx (
        .clk(clk), .rst(rst), .load(load), .load_value(p0), .coef_a_in(dp_dx), .coef_b_in(dp_dy),
        .step_a(move_x), .neg_a(neg_x), .step_b(move_y), .neg_b(neg_y), .advance(do_step),
        .value(p), .next_value(p_next), .overflow(p_ovf), .magnitude(abs_p), .next_magnitude(abs_p2)
    );
    gradient_unit #(.WIDTH(PW)) u_dy (
        .clk(clk), .rst(rst), .load(load), .load_value(q0), .coef_a_in(dq_dx), .coef_b_in(dq_dy),
        .step_a(move_x), .neg_a(neg_x), .step_b(move_y), .neg_b(neg_y), .advance(do_step),
        .value(q), .next_value(q_next), .overflow(q_ovf), .magnitude(abs_q), .next_magnitude(abs_q2)
    );

    // Magnitudes as PW-bit unsigned (|-2^(PW-1)| = 2^(PW-1) still fits).
    wire [PW-1:0] abs_p0 = p0[PW-1] ? -p0 : p0;
    wire [PW-1:0] abs_q0 = q0[PW-1] ? -q0 : q0;

    // ---- point 1: E0 = L - 2S ----
    wire          x_major0 = abs_p0 >= abs_q0;
    wire [EW-1:0] l0 = {4'b0, x_major0 ? abs_p0 : abs_q0};
    wire [EW-1:0] s0 = {4'b0, x_major0 ? abs_q0 : abs_p0};
    wire [EW-1:0] e0 = l0 - {s0[EW-2:0], 1'b0};
    wire [EW-1:0] e_start = e_load ? e_init : e0;

    // ---- point 2: the step ----
    // For speed the step choice is kept in registers, set with ΔX, ΔY and E
    // (at `load` and with every step) from their new values:
    //   x_major = |ΔX| >= |ΔY|,  p_nz = ΔX != 0,  q_nz = ΔY != 0,
    //   move_x = p_nz & (x_major | E < 0),  move_y = q_nz & (~x_major | E < 0),
    //   neg_x = (ΔX < 0) ^ reverse,  neg_y = (ΔY < 0) ^ reverse.
    reg  x_major, p_nz, q_nz;
    wire e_neg   = e_q[EW-1];

    // ---- points 5-8 merged ----
    wire [TW-1:0] l  = {7'b0, x_major ? abs_p  : abs_q};
    wire [TW-1:0] s  = {7'b0, x_major ? abs_q  : abs_p};
    wire [TW-1:0] l2 = {7'b0, x_major ? abs_p2 : abs_q2};
    wire [TW-1:0] s2 = {7'b0, x_major ? abs_q2 : abs_p2};
    wire          x_major2 = abs_p2 >= abs_q2;
    wire          axis_change = x_major2 ^ x_major;
    wire [TW-1:0] e_ext = {{(TW-EW){e_q[EW-1]}}, e_q};
    // literal:  E' = E + L' - 4S' - L + 2S + 2L'd,  axis change: + 3S' - 3L'
    // improved: E' = E + L' - 3S' - L +  S + 2L'd,  axis change: -E' - L' - S'
    // For speed the register-only part K = E - L + 2S (literal) or E - L + S
    // (improved) is formed alongside the new projections, and each case is
    // K plus small multiples of L', S' (d = E < 0 and the mode are registers):
    //   no change: K + (1 + 2d) L' - (4 or 3) S'
    //   change:    literal  K - 2(1 - d) L' - S';  improved -K - 2(1 + d) L' + 2S'
    wire [TW-1:0] k_reg = e_ext - l + (improved_q ? s : {s[TW-2:0], 1'b0});
    wire [TW-1:0] l2x2  = {l2[TW-2:0], 1'b0};
    wire [TW-1:0] s2x2  = {s2[TW-2:0], 1'b0};
    wire [TW-1:0] s2x4  = {s2[TW-3:0], 2'b0};
    wire [TW-1:0] l2_term = e_neg ? l2 + l2x2 : l2;                // (1 + 2d) L'
    wire [TW-1:0] s2_term = ~(improved_q ? s2x4 - s2 : s2x4);      // ~(3S' or 4S') = -(..) - 1
    // Each case: three operands to two by one carry-save row, then one adder.
    wire [TW-1:0] kp_s = k_reg ^ l2_term ^ s2_term;
    wire [TW-1:0] kp_c = {(k_reg[TW-2:0] & l2_term[TW-2:0]) | (k_reg[TW-2:0] & s2_term[TW-2:0])
                          | (l2_term[TW-2:0] & s2_term[TW-2:0]), 1'b0};
    wire [TW-1:0] e_keep = kp_s + kp_c + {{(TW-1){1'b0}}, 1'b1};
    wire [TW-1:0] kn_reg  = ~e_ext + l + ~s + {{(TW-2){1'b0}}, 2'b10};   // -(E - L + S)
    wire [TW-1:0] k_sw    = improved_q ? kn_reg : k_reg;
    // change: literal K + ~X2 + ~S' + 2, improved -K + ~X2 + 2S' + 1, X2 = 2(1 -+ d) L'
    wire [TW-1:0] sw_x2 = ~(improved_q ? (e_neg ? {l2[TW-3:0], 2'b0} : l2x2) : (e_neg ? {TW{1'b0}} : l2x2));
    wire [TW-1:0] sw_x3 = improved_q ? s2x2 : ~s2;
    wire [TW-1:0] sw_s = k_sw ^ sw_x2 ^ sw_x3;
    wire [TW-1:0] sw_c = {(k_sw[TW-2:0] & sw_x2[TW-2:0]) | (k_sw[TW-2:0] & sw_x3[TW-2:0])
                          | (sw_x2[TW-2:0] & sw_x3[TW-2:0]), ~improved_q};
    wire [TW-1:0] e_switch = sw_s + sw_c + {{(TW-1){1'b0}}, 1'b1};
    wire [TW-1:0] e_next = axis_change ? e_switch : e_keep;
    wire          e_ovf_keep   = e_keep[TW-1:EW-1] != {(TW-EW+1){e_keep[EW-1]}};
    wire          e_ovf_switch = e_switch[TW-1:EW-1] != {(TW-EW+1){e_switch[EW-1]}};
    wire          e_ovf = axis_change ? e_ovf_switch : e_ovf_keep;

    // ---- point 3: the new node, with range check ----
    localparam [WIDTH-1:0] XMAX = {1'b0, {(WIDTH-1){1'b1}}};
    localparam [WIDTH-1:0] XMIN = {1'b1, {(WIDTH-1){1'b0}}};
    wire x_ovf = move_x & (neg_x ? x_q == XMIN : x_q == XMAX);
    wire y_ovf = move_y & (neg_y ? y_q == XMIN : y_q == XMAX);
    wire [WIDTH-1:0] x_next = move_x ? (neg_x ? x_q - 1'b1 : x_q + 1'b1) : x_q;
    wire [WIDTH-1:0] y_next = move_y ? (neg_y ? y_q - 1'b1 : y_q + 1'b1) : y_q;

    // ---- point 9 and the defined stops ----
    wire stall  = ~p_nz & ~q_nz;
    wire fault  = stall | x_ovf | y_ovf | p_ovf | q_ovf | e_ovf;
    wire bad_sel = end_sel_q == 2'd3;
    wire at_end = (cnt_q == {CW{1'b0}}) | (end_sel_q == 2'd1 && x_q == end_coord_q)
                | (end_sel_q == 2'd2 && y_q == end_coord_q);
    wire finish = run_q & (at_end | bad_sel);
    wire trying = run_q & ~finish & tick;
    assign do_step = trying & ~fault;
    wire fault_stop = trying & fault;

    always @(posedge clk) begin
        if (rst) begin
            run_q       <= 1'b0;
            x_major     <= 1'b1;                    // |0| >= |0|
            p_nz        <= 1'b0;
            q_nz        <= 1'b0;
            move_x      <= 1'b0;
            move_y      <= 1'b0;
            neg_x       <= 1'b0;
            neg_y       <= 1'b0;
            x_q         <= {WIDTH{1'b0}};
            y_q         <= {WIDTH{1'b0}};
            e_q         <= {EW{1'b0}};
            cnt_q       <= {CW{1'b0}};
            end_sel_q   <= 2'd0;
            end_coord_q <= {WIDTH{1'b0}};
            reverse_q   <= 1'b0;
            improved_q  <= 1'b0;
            step_x      <= 1'b0;
            step_y      <= 1'b0;
            dir_x       <= 1'b0;
            dir_y       <= 1'b0;
            done        <= 1'b0;
            error       <= 1'b0;
        end else begin
            if (load) begin
                run_q       <= 1'b1;
                x_major     <= x_major0;
                p_nz        <= p0 != {PW{1'b0}};
                q_nz        <= q0 != {PW{1'b0}};
                move_x      <= (p0 != {PW{1'b0}}) & (x_major0 | e_start[EW-1]);
                move_y      <= (q0 != {PW{1'b0}}) & (~x_major0 | e_start[EW-1]);
                neg_x       <= p0[PW-1] ^ reverse;
                neg_y       <= q0[PW-1] ^ reverse;
                x_q         <= x0;
                y_q         <= y0;
                e_q         <= e_start;
                cnt_q       <= count;
                end_sel_q   <= end_sel;
                end_coord_q <= end_coord;
                reverse_q   <= reverse;
                improved_q  <= improved;
            end else if (finish | fault_stop) begin
                run_q <= 1'b0;
            end else if (do_step) begin
                x_q   <= x_next;
                y_q   <= y_next;
                e_q   <= e_next[EW-1:0];
                cnt_q <= cnt_q - 1'b1;
                x_major <= x_major2;
                p_nz  <= p_next != {PW{1'b0}};
                q_nz  <= q_next != {PW{1'b0}};
                move_x <= (p_next != {PW{1'b0}}) & (x_major2 | e_next[EW-1]);
                move_y <= (q_next != {PW{1'b0}}) & (~x_major2 | e_next[EW-1]);
                neg_x <= p_next[PW-1] ^ reverse_q;
                neg_y <= q_next[PW-1] ^ reverse_q;
            end
            step_x <= do_step & move_x;
            step_y <= do_step & move_y;
            if (do_step & move_x) dir_x <= neg_x;
            if (do_step & move_y) dir_y <= neg_y;
            done  <= finish | fault_stop;
            error <= (finish & bad_sel) | fault_stop;
        end
    end

    wire unused = &{1'b0, p, q, l0[EW-1:PW], s0[EW-1], l[TW-1:PW], s[TW-1:PW], l2[TW-1], s2[TW-1:TW-2],
                   e_next[TW-1:EW]};
endmodule
`default_nettype wire
