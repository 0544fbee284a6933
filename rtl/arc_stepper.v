`default_nettype none
// Run loop of the production arc core circ_arc: the midpoint steps of SPEC §4/§5 in
// octant-local coordinates, so that a step is a handful of register + register sums
// and every decision reads registers.
//
// Midpoint choice.  In an octant the leading step a and the minor step b are fixed;
// with p = P.a, q = P.b (P = (u, v) relative to the centre), E = u^2 + v^2 - R^2:
//   T = E + 2p + q + 1 (F at the midpoint P + a + b/2),  diagonal a + b <=> (T < 0) == (q > 0);
//   axial:    E += 2p + 1,       T += 2p + 3,       p += 1;
//   diagonal: E += 2p + 2q + 2,  T += 2p + 2q + 5,  p += 1, q += 1;
// so E and T move by {p, 1}, {p + 1, 1}, {p + q + 1, 0}, {p + q + 2, 1}: counters.  q is
// never 0; p runs from -q to 0 (q > 0) or from 0 to |q| (q < 0).  The octant ends when the
// next point has p >= 0 (q > 0: b turns, q = -q) or |p| >= |q| (q < 0: a and b swap, and
// b turns as well if q reaches 0): the signs of p + 1, p + q + 1, p + q + 2.  The two cycles
// after a step into a new octant reload T (a carry-save step, then the carry chain) and the
// counters, and take no step (`tick` is an enable).
//
// End.  The last step goes to the end point End when the next point P' reaches or
// passes the ray from the centre through End with dot(P', End) > 0, which happens only
// with P within one step of End (tb/circ_arc/test_arc_model.py).  So with D = P - End:
//   last = |D| <= 1 and pos(D) and not pos(D + s) and dot(End + D + s, End) > 0,
//   pos(D) = turn * cross(D, End) > 0  (turn = +1 CCW, -1 CW);
// the signs of cross(d, End) for the eight directions d of the 5x5 grid, and the dot
// test (always true for |End|^2 > 8), form two 25-bit tables of the command; per octant
// they give 9-bit last-step tables for the axial and the diagonal step, and tables
// shifted by either step, so the last-step flags for the next step are registered from
// the one-hot windows D = -2 .. 2 per axis.
//
// For the clock: T is held as -T - 1 while q < 0, so the decision is T's top bit (no
// register and LUT of its own); the point is kept only as D (u, v = End + D, for the
// benches); both candidate values are summed from registers and the decision selects
// after the carry chains; the counters of diagonal steps are sums with the decision at
// bit 0, not holds (a hold becomes a clock enable net of its own); the reload values,
// the octants' tables and `fin`/reload state for the step enable are registered, so a
// reload is a plain load and the enable one LUT.
//
// Timing: while `run` is low the registers follow the inputs; they settle within
// 9 cycles.  With `run` high, one step per `tick` (strobes and dir levels registered
// together), plus two reload cycles after each step into a new octant; `fin` comes with
// the last step's strobes.  Used by circ_arc.
module arc_stepper #(
    parameter integer WIDTH = 32,           // circ_arc's coordinate width (>= 6); |u|, |v| < 2^(WIDTH-3)
    parameter integer CARRY_SELECT = 1      // 1: loop adders cut in two (iCE40); 0: one chain (ECP5)
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             run,    // 1: step; 0: follow the inputs
    input  wire             tick,
    input  wire [WIDTH:0]   u0,     // start point relative to the centre (signed)
    input  wire [WIDTH:0]   v0,
    input  wire [WIDTH:0]   u1,     // end point relative to the centre
    input  wire [WIDTH:0]   v1,
    input  wire             ccw,
    output reg              step_x,
    output reg              step_y,
    output reg              dir_x,  // 1 = negative direction
    output reg              dir_y,
    output reg              fin,    // the last step's strobes are out
    output wire [WIDTH:0]   u,      // current point (for the benches)
    output wire [WIDTH:0]   v,
    output wire [WIDTH+1:0] e       // E
);
    initial begin
        if (WIDTH < 6) $error("%m: WIDTH must be at least 6");
        if (CARRY_SELECT != 0 && CARRY_SELECT != 1) $error("%m: CARRY_SELECT must be 0 or 1");
    end

    localparam integer UW = WIDTH + 1;      // coordinates, p, q and their sums
    localparam integer NW = WIDTH + 2;      // E and T

    reg               reload_q, reload2_q;          // the two reload cycles after a new octant
    reg               ok_q;                         // none of fin, reload_q, reload2_q
    reg               xm_q, mjn_q, mnn_q, qpos_q;  // x major, a < 0, b < 0, q > 0
    reg  [UW-1:0]     u_q, v_q, du_q, dv_q;        // the start point (loading), D = P - End
    reg  [UW-1:0]     u1_q, v1_q;                  // End (read while loading)
    reg  [UW-1:0]     s1_q, s3_q;                  // u + v, v - u (first octant only)
    reg               uz_q, vz_q, s1z_q, s3z_q;    // == 0
    reg  [UW-1:0]     ua_q, ud_q, va_q, vd_q;      // the axial and the diagonal step (-1, 0, +1)
    reg  [UW-1:0]     pa_q, pb_q;                  // P.a, P.b less the + 1 of a negation (loading)
    reg  [UW-1:0]     p_q, p1_q, q_q, q1_q, q2_q, nq_q;  // p, p + 1, q, q + 1, q + 2, -q
    reg  [UW-1:0]     g1_r, g2_r, q1_r, q2_r, nq_r;      // reload values of g1_q .. nq_q
    reg               qm1_r, last_a_r, last_d_r;         // and of qm1_q, last_a_q, last_d_q
    reg  [NW-1:0]     t_cs_q, t_cc_q;              // T's reload: E + 2p + q + 1 in carry-save form
    reg  [UW-1:0]     g1_q, g2_q;                  // p + q + 1, p + q + 2
    reg               qm1_q;                       // q == -1
    reg  [NW-1:0]     t_q, e_q;                    // T (-T - 1 when q < 0: the decision is its sign), E
    // T's steps p + 1, p + q + 2, complemented when q < 0 (p1_q, g2_q XOR !qpos_q), held in registers
    // so that T's chains start at registers (and their reload values, like g1_r .. nq_r).
    reg  [UW-1:0]     p1x_q, g2x_q, p1x_r, g2x_r;
    reg  [4:0]        duw_q, dvw_q;                // D = -2 .. 2, per axis (one-hot or none)
    reg               near_u_q, near_v_q;          // |D| <= 4 per axis, a cycle ago
    reg  [UW-1:0]     r1_q, r2_q, r3_q, r5_q, r6_q, r7_q;   // cross(d, End), see `dirs`
    reg               small_q;                     // |u1|, |v1| <= 2
    reg  [7:0]        dneg_q, dzero_q;             // cross(d, End) < 0, == 0
    reg  [24:0]       pos_q, dot_q;                // pos(D), dot(End + D, End) > 0 on the 5x5 grid
    reg  [8*18-1:0]   lt_all_q;                    // lt_all, registered
    reg  [17:0]       lt_q, lt1_q, lt2_q;          // {diagonal, axial} last-step tables: octant, next ones
    reg  [99:0]       st_q;                        // tables shifted by a step: {DD, DA, AD, AA}
    reg               last_a_q, last_d_q;          // the axial / diagonal step is the last

    reg               loaded_q;                    // loading a cycle ago: u_q, v_q hold P
    assign u = loaded_q ? u_q : u1_q + du_q;       // P = End + D while running (for the benches only)
    assign v = loaded_q ? v_q : v1_q + dv_q;
    assign e = e_q;

    // ---------------------------------------------------------------- first octant
    // Leading axis: the tangent's larger component; on a diagonal, the one of the next octant.
    // |v| > |u| <=> (v + u)(v - u) > 0;  |v| = |u| <=> v + u = 0 or v - u = 0.
    function automatic [2:0] octant;   // {x_major, major_neg, minor_neg}
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
    wire [2:0] oct_0 = octant(u_q[UW-1], uz_q, v_q[UW-1], vz_q, s1_q[UW-1], s1z_q, s3_q[UW-1], s3z_q, ccw);

    // ---------------------------------------------------------------- end tables
    // The eight directions d of the grid (upper half plane) and cross(d, End) = du v1 - dv u1:
    //   0 (1,0): v1      1 (2,1): 2v1 - u1   2 (1,1): v1 - u1    3 (1,2): v1 - 2u1
    //   4 (0,1): -u1     5 (-1,2): -(v1 + 2u1)  6 (-1,1): -(v1 + u1)  7 (-2,1): -(2v1 + u1)
    // Index of the direction of a grid point, + 8 when it points the other way.
    function integer dirs(input integer du, dv);
        integer g, pu, pv, flip;
        begin
            g = (du % 2 == 0 && dv % 2 == 0) ? 2 : 1;
            pu = du / g;
            pv = dv / g;
            flip = (pv < 0 || (pv == 0 && pu < 0)) ? 8 : 0;
            if (flip != 0) begin
                pu = -pu;
                pv = -pv;
            end
            dirs = flip + (pv == 0 ? 0 : pv == 2 ? (pu == 1 ? 3 : 5) : pu == 2 ? 1 : pu == 1 ? 2 : pu == 0 ? 4 :
                           pu == -1 ? 6 : 7);
        end
    endfunction
    // dot(End + D, End) > 0 for End = (eu, ev) in -4 .. 3 per axis, bit {eu, ev} (3 bits each).
    function [63:0] dot_table(input integer du, dv);
        integer i, eu, ev;
        begin
            for (i = 0; i < 64; i = i + 1) begin
                eu = i / 8 >= 4 ? i / 8 - 8 : i / 8;
                ev = i % 8 >= 4 ? i % 8 - 8 : i % 8;
                dot_table[i] = eu * eu + ev * ev + du * eu + dv * ev > 0;
            end
        end
    endfunction
    // The signs and zeros of cross(d, End) are registers, dneg_q and dzero_q (loaded
    // while loading, one cycle after r1_q .. r7_q).
    // turn * cross(d, End) > 0 and < 0 (directions 4 .. 7 hold -cross).
    wire [7:0] flip = {{4{ccw}}, {4{!ccw}}};
    wire [7:0] dgt = (dneg_q & flip) | (~dneg_q & ~dzero_q & ~flip);
    wire [7:0] dlt = (dneg_q & ~flip) | (~dneg_q & ~dzero_q & flip);
    wire [24:0] pos_w, dot_w;
    genvar gi;
    generate
        for (gi = 0; gi < 25; gi = gi + 1) begin : g_grid        // grid point D = (gi / 5 - 2, gi % 5 - 2)
            localparam integer DU = gi / 5 - 2, DV = gi % 5 - 2;
            localparam integer DIR = (DU == 0 && DV == 0) ? 0 : dirs(DU, DV);
            if (DU == 0 && DV == 0) begin : g_centre
                assign pos_w[gi] = 1'b0;
            end else if (DIR >= 8) begin : g_back
                assign pos_w[gi] = dlt[DIR-8];
            end else begin : g_fore
                assign pos_w[gi] = dgt[DIR];
            end
            // dot(End + D, End) = |End|^2 + D.End > 0: true when |End|^2 > 8 (|D| <= 2 sqrt 2),
            // else a function of End's low three bits per axis.
            localparam [63:0] DOT_SMALL = dot_table(DU, DV);
            assign dot_w[gi] = !small_q || DOT_SMALL[{u1_q[2:0], v1_q[2:0]}];
        end
    endgenerate
    // Last-step tables for the steps a, a + b (unit vectors (au, av), (bu, bv)): bit
    // 3 (du + 1) + (dv + 1) for D in -1 .. 1 per axis, {diagonal step, axial step}.
    function automatic [17:0] tables_for(input integer au, av, bu, bv, input [24:0] pos_t, dot_t);
        integer i, j, k;
        begin
            for (i = -1; i <= 1; i = i + 1)
                for (j = -1; j <= 1; j = j + 1) begin
                    k = 3 * (i + 1) + j + 1;
                    tables_for[k] = pos_t[5 * (i + 2) + j + 2] && !pos_t[5 * (i + au + 2) + j + av + 2] &&
                                    dot_t[5 * (i + au + 2) + j + av + 2];
                    tables_for[9 + k] = pos_t[5 * (i + 2) + j + 2] &&
                                        !pos_t[5 * (i + au + bu + 2) + j + av + bv + 2] &&
                                        dot_t[5 * (i + au + bu + 2) + j + av + bv + 2];
                end
        end
    endfunction
    // A 9-bit table moved onto the 5x5 grid of the point before a step s: bit 5 (du + 2) + dv + 2.
    function automatic [24:0] moved(input [8:0] table_t, input integer su_f, sv_f);
        integer i, j;
        begin
            for (i = -2; i <= 2; i = i + 1)
                for (j = -2; j <= 2; j = j + 1)
                    moved[5 * (i + 2) + j + 2] = (i + su_f >= -1 && i + su_f <= 1 && j + sv_f >= -1 && j + sv_f <= 1) &&
                                                 table_t[3 * (i + su_f + 1) + j + sv_f + 1];
        end
    endfunction
    // The tables moved by the axial and the diagonal step: {DD, DA, AD, AA} (step, test).
    function automatic [99:0] moved_for(input integer au, av, bu, bv, input [17:0] tables);
        moved_for = {moved(tables[17:9], au + bu, av + bv), moved(tables[8:0], au + bu, av + bv),
                     moved(tables[17:9], au, av), moved(tables[8:0], au, av)};
    endfunction
    // Per octant {x major, a < 0, b < 0} the tables are plain wiring of the command's and
    // the octant's tables (continuous assignments: simulators re-evaluate them only when
    // those change): last-step tables of every octant, and the current one's moved tables.
    wire [8*18-1:0] lt_all;                    // octant o at bits 18 o
    wire [8*100-1:0] st_all;
    genvar go_i;
    generate
        for (go_i = 0; go_i < 8; go_i = go_i + 1) begin : g_octant
            localparam integer XM = go_i / 4, MJ = go_i / 2 % 2, MN = go_i % 2;
            localparam integer AU = XM != 0 ? (MJ != 0 ? -1 : 1) : 0, AV = XM != 0 ? 0 : (MJ != 0 ? -1 : 1);
            localparam integer BU = XM != 0 ? 0 : (MN != 0 ? -1 : 1), BV = XM != 0 ? (MN != 0 ? -1 : 1) : 0;
            assign lt_all[18 * go_i +: 18] = tables_for(AU, AV, BU, BV, pos_q, dot_q);
            assign st_all[100 * go_i +: 100] = moved_for(AU, AV, BU, BV, lt_q);
        end
    endgenerate
    // Flags: x == k for k = -3 .. 3 (bit k + 3); the window of x + step for D = -2 .. 2.
    function automatic [6:0] small_eq(input [UW-1:0] x);
        reg hz, ho;
        integer k;
        begin
            hz = x[UW-1:2] == {(UW-2){1'b0}};
            ho = x[UW-1:2] == {(UW-2){1'b1}};
            for (k = -3; k <= 3; k = k + 1)
                small_eq[k+3] = (k >= 0 ? hz : ho) && x[1:0] == k[1:0];
        end
    endfunction
    // The same for D, which moves by at most 1 per cycle: near_q says |D| <= 4 a cycle
    // ago, so D is in -5 .. 5 now and its low four bits tell -3 .. 3 (no wide compare).
    function automatic [6:0] near_eq(input near, input [3:0] x);
        integer k;
        begin
            for (k = -3; k <= 3; k = k + 1)
                near_eq[k+3] = near && x == k[3:0];
        end
    endfunction
    function automatic near4(input [UW-1:0] x);     // -4 <= x <= 4
        near4 = x[UW-1] ? x[UW-1:2] == {(UW-2){1'b1}} : x[UW-1:2] == {(UW-2){1'b0}} || x == {{(UW-3){1'b0}}, 3'd4};
    endfunction
    function automatic [4:0] window(input move, neg, input [6:0] eq);
        window = !move ? eq[5:1] : neg ? eq[6:2] : eq[4:0];
    endfunction
    // OR over the grid of window AND table (the window: one-hot per axis).
    function automatic hit(input [4:0] wu, wv, input [24:0] table_t);
        hit = |({{5{wu[4]}}, {5{wu[3]}}, {5{wu[2]}}, {5{wu[1]}}, {5{wu[0]}}} & {5{wv}} & table_t);
    endfunction

    // Carry-select sums for the loop (iCE40's carry chain is slow): the low part and both
    // versions of the high part at once; a + b + 1 written as a - ~b, so Yosys keeps it apart.
    localparam integer LN = NW * 2 / 5, LU = UW * 2 / 5;     // low parts
    function automatic [NW-1:0] add_n(input [NW-1:0] a, b);
        reg [LN:0] lo;
        begin
            lo = {1'b0, a[LN-1:0]} + {1'b0, b[LN-1:0]};
            add_n = CARRY_SELECT == 0 ? a + b
                                      : {lo[LN] ? a[NW-1:LN] - ~b[NW-1:LN] : a[NW-1:LN] + b[NW-1:LN], lo[LN-1:0]};
        end
    endfunction
    /* verilator lint_off UNUSEDSIGNAL */        // sum's top bit
    function automatic [UW-1:0] add_u(input [UW-1:0] a, b);   // the same, one bit narrower
        reg [NW-1:0] sum;
        begin
            sum = add_n({a[UW-1], a}, {b[UW-1], b});
            add_u = sum[UW-1:0];
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    function automatic [UW-1:0] add1_u(input [UW-1:0] a, b);  // a + b + 1 ({0, x} - {1, ~y} = x + y + 1)
        reg [LU:0] lo;
        begin
            lo = {1'b0, a[LU-1:0]} - {1'b1, ~b[LU-1:0]};
            add1_u = CARRY_SELECT == 0 ? a - ~b
                                       : {lo[LU] ? a[UW-1:LU] - ~b[UW-1:LU] : a[UW-1:LU] + b[UW-1:LU], lo[LU-1:0]};
        end
    endfunction
    function automatic [UW-1:0] inc_u(input [UW-1:0] a);     // a + 1
        inc_u = CARRY_SELECT == 0 ? a + 1'b1 : {&a[LU-1:0] ? a[UW-1:LU] + 1'b1 : a[UW-1:LU], a[LU-1:0] + 1'b1};
    endfunction

    // ---------------------------------------------------------------- the step
    wire td   = t_q[NW-1];                       // take the diagonal: (T < 0) == (q > 0)
    wire go   = run && ok_q && tick;             // ok_q = !fin && !reload_q && !reload2_q
    wire loading = !run || rst;
    wire last = td ? last_d_q : last_a_q;
    // At the last step the end point is one step away: D = P - End in -1 .. 1 per axis.
    // Axial step a, diagonal step a + b.
    wire nxa = mjn_q, nxd = xm_q ? mjn_q : mnn_q;   // x step negative (A: when x major)
    wire nya = mjn_q, nyd = xm_q ? mnn_q : mjn_q;
    wire mx = td || xm_q, my = td || !xm_q;         // the candidate moves x, y
    wire nx = td ? nxd : nxa, ny = td ? nyd : nya;
    wire act_x = go && (last ? !duw_q[2] : mx);
    wire act_y = go && (last ? !dvw_q[2] : my);
    wire neg_x = last ? duw_q[3] : nx;
    wire neg_y = last ? dvw_q[3] : ny;
    wire [UW-1:0] one = {{(UW-1){1'b0}}, 1'b1}, two = {{(UW-2){1'b0}}, 2'b10}, td_u = {{(UW-1){1'b0}}, td};
    // Both candidate values of D are summed from registers (the octant's step vectors,
    // registered from the octant) and the decision selects late, after the carry chains.
    wire [UW-1:0] du_a = add_u(du_q, ua_q), du_d = add_u(du_q, ud_q), dv_a = add_u(dv_q, va_q), dv_d = add_u(dv_q, vd_q);
    wire [UW-1:0] zero = {UW{1'b0}};
    function automatic [UW-1:0] unit(input move, neg);      // -1, 0, +1
        unit = {{(UW-1){move && neg}}, move};
    endfunction
    // With q < 0 the register holds ~T, and ~(T + {x, 1}) = ~T + {~x, 1}.
    wire [NW-1:0] t_a = add_n(t_q, {p1x_q, 1'b1}), t_d = add_n(t_q, {g2x_q, 1'b1});
    wire [NW-1:0] e_a = add_n(e_q, {p_q, 1'b1}),  e_d = add_n(e_q, {g1_q, 1'b0});
    wire [UW-1:0] p1_1 = add_u(p1_q, one), g2_next = g2_q + {{(UW-2){1'b0}}, td, !td};
    wire [UW-1:0] q_next = td ? q1_q : q_q;          // q', -q' (-(q + 1) = ~q)
    wire [UW-1:0] nq_next = td ? ~q_q : nq_q;
    // The octant ends: p' >= 0 (q > 0) or p' + q' >= 0 (q < 0).
    wire bound = qpos_q ? !p1_q[UW-1] : td ? !g2_q[UW-1] : !g1_q[UW-1];
    wire turn2 = !qpos_q && qm1_q && td;             // swap, and q' = 0: turn as well
    // The next octants: q > 0: b turns; q < 0: a and b swap (and b turns).
    wire [2:0] oct1 = qpos_q ? {xm_q, mjn_q, !mnn_q} : {!xm_q, mnn_q, mjn_q};
    wire [2:0] oct2 = {!xm_q, mnn_q, !mjn_q};
    wire [UW-1:0] p_new = qpos_q ? p1_q : q_next;                        // after the turn / swap
    wire [UW-1:0] q_new = qpos_q ? nq_next : turn2 ? ~p_q : p1_q;
    // Reload (and while not running): T and the counters from E, p and q.
    wire [NW-1:0] p2w = {p_q, 1'b0}, qw = {q_q[UW-1], q_q};
    // ~(a + b) = ~a + ~b + 1: b's bit 0 is the + 1 when q > 0 and 0 in ~b, so it stays 1.
    wire [NW-1:0] t_cs = e_q ^ p2w ^ qw ^ {NW{!qpos_q}};
    wire [NW-1:0] t_cc = {((e_q[NW-2:0] & p2w[NW-2:0]) | (e_q[NW-2:0] & qw[NW-2:0]) |
                           (p2w[NW-2:0] & qw[NW-2:0])) ^ {(NW-1){!qpos_q}}, 1'b1};   // + 1
    wire [NW-1:0] t_new = add_n(t_cs_q, t_cc_q);
    wire [6:0] due = near_eq(near_u_q, du_q[3:0]), dve = near_eq(near_v_q, dv_q[3:0]);
    wire [4:0] w1u = {1'b0, duw_q[3:1], 1'b0}, w1v = {1'b0, dvw_q[3:1], 1'b0};   // |D| <= 1
    function automatic [24:0] grid(input [8:0] table_t);   // a 9-bit table on the 5x5 grid
        grid = moved(table_t, 0, 0);
    endfunction
    // Inputs of the registers that take a new value every cycle, as continuous
    // assignments (simulators evaluate the functions only when their inputs change).
    wire [UW-1:0] g1_w = add_u(p1_q, q_q), g2_w = add1_u(p1_q, q_q), q1_w = inc_u(q_q);
    wire [UW-1:0] q2_w = add_u(q_q, two), nq_w = inc_u(~q_q);
    wire          last_a_w = hit(w1u, w1v, grid(lt_q[8:0])), last_d_w = hit(w1u, w1v, grid(lt_q[17:9]));
    wire [UW-1:0] ua_w = unit(xm_q, nxa), ud_w = unit(1'b1, nxd), va_w = unit(!xm_q, nya), vd_w = unit(1'b1, nyd);
    wire          near_u_w = near4(du_q), near_v_w = near4(dv_q);

    always @(posedge clk) begin
        if (rst) begin
            reload_q <= 1'b0;
            reload2_q <= 1'b0;
            ok_q     <= 1'b1;
            fin      <= 1'b0;
            step_x   <= 1'b0;
            step_y   <= 1'b0;
            dir_x    <= 1'b0;
            dir_y    <= 1'b0;
        end else begin
            fin      <= go && last;
            reload_q <= go && bound && !last;
            reload2_q <= reload_q;
            ok_q     <= !(go && (last || bound)) && !reload_q;
            step_x   <= act_x;
            step_y   <= act_y;
            if (act_x) dir_x <= neg_x;
            if (act_y) dir_y <= neg_y;
        end
    end

    // Data registers without reset: they follow the inputs whenever `run` is low (or in reset).
    always @(posedge clk) begin
        // Registers without an enable: fewer enable nets to route.  The reload values
        // (t_cs_q .. last_d_r) and the step vectors change only with the octant, E, p, q
        // and the tables, so they are valid in the second reload cycle.
        t_cs_q <= t_cs;
        t_cc_q <= t_cc;
        st_q  <= st_all[100 * {xm_q, mjn_q, mnn_q} +: 100];
        g1_r  <= g1_w;
        g2_r  <= g2_w;
        p1x_r <= p1_q ^ {UW{!qpos_q}};
        g2x_r <= g2_w ^ {UW{!qpos_q}};
        q1_r  <= q1_w;
        q2_r  <= q2_w;
        nq_r  <= nq_w;
        qm1_r <= q_q == {UW{1'b1}};
        last_a_r <= last_a_w;
        last_d_r <= last_d_w;
        ua_q  <= ua_w;
        ud_q  <= ud_w;
        va_q  <= va_w;
        vd_q  <= vd_w;
        near_u_q <= near_u_w;
        near_v_q <= near_v_w;
        lt_all_q <= lt_all;
        loaded_q <= loading;
        lt1_q <= lt_all_q[18 * oct1 +: 18];
        lt2_q <= lt_all_q[18 * oct2 +: 18];
        if (loading) begin                    // the command's tables; the first octant, p and q
            u1_q    <= u1;
            v1_q    <= v1;
            u_q     <= u0;
            v_q     <= v0;
            e_q     <= {NW{1'b0}};
            du_q    <= u0 - u1_q;
            dv_q    <= v0 - v1_q;
            r1_q    <= {v1_q[UW-2:0], 1'b0} - u1_q;
            r2_q    <= v1_q - u1_q;
            r3_q    <= v1_q - {u1_q[UW-2:0], 1'b0};
            r5_q    <= v1_q + {u1_q[UW-2:0], 1'b0};
            r6_q    <= v1_q + u1_q;
            r7_q    <= {v1_q[UW-2:0], 1'b0} + u1_q;
            dneg_q  <= {r7_q[UW-1], r6_q[UW-1], r5_q[UW-1], u1_q[UW-1], r3_q[UW-1], r2_q[UW-1], r1_q[UW-1], v1_q[UW-1]};
            dzero_q <= {r7_q == {UW{1'b0}}, r6_q == {UW{1'b0}}, r5_q == {UW{1'b0}}, u1_q == {UW{1'b0}},
                        r3_q == {UW{1'b0}}, r2_q == {UW{1'b0}}, r1_q == {UW{1'b0}}, v1_q == {UW{1'b0}}};
            small_q <= (small_eq(u1_q) & 7'b0111110) != 7'd0 && (small_eq(v1_q) & 7'b0111110) != 7'd0;
            pos_q   <= pos_w;
            dot_q   <= dot_w;
            s1_q    <= u_q + v_q;
            s3_q    <= v_q - u_q;
            uz_q    <= u_q == {UW{1'b0}};
            vz_q    <= v_q == {UW{1'b0}};
            s1z_q   <= s1_q == {UW{1'b0}};
            s3z_q   <= s3_q == {UW{1'b0}};
            {xm_q, mjn_q, mnn_q} <= oct_0;
            pa_q    <= (xm_q ? u_q : v_q) ^ {UW{mjn_q}};
            pb_q    <= (xm_q ? v_q : u_q) ^ {UW{mnn_q}};
            qpos_q  <= !pb_q[UW-1];             // q = P.b > 0 (never 0)
            p_q     <= add_u(pa_q, {{(UW-1){1'b0}}, mjn_q});    // P.a
            p1_q    <= inc_u(p_q);
            q_q     <= add_u(pb_q, {{(UW-1){1'b0}}, mnn_q});    // P.b
            lt_q    <= lt_all_q[18 * {xm_q, mjn_q, mnn_q} +: 18];
            duw_q   <= due[5:1];
            dvw_q   <= dve[5:1];
        end else if (go) begin
            e_q     <= td ? e_d : e_a;
            {xm_q, mjn_q, mnn_q} <= !bound ? {xm_q, mjn_q, mnn_q} : turn2 ? oct2 : oct1;
            qpos_q  <= bound ? !qpos_q && !turn2 : qpos_q;
            lt_q    <= !bound ? lt_q : turn2 ? lt2_q : lt1_q;
            du_q    <= td ? (last_d_q ? zero : du_d) : (last_a_q ? zero : du_a);   // the last step ends at End
            dv_q    <= td ? (last_d_q ? zero : dv_d) : (last_a_q ? zero : dv_a);
            duw_q   <= window(mx, nx, due);
            dvw_q   <= window(my, ny, dve);
            p_q     <= bound ? p_new : p1_q;
            // Counters of the diagonal steps: sums with td at bit 0, not holds (Yosys would
            // make each hold a clock enable of its own, a net that goes everywhere), and
            // one chain each (a carry select's halves would be such holds again).
            q_q     <= bound ? q_new : q_q + td_u;
            q1_q    <= q1_q + td_u;
            q2_q    <= q2_q + td_u;
            nq_q    <= nq_q - td_u;
            qm1_q   <= td ? q_q == {{(UW-1){1'b1}}, 1'b0} : q_q == {UW{1'b1}};
            p1_q    <= bound && !qpos_q ? (td ? q2_q : q1_q) : p1_1;   // swap: p = q'
            g1_q    <= g2_q + td_u;
            g2_q    <= g2_next;
            p1x_q   <= p1_1 ^ {UW{!qpos_q}};
            g2x_q   <= g2_next ^ {UW{!qpos_q}};
            t_q     <= td ? t_d : t_a;            // (a new octant reloads T, p1x_q and g2x_q)
            last_a_q <= td ? hit(duw_q, dvw_q, st_q[74:50]) : hit(duw_q, dvw_q, st_q[24:0]);
            last_d_q <= td ? hit(duw_q, dvw_q, st_q[99:75]) : hit(duw_q, dvw_q, st_q[49:25]);
        end
        // Reload, in the second reload cycle: T (its carry-save step t_cs_q, t_cc_q
        // registered in the first) and the counters, from registers computed every cycle,
        // which are valid then since p, q, the tables and the windows hold still after the
        // step; so a reload is a plain load.
        if (loading || reload2_q) begin
            t_q      <= t_new;
            p1x_q    <= p1x_r;
            g2x_q    <= g2x_r;
            g1_q     <= g1_r;
            g2_q     <= g2_r;
            q1_q     <= q1_r;
            q2_q     <= q2_r;
            nq_q     <= nq_r;
            qm1_q    <= qm1_r;
            last_a_q <= last_a_r;
            last_d_q <= last_d_r;
        end
    end
endmodule
`default_nettype wire
