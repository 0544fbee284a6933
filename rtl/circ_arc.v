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
// End: cross = P x End and dot = P . End follow the steps; when the next point
// would reach or pass the ray from the centre through the end point (the sign of
// cross flips with dot > 0), the last step goes to the end point itself.
// R^2 = |start - centre|^2 (an integer; R itself need not be one).
//
// Widths: |E| <= R + 1/4 on the path, so E has WIDTH + 2 bits (held as E + 1).  Only
// the signs of cross and dot matter, kept as C = turn * cross - 1 and D = dot - 1 (turn = +1
// CCW, -1 CW), each a high part H and a low part L of K = WIDTH - 2 bits: a step
// changes them by less than 2^K, so the step's sum L + delta (K + 2 bits) and
// flags of H (H = 0, -1, 1 ...) give the signs; H moves by the carry, -1, 0 or +1.
// The octant comes from the signs and registered flags (= 0, +-1, +-2) of u, v, u + v
// and v - u (|v| > |u| <=> (v + u)(v - u) > 0); next flags from compares with -4 .. 4.
// Registered with the octant: the operands it selects for T (P.a, P.b) and for the
// end test, and H's flags; so T is a carry-save step and one chain from registers.
// The last step sets fin_q, which ends the run in the next cycle (acts as LAST).
//
// Set-up (no combinational multiplier: four seq_mult instances, two rounds):
// round 1 u^2, v^2, u1^2, v1^2 -> a = R^2, b = |End|^2, d = b - a; round 2 the
// three products of the complex product (u + iv)(u1 - iv1) (dot, -cross) and
// m^2 with m = |d|; on the circle's band (|sqrt(b) - sqrt(a)| <= 1/2) <=>
// d = 0 or m^2 <= min(a, b) + (m - 1) div 2.  Wide sums (2*WIDTH - 2 bits) take
// two cycles, two half-width chunks with a registered carry.
//
// Timing: `start` in an idle cycle captures the command (cycle 0); the set-up
// (PREP, two multiplier rounds of WIDTH + 4 cycles, three two-cycle sums) checks
// the command in cycle 2*WIDTH + 16; from cycle 2*WIDTH + 17 one step per `tick`
// (the step strobes and dir levels are registered together); `done` one cycle
// after the last step.  Bad command (error strobe instead of done, no steps):
// start = centre (R = 0); end point more than half a step off the circle; a
// start or end coordinate relative to the centre outside
// -2^(WIDTH-3) < u < 2^(WIDTH-3) (radius limit of the internal widths).
// End = start: a full circle when `full`, else `done` with no step.  `start`
// while busy is ignored; `rst` returns to idle at once.
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
    localparam integer NW = WIDTH + 2;      // E and the midpoint test T
    localparam integer SW = 2 * WIDTH - 2;  // set-up sums, C and D (|value| < 2^(2*WIDTH-4))
    localparam integer SK = SW / 2;         // set-up chunk
    localparam integer K = WIDTH - 2;       // low part of C and D
    localparam integer HW = SW - K;         // high part of C and D
    localparam integer PW = 2 * UW;         // seq_mult product
    localparam [3:0] IDLE = 4'd0, PREP = 4'd1, MUL1 = 4'd2, ADD1 = 4'd3, ADD2 = 4'd4, MUL2 = 4'd5,
                     ADD3 = 4'd6, CHECK = 4'd7, RUN = 4'd8, LAST = 4'd9;

    reg  [3:0]           state_q;
    reg                  fin_q;              // RUN took its last step: acts as LAST
    reg                  sub_q;              // second cycle of a two-cycle sum
    reg  signed [UW-1:0] u_q, v_q;           // current point relative to the centre
    reg  signed [UW-1:0] s1_q, s3_q;         // u + v, v - u
    reg  signed [UW-1:0] u1_q, v1_q;         // end point relative to the centre
    reg  signed [UW-1:0] wp_q, wm_q;         // u1 + v1, v1 - u1
    reg                  ccw_q, full_q;
    reg  [4:0]           uw_q, vw_q, s1w_q, s3w_q;   // u, v, s1, s3 == 2, 1, 0, -1, -2
    reg                  xm_q, mjn_q, mnn_q;         // octant: x major, major step < 0, minor < 0
    reg  [UW-1:0]        xs_q, ys_q;         // P.a - major_neg, P.b - minor_neg (= u or v, inverted if negative)
    reg  [4*K+11:0]      eop_q;              // end test operands of the octant (end_ops)
    reg                  hcz_q, hdz_q, hdm1_q, hdpos_q;   // high parts: H(C) = 0, H(D) = 0, -1, > 0
    reg  signed [NW-1:0] e1_q;               // E + 1, E = u^2 + v^2 - R^2
    reg  [SW-1:0]        c_q, d_q;           // C = turn * cross - 1, D = dot - 1
    reg  [SW-1:0]        a_q, b_q;           // R^2 (then min(R^2, |End|^2)), |End|^2
    reg  [SW-1:0]        dd_q, nd_q;         // d = b - a, -d
    reg  [SW-1:0]        t_q;                // band test: min(a, b) + (m - 1) div 2 - m^2
    reg  [4:0]           carry_q;            // chunk carries of the two-cycle sums
    reg  [UW-1:0]        m_q, h_q;           // m = |d|, (m - 1) div 2
    reg                  dzero_q, msmall_q;

    wire load = start & (state_q == IDLE);
    assign busy = state_q != IDLE;

    // ---------------------------------------------------------------- set-up products
    wire          round1 = state_q == PREP;
    wire          mstart = round1 || state_q == ADD2 && sub_q;
    wire [SW:0]   d_sum, nd_sum;
    wire [UW-1:0] m_abs = d_sum[SW-1] ? nd_sum[UW-1:0] : d_sum[UW-1:0];           // |d| (ADD2, 2nd cycle)
    wire [UW-1:0] ma0 = round1 ? u_q : u1_q,  mb0 = round1 ? u_q : s1_q;     // u^2 | k1 = u1 (u + v)
    wire [UW-1:0] ma1 = round1 ? v_q : u_q,   mb1 = round1 ? v_q : wp_q;     // v^2 | q2 = u (u1 + v1)
    wire [UW-1:0] ma2 = round1 ? u1_q : v_q,  mb2 = round1 ? u1_q : wm_q;    // u1^2 | q3 = v (v1 - u1)
    wire [UW-1:0] ma3 = round1 ? v1_q : m_abs, mb3 = round1 ? v1_q : m_abs;  // v1^2 | m^2
    wire [PW-1:0] p0, p1, p2, p3;
    wire          mdone;
    wire [3:0]    mbusy;
    wire [2:0]    mdone_other;
    seq_mult #(.WIDTH(UW)) u_mul0 (.clk(clk), .rst(rst), .start(mstart), .a(ma0), .b(mb0),
                                 .busy(mbusy[0]), .done(mdone), .product(p0));
    seq_mult #(.WIDTH(UW)) u_mul1 (.clk(clk), .rst(rst), .start(mstart), .a(ma1), .b(mb1),
                                 .busy(mbusy[1]), .done(mdone_other[0]), .product(p1));
    seq_mult #(.WIDTH(UW)) u_mul2 (.clk(clk), .rst(rst), .start(mstart), .a(ma2), .b(mb2),
                                 .busy(mbusy[2]), .done(mdone_other[1]), .product(p2));
    seq_mult #(.WIDTH(UW)) u_mul3 (.clk(clk), .rst(rst), .start(mstart), .a(ma3), .b(mb3),
                                 .busy(mbusy[3]), .done(mdone_other[2]), .product(p3));
    wire [SW-1:0] k1 = p0[SW-1:0], q2 = p1[SW-1:0], q3 = p2[SW-1:0], msq = p3[SW-1:0];

    // Two-cycle sum x + y + cin: low chunk now, high chunk with the registered carry.
    function automatic [SW:0] sum2;          // {carry out of the low chunk, sum}
        input [SW-1:0] x, y;
        input cin, hcin;
        reg [SK:0]   lo;
        reg [SK-1:0] hi;
        begin
            lo = {1'b0, x[SK-1:0]} + {1'b0, y[SK-1:0]} + {{SK{1'b0}}, cin};
            hi = x[SW-1:SK] + y[SW-1:SK] + {{(SK-1){1'b0}}, hcin};
            sum2 = {lo[SK], hi, lo[SK-1:0]};
        end
    endfunction
    // ADD1: a = u^2 + v^2, b = u1^2 + v1^2.   ADD2: d = b - a, -d.
    wire [SW:0] a_sum = sum2(p0[SW-1:0], p1[SW-1:0], 1'b0, carry_q[0]);
    wire [SW:0] b_sum = sum2(p2[SW-1:0], p3[SW-1:0], 1'b0, carry_q[1]);
    assign d_sum = sum2(b_q, ~a_q, 1'b1, carry_q[0]);
    assign nd_sum = sum2(a_q, ~b_q, 1'b1, carry_q[1]);
    // ADD3: C = q2 - k1 - 1 (CCW) or k1 - q2 - 1 (CW); D = k1 + q3 - 1 and the
    // band test s + h - m^2, each with a carry-save step in front.
    wire [SW:0] c_sum = ccw_q ? sum2(q2, ~k1, 1'b0, carry_q[0]) : sum2(k1, ~q2, 1'b0, carry_q[0]);
    wire [SW-1:0] dcs_s = ~(k1 ^ q3), dcs_c = {k1[SW-2:0] | q3[SW-2:0], 1'b0};  // k1 + q3 + (-1)
    wire [SW:0] dsum = sum2(dcs_s, dcs_c, 1'b0, carry_q[1]);
    wire [SW-1:0] h_w = {{(SW-UW){1'b0}}, h_q};
    wire [SW-1:0] tcs_s = a_q ^ h_w ^ ~msq;
    wire [SW-1:0] tcs_c = {(a_q[SW-2:0] & h_w[SW-2:0]) | (a_q[SW-2:0] & ~msq[SW-2:0]) |
                           (h_w[SW-2:0] & ~msq[SW-2:0]), 1'b1};               // + 1: -m^2 = ~m^2 + 1
    wire [SW:0] t_sum = sum2(tcs_s, tcs_c, 1'b0, carry_q[2]);

    // ---------------------------------------------------------------- command check (CHECK)
    localparam integer LIMIT_BITS = WIDTH - 3;
    function automatic in_range(input [UW-1:0] value);      // -2^(W-3) < value < 2^(W-3)
        in_range = value[UW-1] ? value[UW-1:LIMIT_BITS] == {(UW-LIMIT_BITS){1'b1}} && value[LIMIT_BITS-1:0] != {LIMIT_BITS{1'b0}}
                               : value[UW-1:LIMIT_BITS] == {(UW-LIMIT_BITS){1'b0}};
    endfunction
    wire fits = in_range(u_q) && in_range(v_q) && in_range(u1_q) && in_range(v1_q);
    wire on_band = dzero_q || (msmall_q && !t_q[SW-1]);
    wire bad = !fits || (u_q == {UW{1'b0}} && v_q == {UW{1'b0}}) || !on_band;
    wire at_start = u_q == u1_q && v_q == v1_q;

    // ---------------------------------------------------------------- octant
    // Leading axis: the tangent's larger component; on a diagonal, the one of the next octant.
    // |v| > |u| <=> (v + u)(v - u) > 0;  |v| = |u| <=> v + u = 0 or v - u = 0.
    function automatic [2:0] octant;   // {x_major, major_neg, minor_neg} from a point's flags
        input un, uz, vn, vz, s1n, s1z, s3n, s3z, cc;
        reg xm, up, vp;
        begin
            xm = (!s1z && !s3z && s1n == s3n) || ((s1z || s3z) && ((un == vn) == cc));
            up = !un && !uz;
            vp = !vn && !vz;
            // Tangent (-v, u) for CCW, (v, -u) for CW; a zero minor component steps inwards.
            octant = {xm, xm ? (cc ? vp : vn) : (cc ? un : up),
                          xm ? (uz ? vp : (cc ? un : up)) : (vz ? up : (cc ? vp : vn))};
        end
    endfunction
    // {negative, zero} of x + s from x's flags: s = +-1 (neg_step: -1) ...
    function automatic [1:0] after1(input neg_step, xn, xz, xp1, xm1);
        after1 = neg_step ? {xn | xz, xp1} : {xn & !xm1, xm1};
    endfunction
    // ... and s in {0, +-2} (move: s != 0).
    function automatic [1:0] after2(input move, neg_step, xn, xz, xp1, xm1, xp2, xm2);
        after2 = !move ? {xn, xz} : neg_step ? {xn | xz | xp1, xp2} : {xn & !xm1 & !xm2, xm2};
    endfunction
    function automatic [1:0] after01(input move, neg_step, xn, xz, xp1, xm1);   // s in {0, +-1}
        after01 = move ? after1(neg_step, xn, xz, xp1, xm1) : {xn, xz};
    endfunction

    // ---------------------------------------------------------------- candidates (RUN)
    // The registered octant of the current point gives the axial step A = a and the
    // diagonal step D = a + b; every next value is formed for both (and for the last
    // step), from registers, and the midpoint decision only selects.
    wire xm = xm_q;
    wire nxa = mjn_q, nya = mjn_q;                       // A: x (xm) or y, negative?
    wire nxd = xm ? mjn_q : mnn_q, nyd = xm ? mnn_q : mjn_q;
    wire same = mjn_q == mnn_q;                          // D: sx == sy
    wire u_neg = u_q[UW-1], v_neg = v_q[UW-1], s1_neg = s1_q[UW-1], s3_neg = s3_q[UW-1];

    // Midpoint: P.a = xop + major_neg, P.b = yop + minor_neg (two's complement); the
    // register holds E + 1, so T = (E + 1) + 2 P.a + P.b is one carry-save step and one
    // carry chain: (E + 1) + {xop, major_neg} + yop + major_neg + minor_neg.
    // xs_q and ys_q hold the selected and inverted coordinates, formed with the octant.
    function automatic [2*UW-1:0] point_ops(input xm_f, mjn_f, mnn_f, input [UW-1:0] u_f, v_f);
        point_ops = {(xm_f ? u_f : v_f) ^ {UW{mjn_f}}, (xm_f ? v_f : u_f) ^ {UW{mnn_f}}};
    endfunction
    wire [NW-1:0] xop = {{(NW-UW){xs_q[UW-1]}}, xs_q};
    wire [NW-1:0] yop = {{(NW-UW){ys_q[UW-1]}}, ys_q};
    wire [NW-1:0] xop2 = {xop[NW-2:0], mjn_q}, yop2 = {yop[NW-2:0], mnn_q};   // 2 P.a - major_neg, ...
    wire [NW-1:0] axial_e = e1_q + xop2 + {{(NW-2){1'b0}}, mjn_q, !mjn_q};        // + 2 P.a + 1
    wire [NW-1:0] diagonal_e = e1_q + xop2 + yop2 +
                               {{(NW-3){1'b0}}, mjn_q & mnn_q, !(mjn_q & mnn_q), mjn_q ^ mnn_q};  // + 2 P.a + 2 P.b + 2
    wire [NW-1:0] t_s = e1_q ^ xop2 ^ yop;
    wire [NW-1:0] t_c = {(e1_q[NW-2:0] & xop2[NW-2:0]) | (e1_q[NW-2:0] & yop[NW-2:0]) |
                         (xop2[NW-2:0] & yop[NW-2:0]), mjn_q};
    wire [NW-1:0] test = t_s + t_c + {{(NW-1){1'b0}}, mnn_q};                      // T
    // T < 0 (M inside): the outer candidate, which is D when P.b >= 0.
    wire pb_nonneg = (xm ? vz_q : uz_q) || !ys_q[UW-1];
    wire take_diagonal = test[NW-1] == pb_nonneg;

    // Position and the octant helpers s1 = u + v, s3 = v - u for A and D.
    wire [UW-1:0] one = {{(UW-1){1'b0}}, 1'b1}, two = {{(UW-2){1'b0}}, 2'b10};
    wire [UW-1:0] u_inc = u_q + one, u_dec = u_q - one, v_inc = v_q + one, v_dec = v_q - one;
    wire [UW-1:0] u_a = xm ? (nxa ? u_dec : u_inc) : u_q, u_d = nxd ? u_dec : u_inc;
    wire [UW-1:0] v_a = xm ? v_q : (nya ? v_dec : v_inc), v_d = nyd ? v_dec : v_inc;
    wire s3a_dec = xm ^ mjn_q;                           // A: s1 += sx + sy = -+1, s3 += sy - sx
    wire [UW-1:0] s1_a = s1_q + (mjn_q ? {UW{1'b1}} : one);
    wire [UW-1:0] s3_a = s3_q + (s3a_dec ? {UW{1'b1}} : one);
    wire [UW-1:0] s1_d = s1_q + (same ? (nxd ? -two : two) : {UW{1'b0}});   // D: 0 or +-2
    wire [UW-1:0] s3_d = s3_q + (same ? {UW{1'b0}} : (nyd ? -two : two));
    // Flags: x == 0, +-1, +-2 (zero and sign of the next values), registered: the next flags
    // are compares of x with -4 .. 4, picked by the step (x' == c <=> x == c - s).
    function automatic [8:0] small_eq(input [UW-1:0] x);       // bit k + 4: x == k, k = -4 .. 4
        reg hz, ho;
        integer k;
        begin
            hz = x[UW-1:3] == {(UW-3){1'b0}};
            ho = x[UW-1:3] == {(UW-3){1'b1}};
            for (k = -4; k <= 4; k = k + 1)
                small_eq[k+4] = (k >= 0 ? hz : ho) && x[2:0] == k[2:0];
        end
    endfunction
    function automatic [4:0] window(input [2:0] step, input [8:0] e);   // flags of x + step
        case (step)                                                    // step: signed -2 .. 2
            3'b001:  window = e[5:1];
            3'b010:  window = e[4:0];
            3'b111:  window = e[7:3];
            3'b110:  window = e[8:4];
            default: window = e[6:2];
        endcase
    endfunction
    wire [8:0] ue = small_eq(u_q), ve = small_eq(v_q), s1e = small_eq(s1_q), s3e = small_eq(s3_q);
    wire uz_q = uw_q[2], vz_q = vw_q[2], s1z_q = s1w_q[2], s3z_q = s3w_q[2];
    wire u_p1 = uw_q[3], u_m1 = uw_q[1], v_p1 = vw_q[3], v_m1 = vw_q[1];
    wire s1_p1 = s1w_q[3], s1_m1 = s1w_q[1], s1_p2 = s1w_q[4], s1_m2 = s1w_q[0];
    wire s3_p1 = s3w_q[3], s3_m1 = s3w_q[1], s3_p2 = s3w_q[4], s3_m2 = s3w_q[0];
    wire [2:0] p1s = 3'b001, m1s = 3'b111, p2s = 3'b010, m2s = 3'b110, zs = 3'b000;
    wire [2:0] su_a = xm ? (nxa ? m1s : p1s) : zs, su_d = nxd ? m1s : p1s;
    wire [2:0] sv_a = xm ? zs : (nya ? m1s : p1s), sv_d = nyd ? m1s : p1s;
    wire [2:0] ss1_a = mjn_q ? m1s : p1s, ss1_d = same ? (nxd ? m2s : p2s) : zs;
    wire [2:0] ss3_a = s3a_dec ? m1s : p1s, ss3_d = same ? zs : (nyd ? m2s : p2s);
    wire [1:0] uf_a = after01(xm, nxa, u_neg, uz_q, u_p1, u_m1), uf_d = after1(nxd, u_neg, uz_q, u_p1, u_m1);
    wire [1:0] vf_a = after01(!xm, nya, v_neg, vz_q, v_p1, v_m1), vf_d = after1(nyd, v_neg, vz_q, v_p1, v_m1);
    wire [1:0] s1f_a = after1(mjn_q, s1_neg, s1z_q, s1_p1, s1_m1);
    wire [1:0] s3f_a = after1(s3a_dec, s3_neg, s3z_q, s3_p1, s3_m1);
    wire [1:0] s1f_d = after2(same, nxd, s1_neg, s1z_q, s1_p1, s1_m1, s1_p2, s1_m2);
    wire [1:0] s3f_d = after2(!same, nyd, s3_neg, s3z_q, s3_p1, s3_m1, s3_p2, s3_m2);
    wire [2:0] oct_a = octant(uf_a[1], uf_a[0], vf_a[1], vf_a[0], s1f_a[1], s1f_a[0], s3f_a[1], s3f_a[0], ccw_q);
    wire [2:0] oct_d = octant(uf_d[1], uf_d[0], vf_d[1], vf_d[0], s1f_d[1], s1f_d[0], s3f_d[1], s3f_d[0], ccw_q);
    wire [2:0] oct_0 = octant(u_neg, uz_q, v_neg, vz_q, s1_neg, s1z_q, s3_neg, s3z_q, ccw_q);  // set-up

    // ---------------------------------------------------------------- end test (RUN)
    // Step deltas of C and D for A and D: C += turn (sx v1 - sy u1), D += sx u1 + sy v1;
    // operand and sign per octant.
    // The operands are formed with the octant and held in eop_q: {x, neg} per sum, x inverted if neg.
    wire tneg = !ccw_q;
    function automatic [4*K+11:0] end_ops(input xm_f, mjn_f, mnn_f);
        reg [K+1:0] ca_op, da_op, cd_op, dd_op;
        reg         ca_neg, da_neg, cd_neg, dd_neg, nxd_f, same_f;
        begin
            nxd_f  = xm_f ? mjn_f : mnn_f;
            same_f = mjn_f == mnn_f;
            ca_op  = xm_f ? v1_q[K+1:0] : u1_q[K+1:0];
            da_op  = xm_f ? u1_q[K+1:0] : v1_q[K+1:0];
            ca_neg = xm_f ? mjn_f ^ tneg : !(mjn_f ^ tneg);
            da_neg = mjn_f;
            cd_op  = same_f ? wm_q[K+1:0] : wp_q[K+1:0];
            dd_op  = same_f ? wp_q[K+1:0] : wm_q[K+1:0];
            cd_neg = nxd_f ^ tneg;
            dd_neg = same_f ? nxd_f : !nxd_f;
            end_ops = {ca_op ^ {(K+2){ca_neg}}, ca_neg, cd_op ^ {(K+2){cd_neg}}, cd_neg,
                       da_op ^ {(K+2){da_neg}}, da_neg, dd_op ^ {(K+2){dd_neg}}, dd_neg};
        end
    endfunction
    wire [K+1:0]  ca_x = eop_q[4*K+11:3*K+10], cd_x = eop_q[3*K+8:2*K+7];
    wire [K+1:0]  da_x = eop_q[2*K+5:K+4],     dd_x = eop_q[K+2:1];
    wire          ca_neg = eop_q[3*K+9], cd_neg = eop_q[2*K+6], da_neg = eop_q[K+3], dd_neg = eop_q[0];
    // L + delta, K + 2 bits signed, in (-2^K, 2^(K+1)): bit K+1 = negative, bits K+1..K = carry.
    // Carry-select: the low LS bits, and the upper bits for both carries from them.
    localparam integer LS = K / 2;
    function automatic [K+1:0] low_step(input [K-1:0] low, input [K+1:0] x, input neg);
        reg [LS:0]     lo;
        reg [K+1-LS:0] hi0, hi1;
        begin
            lo  = {1'b0, low[LS-1:0]} + {1'b0, x[LS-1:0]} + {{LS{1'b0}}, neg};
            hi0 = {2'b00, low[K-1:LS]} + x[K+1:LS];
            hi1 = {2'b00, low[K-1:LS]} + x[K+1:LS] + {{(K+1-LS){1'b0}}, 1'b1};
            low_step = {lo[LS] ? hi1 : hi0, lo[LS-1:0]};
        end
    endfunction
    wire [K+1:0] lc_a = low_step(c_q[K-1:0], ca_x, ca_neg), lc_d = low_step(c_q[K-1:0], cd_x, cd_neg);
    wire [K+1:0] ld_a = low_step(d_q[K-1:0], da_x, da_neg), ld_d = low_step(d_q[K-1:0], dd_x, dd_neg);
    wire [HW-1:0] hc = c_q[SW-1:K], hd = d_q[SW-1:K];
    wire [HW-1:0] hone = {{(HW-1){1'b0}}, 1'b1};
    // H's flags are registered; the next ones are compares of H, picked by the carry.
    wire hc_z = hcz_q, hd_z = hdz_q, hd_m1 = hdm1_q, hd_pos = hdpos_q;
    wire hc_e0 = hc == {HW{1'b0}}, hc_e1 = hc == hone, hc_em1 = hc == {HW{1'b1}};
    wire hd_e0 = hd == {HW{1'b0}}, hd_e1 = hd == hone, hd_em1 = hd == {HW{1'b1}}, hd_em2 = hd == {{(HW-1){1'b1}}, 1'b0};
    wire hd_gt0 = !hd[HW-1] && !hd_e0;
    function automatic [3:0] high_flags(input [1:0] cc, cd);   // {H(C)' = 0, H(D)' = 0, -1, > 0}
        high_flags = {cc == 2'b01 ? hc_em1 : cc == 2'b11 ? hc_e1 : hc_e0,
                      cd == 2'b01 ? {hd_em1, hd_em2, !hd[HW-1]} :
                      cd == 2'b11 ? {hd_e1, hd_e0, hd_gt0 && !hd_e1} : {hd_e0, hd_em1, hd_gt0}};
    endfunction
    // D + delta >= 0 from H's flags and the low sum (carry -1, 0 or +1).
    function automatic dot_ok(input [K+1:0] low, input pos, zero, minus1);
        dot_ok = pos || (zero && !low[K+1]) || (minus1 && low[K+1:K] == 2'b01);
    endfunction
    // Ahead (C >= 0) and reached (C + delta < 0): only when H = 0 (|delta| < 2^K).
    wire last_a = hc_z && lc_a[K+1] && dot_ok(ld_a, hd_pos, hd_z, hd_m1);
    wire last_d = hc_z && lc_d[K+1] && dot_ok(ld_d, hd_pos, hd_z, hd_m1);
    wire last = take_diagonal ? last_d : last_a;
    // H + carry: formed for each carry, picked by the chosen low sum.
    wire [HW-1:0] hc_inc = hc + hone, hc_dec = hc - hone, hd_inc = hd + hone, hd_dec = hd - hone;
    function automatic [HW-1:0] high_next(input [1:0] carry, input [HW-1:0] h, inc, dec);
        high_next = carry == 2'b01 ? inc : carry == 2'b11 ? dec : h;
    endfunction
    wire [SW-1:0] c_a = {high_next(lc_a[K+1:K], hc, hc_inc, hc_dec), lc_a[K-1:0]};
    wire [SW-1:0] c_d = {high_next(lc_d[K+1:K], hc, hc_inc, hc_dec), lc_d[K-1:0]};
    wire [SW-1:0] d_a = {high_next(ld_a[K+1:K], hd, hd_inc, hd_dec), ld_a[K-1:0]};
    wire [SW-1:0] d_d = {high_next(ld_d[K+1:K], hd, hd_inc, hd_dec), ld_d[K-1:0]};

    // The last step goes to the end point, which is one step away (tb/circ_arc/test_arc_model.py
    // checks it for every start and end point with |u|, |v| <= 9, and large full circles): the
    // rest End - P is -1, 0 or 1 per axis, read from the low two bits.
    wire [1:0] rest_u = u1_q[1:0] - u_q[1:0], rest_v = v1_q[1:0] - v_q[1:0];
    wire last_mx = rest_u != 2'b00, last_nx = rest_u[1];
    wire last_my = rest_v != 2'b00, last_ny = rest_v[1];
    // Everything is formed for both candidates; the midpoint decision selects last.
    wire go = state_q == RUN && !fin_q && tick;
    wire act_x = go && (take_diagonal ? !last_d || last_mx : (last_a ? last_mx : xm));
    wire act_y = go && (take_diagonal ? !last_d || last_my : (last_a ? last_my : !xm));
    wire neg_x = take_diagonal ? (last_d ? last_nx : nxd) : (last_a ? last_nx : nxa);
    wire neg_y = take_diagonal ? (last_d ? last_ny : nyd) : (last_a ? last_ny : nya);
    wire [UW-1:0] u_x = take_diagonal ? (last_d ? u1_q : u_d) : (last_a ? u1_q : u_a);
    wire [UW-1:0] v_x = take_diagonal ? (last_d ? v1_q : v_d) : (last_a ? v1_q : v_a);

    always @(posedge clk) begin
        if (rst) begin
            state_q  <= IDLE;
            fin_q    <= 1'b0;
            sub_q    <= 1'b0;
            u_q      <= {UW{1'b0}};
            v_q      <= {UW{1'b0}};
            s1_q     <= {UW{1'b0}};
            s3_q     <= {UW{1'b0}};
            u1_q     <= {UW{1'b0}};
            v1_q     <= {UW{1'b0}};
            wp_q     <= {UW{1'b0}};
            wm_q     <= {UW{1'b0}};
            ccw_q    <= 1'b0;
            full_q   <= 1'b0;
            uw_q     <= 5'd0;
            vw_q     <= 5'd0;
            s1w_q    <= 5'd0;
            s3w_q    <= 5'd0;
            xm_q     <= 1'b0;
            mjn_q    <= 1'b0;
            mnn_q    <= 1'b0;
            xs_q     <= {UW{1'b0}};
            ys_q     <= {UW{1'b0}};
            eop_q    <= {(4*K+12){1'b0}};
            hcz_q    <= 1'b0;
            hdz_q    <= 1'b0;
            hdm1_q   <= 1'b0;
            hdpos_q  <= 1'b0;
            e1_q     <= {{(NW-1){1'b0}}, 1'b1};
            c_q      <= {SW{1'b0}};
            d_q      <= {SW{1'b0}};
            a_q      <= {SW{1'b0}};
            b_q      <= {SW{1'b0}};
            dd_q     <= {SW{1'b0}};
            nd_q     <= {SW{1'b0}};
            t_q      <= {SW{1'b0}};
            carry_q  <= 5'd0;
            m_q      <= {UW{1'b0}};
            h_q      <= {UW{1'b0}};
            dzero_q  <= 1'b0;
            msmall_q <= 1'b0;
            dir_x    <= 1'b0;
            dir_y    <= 1'b0;
            step_x   <= 1'b0;
            step_y   <= 1'b0;
            done     <= 1'b0;
            error    <= 1'b0;
        end else begin
            sub_q <= 1'b0;
            case (state_q)
                IDLE: if (load) begin
                    u_q     <= {x0[WIDTH-1], x0} - {cx[WIDTH-1], cx};
                    v_q     <= {y0[WIDTH-1], y0} - {cy[WIDTH-1], cy};
                    u1_q    <= {x1[WIDTH-1], x1} - {cx[WIDTH-1], cx};
                    v1_q    <= {y1[WIDTH-1], y1} - {cy[WIDTH-1], cy};
                    ccw_q   <= ccw;
                    full_q  <= full;
                    state_q <= PREP;
                end
                PREP: begin                     // round 1 starts; operand sums
                    s1_q    <= u_q + v_q;
                    s3_q    <= v_q - u_q;
                    wp_q    <= u1_q + v1_q;
                    wm_q    <= v1_q - u1_q;
                    state_q <= MUL1;
                end
                MUL1: if (mdone) state_q <= ADD1;
                ADD1: begin
                    a_q     <= a_sum[SW-1:0];
                    b_q     <= b_sum[SW-1:0];
                    carry_q <= {3'b000, b_sum[SW], a_sum[SW]};
                    sub_q   <= !sub_q;
                    if (sub_q) state_q <= ADD2;
                end
                ADD2: begin                     // round 2 starts in the second cycle
                    dd_q    <= d_sum[SW-1:0];
                    nd_q    <= nd_sum[SW-1:0];
                    carry_q <= {3'b000, nd_sum[SW], d_sum[SW]};
                    sub_q   <= !sub_q;
                    if (sub_q) state_q <= MUL2;
                end
                MUL2: begin
                    h_q <= (m_q - 1'b1) >> 1;
                    if (mdone) state_q <= ADD3;
                end
                ADD3: begin
                    c_q     <= c_sum[SW-1:0];
                    d_q     <= dsum[SW-1:0];
                    t_q     <= t_sum[SW-1:0];
                    carry_q <= {2'b00, t_sum[SW], dsum[SW], c_sum[SW]};
                    sub_q   <= !sub_q;
                    if (sub_q) state_q <= CHECK;
                end
                CHECK: begin
                    e1_q    <= {{(NW-1){1'b0}}, 1'b1};
                    state_q <= bad ? IDLE : (at_start && !full_q) ? LAST : RUN;
                end
                RUN: if (fin_q) state_q <= IDLE; else if (go) begin
                    u_q     <= u_x;
                    v_q     <= v_x;
                    s1_q    <= take_diagonal ? s1_d : s1_a;
                    s3_q    <= take_diagonal ? s3_d : s3_a;
                    uw_q    <= take_diagonal ? window(su_d, ue) : window(su_a, ue);
                    vw_q    <= take_diagonal ? window(sv_d, ve) : window(sv_a, ve);
                    s1w_q   <= take_diagonal ? window(ss1_d, s1e) : window(ss1_a, s1e);
                    s3w_q   <= take_diagonal ? window(ss3_d, s3e) : window(ss3_a, s3e);
                    {xm_q, mjn_q, mnn_q} <= take_diagonal ? oct_d : oct_a;
                    {xs_q, ys_q} <= take_diagonal ? point_ops(oct_d[2], oct_d[1], oct_d[0], u_d, v_d)
                                                  : point_ops(oct_a[2], oct_a[1], oct_a[0], u_a, v_a);
                    eop_q   <= take_diagonal ? end_ops(oct_d[2], oct_d[1], oct_d[0])
                                             : end_ops(oct_a[2], oct_a[1], oct_a[0]);
                    e1_q    <= take_diagonal ? diagonal_e : axial_e;
                    c_q     <= take_diagonal ? c_d : c_a;
                    d_q     <= take_diagonal ? d_d : d_a;
                    {hcz_q, hdz_q, hdm1_q, hdpos_q} <= take_diagonal ? high_flags(lc_d[K+1:K], ld_d[K+1:K])
                                                                     : high_flags(lc_a[K+1:K], ld_a[K+1:K]);
                end
                LAST: state_q <= IDLE;
                default: state_q <= IDLE;
            endcase
            if (state_q == ADD2 && sub_q) begin     // s = min(a, b), m = |d| and its flags
                a_q      <= d_sum[SW-1] ? b_q : a_q;
                m_q      <= m_abs;
            end
            if (state_q == MUL2) begin
                dzero_q  <= dd_q == {SW{1'b0}};
                msmall_q <= dd_q[SW-1] ? nd_q[SW-1:K] == {HW{1'b0}} : dd_q[SW-1:K] == {HW{1'b0}};
            end
            if (state_q != RUN) begin           // the flags, octant and operands of the start point
                uw_q     <= ue[6:2];                // (settled long before CHECK; only RUN reads them)
                vw_q     <= ve[6:2];
                s1w_q    <= s1e[6:2];
                s3w_q    <= s3e[6:2];
                {xm_q, mjn_q, mnn_q} <= oct_0;
                {xs_q, ys_q} <= point_ops(xm_q, mjn_q, mnn_q, u_q, v_q);
                eop_q    <= end_ops(xm_q, mjn_q, mnn_q);
                {hcz_q, hdz_q, hdm1_q, hdpos_q} <= high_flags(2'b00, 2'b00);
            end
            if (act_x) dir_x <= neg_x;
            if (act_y) dir_y <= neg_y;
            step_x <= act_x;
            step_y <= act_y;
            fin_q  <= go && last;
            done   <= state_q == LAST || fin_q;
            error  <= state_q == CHECK && bad;
        end
    end

    wire [NW-1:0] e_q = e1_q - {{(NW-1){1'b0}}, 1'b1};    // E, for the benches (not used here)
    wire unused = &{1'b0, e_q, mbusy, mdone_other, p0[PW-1:SW], p1[PW-1:SW], p2[PW-1:SW], p3[PW-1:SW],
                    carry_q[4:3], nd_q[K-1:0], uw_q[4], uw_q[0], vw_q[4], vw_q[0], xop[NW-1]};
endmodule
`default_nettype wire
