`default_nettype none
// Production arc interpolator: any start point to any end point on a circle about
// an integer centre, clockwise or counter-clockwise, across quadrant and octant
// boundaries (a full circle included), one step per tick, diagonal steps allowed.
// Built on the lecture's accelerated circular algorithm (seed 004, SPEC §5: a
// leading axis per octant, F = x^2 + y^2 - R^2 = 0 at the start point) with the
// midpoint choice of SU 1665343 (SPEC §4) generalised to all eight octants:
//   E = u^2 + v^2 - R^2 at the current point (u, v) = (x - cx, y - cy);
//   leading (major) step a and minor step b from the tangent's octant;
//   midpoint M = P + a + b/2:  F(M) < 0  <=>  T = E + 2 P.a + P.b + 1 < 0;
//   F(M) < 0 (M inside): take the outer of the axial (P + a) and diagonal
//   (P + a + b) candidates, else the inner one;
//   axial: E += 2 P.a + 1;  diagonal: E += 2 P.a + 2 P.b + 2.
// End: cross = P x End and dot = P . End are kept by adders; when the next point
// would reach or pass the ray from the centre through the end point (the sign of
// cross flips with dot > 0), the last step goes to the end point itself.
// R^2 = |start - centre|^2 (an integer; R itself need not be one).
//
// Timing: `start` in an idle cycle captures the command; two set-up cycles form
// the squares and products and check the command; then one step per `tick`
// (the step strobes and dir levels are registered together); `done` one cycle
// after the last step.  Bad command (error strobe instead of done, no steps):
// start = centre (R = 0); end point more than half a step off the circle
// (|sqrt(b) - sqrt(R^2)| > 1/2, circle_band); a start or end coordinate relative
// to the centre outside -2^(WIDTH-3) < u < 2^(WIDTH-3) (radius limit of the
// internal widths).  End = start: a full circle when `full`, else `done` with
// no step.  `start` while busy is ignored; `rst` returns to idle at once.
module circ_arc #(
    parameter integer WIDTH = 32    // width of the signed absolute coordinates (>= 6)
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             start,
    input  wire             tick,
    input  wire [WIDTH-1:0] cx,     // centre (signed)
    input  wire [WIDTH-1:0] cy,
    input  wire [WIDTH-1:0] x0,     // start point
    input  wire [WIDTH-1:0] y0,
    input  wire [WIDTH-1:0] x1,     // end point
    input  wire [WIDTH-1:0] y1,
    input  wire             ccw,    // 1 = counter-clockwise
    input  wire             full,   // with end == start: a full circle
    output reg              step_x,
    output reg              step_y,
    output reg              dir_x,  // 1 = negative direction
    output reg              dir_y,
    output wire             busy,
    output reg              done,
    output reg              error   // one-cycle strobe instead of `done` for a bad command
);
    initial begin
        if (WIDTH < 6) $error("%m: WIDTH must be at least 6");
    end

    localparam integer UW = WIDTH + 1;      // relative coordinates (exact differences)
    localparam integer EW = 2 * WIDTH + 3;  // E, cross, dot: sums of two UW x UW products
    localparam integer AW = 2 * WIDTH;      // squared radii: < 2^(2*WIDTH-5) once in range
    localparam [2:0] IDLE = 3'd0, SQUARE = 3'd1, CHECK = 3'd2, RUN = 3'd3, LAST = 3'd4;

    reg  [2:0]           state_q;
    reg  signed [UW-1:0] u_q, v_q;           // current point relative to the centre
    reg  signed [UW-1:0] u1_q, v1_q;         // end point relative to the centre
    reg                  ccw_q, full_q;
    reg  signed [EW-1:0] e_q;                // E = u^2 + v^2 - R^2
    reg  signed [EW-1:0] cross_q, dot_q;     // P x End, P . End
    reg  [AW-1:0]        a_q, b_q;           // R^2, |End|^2

    wire load = start & (state_q == IDLE);
    assign busy = state_q != IDLE;

    // ---- set-up products (SQUARE cycle) ----
    wire signed [EW-1:0] uu = u_q * u_q, vv = v_q * v_q, uu1 = u1_q * u1_q, vv1 = v1_q * v1_q;
    wire signed [EW-1:0] uv1 = u_q * v1_q, vu1 = v_q * u1_q, u_u1 = u_q * u1_q, v_v1 = v_q * v1_q;
    wire signed [EW-1:0] a_full = uu + vv, b_full = uu1 + vv1;

    // ---- command check (CHECK cycle) ----
    localparam integer LIMIT_BITS = WIDTH - 3;
    function automatic in_range(input [UW-1:0] value);      // -2^(W-3) < value < 2^(W-3)
        in_range = value[UW-1] ? value[UW-1:LIMIT_BITS] == {(UW-LIMIT_BITS){1'b1}} && value[LIMIT_BITS-1:0] != {LIMIT_BITS{1'b0}}
                               : value[UW-1:LIMIT_BITS] == {(UW-LIMIT_BITS){1'b0}};
    endfunction
    wire on_band;
    circle_band #(.AW(AW)) u_band (.a(a_q), .b(b_q), .on_band(on_band));
    wire fits = in_range(u_q) && in_range(v_q) && in_range(u1_q) && in_range(v1_q);
    wire bad = !fits || a_q == {AW{1'b0}} || !on_band;
    wire at_start = u_q == u1_q && v_q == v1_q;

    // ---- octant, candidates, midpoint (RUN cycle) ----
    wire u_neg = u_q[UW-1], v_neg = v_q[UW-1];
    wire u_zero = u_q == {UW{1'b0}}, v_zero = v_q == {UW{1'b0}};
    wire [UW-1:0] abs_u = u_neg ? -u_q : u_q;
    wire [UW-1:0] abs_v = v_neg ? -v_q : v_q;
    wire u_pos = !u_neg && !u_zero, v_pos = !v_neg && !v_zero;
    // Leading axis: the tangent's larger component; on a diagonal, the one of the next octant.
    wire x_major = abs_v > abs_u || (abs_v == abs_u && ((u_neg == v_neg) == ccw_q));
    // Tangent (-v, u) for CCW, (v, -u) for CW; a zero minor component steps inwards.
    wire major_neg = x_major ? (ccw_q ? v_pos : v_neg) : (ccw_q ? u_neg : u_pos);
    wire minor_neg = x_major ? (u_zero ? v_pos : (ccw_q ? u_neg : u_pos))
                             : (v_zero ? u_pos : (ccw_q ? v_pos : v_neg));
    wire signed [UW-1:0] p_major = x_major ? u_q : v_q;
    wire signed [UW-1:0] p_minor = x_major ? v_q : u_q;
    wire signed [EW-1:0] major_w = {{(EW-UW){p_major[UW-1]}}, p_major};
    wire signed [EW-1:0] minor_w = {{(EW-UW){p_minor[UW-1]}}, p_minor};
    wire signed [EW-1:0] pa = major_neg ? -major_w : major_w;       // P . a
    wire signed [EW-1:0] pb = minor_neg ? -minor_w : minor_w;       // P . b
    wire signed [EW-1:0] axial_e = e_q + (pa <<< 1) + 1;            // E at P + a
    wire signed [EW-1:0] test = axial_e + pb;                       // T: F(M) < 0 <=> T < 0
    wire take_diagonal = test[EW-1] == !pb[EW-1];                   // outer when M is inside
    wire signed [EW-1:0] diagonal_e = axial_e + (pb <<< 1) + 1;

    // The step (sx, sy) in {-1, 0, 1}: as two bits each (move, negative).
    wire mx = x_major | take_diagonal, my = !x_major | take_diagonal;
    wire nx = x_major ? major_neg : minor_neg;
    wire ny = x_major ? minor_neg : major_neg;
    wire signed [EW-1:0] u1_w = {{(EW-UW){u1_q[UW-1]}}, u1_q};
    wire signed [EW-1:0] v1_w = {{(EW-UW){v1_q[UW-1]}}, v1_q};
    wire signed [EW-1:0] du1 = nx ? -u1_w : u1_w, dv1 = ny ? -v1_w : v1_w;  // sx*u1, sy*v1
    wire signed [EW-1:0] su1 = ny ? -u1_w : u1_w, sv1 = nx ? -v1_w : v1_w;  // sy*u1, sx*v1
    wire signed [EW-1:0] zero = {EW{1'b0}};
    wire signed [EW-1:0] cross_next = cross_q + (mx ? sv1 : zero) - (my ? su1 : zero);
    wire signed [EW-1:0] dot_next = dot_q + (mx ? du1 : zero) + (my ? dv1 : zero);
    // Ray through the end point reached: sign of cross flips (CCW: + to <= 0), dot > 0.
    wire end_ahead = ccw_q ? !cross_q[EW-1] && cross_q != zero : cross_q[EW-1];
    wire reached = ccw_q ? cross_next[EW-1] || cross_next == zero : !cross_next[EW-1];
    wire last = end_ahead && reached && !dot_next[EW-1] && dot_next != zero;
    // The last step goes to the end point, which is one step away (tb/circ_arc/test_arc_model.py
    // checks it for every start and end point with |u|, |v| <= 9, and large full circles).
    wire signed [UW-1:0] rest_u = u1_q - u_q, rest_v = v1_q - v_q;
    wire last_mx = rest_u != {UW{1'b0}}, last_nx = rest_u[UW-1];
    wire last_my = rest_v != {UW{1'b0}}, last_ny = rest_v[UW-1];
    wire go = state_q == RUN && tick;
    wire act_x = go && (last ? last_mx : mx), neg_x = last ? last_nx : nx;
    wire act_y = go && (last ? last_my : my), neg_y = last ? last_ny : ny;

    always @(posedge clk) begin
        if (rst) begin
            state_q <= IDLE;
            u_q     <= {UW{1'b0}};
            v_q     <= {UW{1'b0}};
            u1_q    <= {UW{1'b0}};
            v1_q    <= {UW{1'b0}};
            ccw_q   <= 1'b0;
            full_q  <= 1'b0;
            e_q     <= {EW{1'b0}};
            cross_q <= {EW{1'b0}};
            dot_q   <= {EW{1'b0}};
            a_q     <= {AW{1'b0}};
            b_q     <= {AW{1'b0}};
            dir_x   <= 1'b0;
            dir_y   <= 1'b0;
            step_x  <= 1'b0;
            step_y  <= 1'b0;
            done    <= 1'b0;
            error   <= 1'b0;
        end else begin
            case (state_q)
                IDLE: if (load) begin
                    u_q     <= {x0[WIDTH-1], x0} - {cx[WIDTH-1], cx};
                    v_q     <= {y0[WIDTH-1], y0} - {cy[WIDTH-1], cy};
                    u1_q    <= {x1[WIDTH-1], x1} - {cx[WIDTH-1], cx};
                    v1_q    <= {y1[WIDTH-1], y1} - {cy[WIDTH-1], cy};
                    ccw_q   <= ccw;
                    full_q  <= full;
                    state_q <= SQUARE;
                end
                SQUARE: begin
                    a_q     <= a_full[AW-1:0];
                    b_q     <= b_full[AW-1:0];
                    cross_q <= uv1 - vu1;
                    dot_q   <= u_u1 + v_v1;
                    e_q     <= {EW{1'b0}};
                    state_q <= CHECK;
                end
                CHECK: state_q <= bad ? IDLE : (at_start && !full_q) ? LAST : RUN;
                RUN: if (go) begin
                    u_q     <= act_x ? (neg_x ? u_q - 1'b1 : u_q + 1'b1) : u_q;
                    v_q     <= act_y ? (neg_y ? v_q - 1'b1 : v_q + 1'b1) : v_q;
                    e_q     <= take_diagonal ? diagonal_e : axial_e;
                    cross_q <= cross_next;
                    dot_q   <= dot_next;
                    if (last) state_q <= LAST;
                end
                LAST: state_q <= IDLE;
                default: state_q <= IDLE;
            endcase
            if (act_x) dir_x <= neg_x;
            if (act_y) dir_y <= neg_y;
            step_x <= act_x;
            step_y <= act_y;
            done   <= state_q == LAST;
            error  <= state_q == CHECK && bad;
        end
    end

    // Only the low AW bits of the squares are kept (in range they are < 2^(2*WIDTH-5)).
    wire unused = &{1'b0, a_full[EW-1:AW], b_full[EW-1:AW]};
endmodule
`default_nettype wire
