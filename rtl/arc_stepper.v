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
// b turns as well if q reaches 0): the signs of p + 1, p + q + 1, p + q + 2 (p + q + 1 < 0
// is p + q + 2 <= 0, with a registered zero flag).  The six
// cycles after a step into a new octant reload T and the counters (the new octant's kind,
// the operands, a carry-save step, the carry chains, then the loads through the loop's
// own adders) and take no step (`tick` is an enable).
//
// End.  The last step goes to the end point End when the next point P' reaches or
// passes the ray from the centre through End with dot(P', End) > 0, which happens only
// with P within one step of End (tb/circ_arc/test_arc_model.py).  So with D = P - End:
//   last = |D| <= 1 and pos(D) and not pos(D + s) and dot(End + D + s, End) > 0,
//   pos(D) = turn * cross(D, End) > 0  (turn = +1 CCW, -1 CW);
// the signs of cross(d, End) for the eight directions d of the 5x5 grid, and the dot
// test (always true for |End|^2 > 8), form two 25-bit tables of the command; per octant
// they give 9-bit last-step tables for the axial and the diagonal step, read at D's
// one-hot window -1 .. 1 per axis.
//
// Two stages, for the clock.  The decision loop holds only T, p + 1 and p + q + 2
// (complemented while q < 0, so that the decision (T < 0) == (q > 0) is T's top bit),
// each with one adder and no load select (T and p + q + 2 are cleared and loaded
// through their sums); with iCE40's slow carry chains both candidate values are summed
// from registers and the decision selects after the chains, with ECP5's carry cells
// (mux_add) the decision selects the operand inside the chain's own LUTs, so a step is
// the decision bit, its route and the chain.  The step stage, a cycle behind, takes the loop's
// decisions as tokens: the point (kept as D, whose step is registered with the decision;
// u, v = End + D for the benches), E, the octant, the last-step test and the outputs.
// The end test's window runs a step ahead, with the loop's decision (D's low five bits
// and a |D| <= 6 flag four steps old tell D = -2 .. 2, no wide compare), so the
// last-step flags are a registered lookup.  `run` and the enables' terms are
// registered, so each enable is one LUT.
//
// Timing: `run` is registered: the stepper follows it from the next cycle, loading the
// loop in three cycles (reload cycles 4 to 6).  While not running the registers follow
// the inputs; they settle within 9 cycles.  Running, the loop decides one step per
// `tick` and the step's strobes and dir levels come out a cycle later (registered
// together), plus six reload cycles after each step into a new octant; `fin` comes
// with the last step's strobes.  Used by circ_arc.
module arc_stepper #(
    parameter integer WIDTH = 32            // circ_arc's coordinate width (>= 6); |u|, |v| < 2^(WIDTH-3)
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             run,    // 1: step, 0: follow the inputs, from the next cycle on (registered)
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
    end

    localparam integer UW = WIDTH + 1;      // coordinates, p, q and their sums
    localparam integer NW = WIDTH + 2;      // E and T

    // The decision loop: T, p + 1 and p + q + 2 (complemented while q < 0), q's sign.
    reg               reload_q, reload2_q, reload3_q, reload4_q, reload5_q;   // reload cycles 1 .. 5
    reg               ld_t_q;                      // reload cycle 6: T loads
    reg               reloading_q;                 // reload cycles 1 .. 5, or not running
    reg               run_q, ok_q;                 // run; running and no reload cycle
    reg               clr_q;                       // T and p + q + 2 clear (reload cycle 4, not running)
    reg               ld_p_q;                      // p + 1 loads (reload cycles 5, 6, not running)
    reg               idle_q;                      // not running (= !run_q; `loading` adds the reset)
    reg  [NW-1:0]     t_q;                         // T (-T - 1 when q < 0: the decision is its sign)
    reg  [UW-1:0]     p1x_q, g2x_q;                // p + 1, p + q + 2 (complemented when q < 0)
    reg               qpos_q;                      // q > 0
    reg  [UW-1:0]     inc1_q, inc2_q;              // +1, +2 (-1, -2 when q < 0): p + q + 2's steps
    reg  [UW-1:0]     inc1p_q;                     // +1 (-1): p + 1's step
    reg  [UW-1:0]     p1_load_q;                   // p + 1's reload value (T's high bits first)
    reg               t0_q;                        // T's reload value's low bit
    reg  [UW-1:0]     ls_q, lc_q;                  // p + 1's load value in carry-save form (T's high bits first)
    reg  [UW-1:0]     gs_q, gc_q;                  // p + q + 2's reload value in carry-save form, then +1 (-1)
    // The step stage, a cycle behind: the step's decision and octant's end as tokens.
    reg               tok_q, td_l_q;
    reg               done_q;                      // the last step is out: later tokens are dropped
    reg               xm_q, mjn_q, mnn_q, qpos_l_q; // x major, a < 0, b < 0, q > 0
    reg  [UW-1:0]     u_q, v_q, du_q, dv_q;        // the start point (loading), D = P - End
    reg  [UW-1:0]     du0_q, dv0_q;                // start point - End (every cycle; D's load value)
    reg  [UW-1:0]     u1_q, v1_q;                  // End (read while loading)
    reg  [UW-1:0]     s1_q, s3_q;                  // u + v, v - u (first octant only)
    reg               uz_q, vz_q, s1z_q, s3z_q;    // == 0
    reg  [4:0]        ua_q, ud_q, va_q, vd_q;      // the axial and the diagonal step's low bits (-1, 0, +1)
    reg  [UW-1:0]     pa_q, pb_q;                  // P.a, P.b less the + 1 of a negation (loading)
    reg  [UW-1:0]     p_q, q_q;                    // P.a, P.b (loading)
    reg  [NW-1:0]     e_q;                         // E (for the benches)
    reg               near_u_q, near_v_q;          // |D| <= 6 per axis, three cycles ago
    reg               hz_u_q, ho_u_q, hz_v_q, ho_v_q;   // its second stage: D's bits above 3 all 0, all 1
    reg  [3:0]        lo_u_q, lo_v_q;              // and D's low bits
    // The end test's inputs, a step ahead (with the decision loop): D's low bits and its
    // window -1 .. 1 per axis (one-hot or none) at the next step the step stage takes.
    reg  [4:0]        dau_q, dav_q;
    reg  [2:0]        wau_q, wav_q;
    reg               zu_q, zv_q, pu_q, pv_q;      // D = 0, D = 1 per axis at the step stage's step
    reg               small_q;                     // |u1|, |v1| <= 2
    reg  [7:0]        dneg_q, dzero_q;             // cross(d, End) < 0, == 0
    reg  [24:0]       pos_q, dot_q;                // pos(D), dot(End + D, End) > 0 on the 5x5 grid
    reg  [24:0]       dot_small_q;                 // dot > 0 for |End|^2 <= 8, from End's low bits
    reg  [8*18-1:0]   lt_all_q;                    // lt_all, registered
    reg  [17:0]       lt_q;                        // {diagonal, axial} last-step tables of the octant
    reg  [35:0]       lt0_q, lt1_q, lt2_q;         // the first and the next ones, as two halves to OR
    reg  [7:0]        oct0_oh_q, oct1_oh_q, oct2_oh_q;   // the first and the next octants, one-hot (a cycle old)
    reg  [3:0]        oct_n_q;                     // the new octant and q > 0 (a reload's third cycle)
    reg  [17:0]       lt_n_q;                      // and its tables
    reg               last_a_q, last_d_q;          // the axial / diagonal step is the last

    reg               loaded_q;                    // loading a cycle ago: u_q, v_q hold P
    assign u = loaded_q ? u_q : done_q ? u1_q : u1_q + du_q;   // P = End + D (for the benches only)
    assign v = loaded_q ? v_q : done_q ? v1_q : v1_q + dv_q;
    assign e = e_q;

    // ---------------------------------------------------------------- first octant
    // Leading axis: the tangent's larger component; on a diagonal, the one of the next octant.
    // |v| > |u| <=> (v + u)(v - u) > 0;  |v| = |u| <=> v + u = 0 or v - u = 0.
    // Two register stages: x major and both versions of the signs, then the select.
    function automatic [4:0] octant;   // {x_major; major_neg, minor_neg if x major; if not}
        input un, uz, vn, vz, s1n, s1z, s3n, s3z, cc;
        reg xm, up, vp;
        begin
            xm = (!s1z && !s3z && s1n == s3n) || ((s1z || s3z) && ((un == vn) == cc));
            up = !un && !uz;
            vp = !vn && !vz;
            // Tangent (-v, u) for CCW, (v, -u) for CW; a zero minor component steps inwards.
            octant = {xm, cc ? vp : vn, uz ? vp : (cc ? un : up), cc ? un : up, vz ? up : (cc ? vp : vn)};
        end
    endfunction
    reg  [4:0] oct_p_q;
    wire [4:0] oct_p = octant(u_q[UW-1], uz_q, v_q[UW-1], vz_q, s1_q[UW-1], s1z_q, s3_q[UW-1], s3z_q, ccw);
    wire [2:0] oct_0 = {oct_p_q[4], oct_p_q[4] ? oct_p_q[3:2] : oct_p_q[1:0]};

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
    // while loading, one cycle after r1 .. r7).
    // turn * cross(d, End) > 0 and < 0 (directions 4 .. 7 hold -cross).
    wire [7:0] flip = {{4{ccw}}, {4{!ccw}}};
    wire [7:0] dgt = (dneg_q & flip) | (~dneg_q & ~dzero_q & ~flip);
    wire [7:0] dlt = (dneg_q & ~flip) | (~dneg_q & ~dzero_q & flip);
    wire [24:0] pos_w, dot_w, dot_small_w;
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
            assign dot_small_w[gi] = DOT_SMALL[{u1_q[2:0], v1_q[2:0]}];
            assign dot_w[gi] = !small_q || dot_small_q[gi];
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
    // Per octant {x major, a < 0, b < 0} the tables are plain wiring of the command's and
    // the octant's tables (continuous assignments: simulators re-evaluate them only when
    // those change): the last-step tables of every octant.
    wire [8*18-1:0] lt_all;                    // octant o at bits 18 o
    genvar go_i;
    generate
        for (go_i = 0; go_i < 8; go_i = go_i + 1) begin : g_octant
            localparam integer XM = go_i / 4, MJ = go_i / 2 % 2, MN = go_i % 2;
            localparam integer AU = XM != 0 ? (MJ != 0 ? -1 : 1) : 0, AV = XM != 0 ? 0 : (MJ != 0 ? -1 : 1);
            localparam integer BU = XM != 0 ? 0 : (MN != 0 ? -1 : 1), BV = XM != 0 ? (MN != 0 ? -1 : 1) : 0;
            assign lt_all[18 * go_i +: 18] = tables_for(AU, AV, BU, BV, pos_q, dot_q);
        end
    endgenerate
    // An octant's tables by a one-hot select (registered): two halves of four octants,
    // each an AND-OR of two LUT levels, ORed where they are taken.
    function automatic [7:0] one_hot(input [2:0] o);
        one_hot = 8'd1 << o;
    endfunction
    function automatic [35:0] table_of(input [7:0] oh, input [8*18-1:0] all);   // {octants 4-7, 0-3}
        integer i;
        begin
            table_of = 36'd0;
            for (i = 0; i < 8; i = i + 1)
                table_of[18 * (i / 4) +: 18] = table_of[18 * (i / 4) +: 18] | ({18{oh[i]}} & all[18 * i +: 18]);
        end
    endfunction
    // |x| <= 2 from x's parts: its bits above 1 all 0 or all 1, and its low bits.
    function automatic small2(input hz, ho, input [1:0] lo);
        small2 = (hz && lo != 2'd3) || (ho && lo[1]);
    endfunction
    // x == k for k = -2 .. 2 (bit k + 2) for D, which moves by at most 1 per step: near_q
    // says |D| <= 6 at most four steps before, so D is in -10 .. 10 now and its low five
    // bits tell -2 .. 2 (no wide compare).
    function automatic [4:0] near_eq(input near, input [4:0] x);
        integer k;
        begin
            for (k = -2; k <= 2; k = k + 1)
                near_eq[k+2] = near && x == k[4:0];
        end
    endfunction
    function automatic near6(input hz, ho, input [3:0] lo);    // -6 <= x <= 6 from x's parts
        near6 = (hz && lo <= 4'd6) || (ho && lo >= 4'd10);
    endfunction
    // The window -1 .. 1 of x + s (s = -1, 0, +1: move, neg) from the flags x == -2 .. 2.
    function automatic [2:0] window(input move, neg, input [4:0] eq);
        window = !move ? eq[3:1] : neg ? eq[4:2] : eq[2:0];
    endfunction
    // OR over the 3x3 grid of window AND table (the window: one-hot per axis, or none).
    function automatic hit(input [2:0] wu, wv, input [8:0] table_t);
        hit = |({{3{wu[2]}}, {3{wu[1]}}, {3{wu[0]}}} & {3{wv}} & table_t);
    endfunction

    // Wide sums off the loop: one chain_add each (cut in two by its iCE40 form).
    wire [UW-1:0] s1_w, s3_w, p_w, q_w, du0_w, dv0_w, p1_ld, g2_ld;
    wire [7:0]    unused_carries;
    chain_add #(.WIDTH(UW)) u_s1_add (.a(u_q), .b(v_q), .cin(1'b0), .sum(s1_w), .cout(unused_carries[0]));
    chain_add #(.WIDTH(UW), .SUBTRACT(1)) u_s3_add (.a(v_q), .b(u_q), .cin(1'b1), .sum(s3_w), .cout(unused_carries[1]));
    chain_add #(.WIDTH(UW)) u_p_add (.a(pa_q), .b({UW{1'b0}}), .cin(mjn_q), .sum(p_w), .cout(unused_carries[2]));
    chain_add #(.WIDTH(UW)) u_q_add (.a(pb_q), .b({UW{1'b0}}), .cin(mnn_q), .sum(q_w), .cout(unused_carries[3]));
    chain_add #(.WIDTH(UW), .SUBTRACT(1)) u_du0_add (.a(u_q), .b(u1_q), .cin(1'b1), .sum(du0_w), .cout(unused_carries[4]));
    chain_add #(.WIDTH(UW), .SUBTRACT(1)) u_dv0_add (.a(v_q), .b(v1_q), .cin(1'b1), .sum(dv0_w), .cout(unused_carries[5]));
    chain_add #(.WIDTH(UW)) u_p1_ld_add (.a(ls_q), .b(lc_q), .cin(1'b0), .sum(p1_ld), .cout(unused_carries[6]));
    chain_add #(.WIDTH(UW)) u_g2_ld_add (.a(gs_q), .b(gc_q), .cin(1'b0), .sum(g2_ld), .cout(unused_carries[7]));
    wire unused = &{1'b0, unused_carries};
    // ---------------------------------------------------------------- the decision loop
    wire td   = t_q[NW-1];                       // take the diagonal: (T < 0) == (q > 0)
    // `run` is registered (run_q), and so are the enables' terms: ok_q (running, no reload
    // cycle but the first, whose reload_q is a term of its own), ld_t_q, ld_p_q and
    // reload5_q, so each enable is one LUT.
    wire go   = ok_q && !reload_q && tick;
    wire loading = idle_q || rst;                // (idle_q = !run_q: run_q's loads are few)
    wire nqo  = !qpos_q;                         // the registers hold complements
    wire [UW-1:0] one = {{(UW-1){1'b0}}, 1'b1}, two = {{(UW-2){1'b0}}, 2'b10}, zero = {UW{1'b0}};
    // With q < 0 the register holds ~T, and ~(T + {x, 1}) = ~T + {~x, 1}; p + 1 and
    // p + q + 2 count down then.
    // One adder per register, x + y: T + {p + q + 2 or p + 1, 1} by the decision, p + 1 +
    // its step or its load value (x cleared), p + q + 2 + its step by the decision.  T and
    // p + q + 2 take their reload values through the same sums: cleared, they add a
    // register holding the value (T = 0 decides axial, so y is then p + 1's, or inc1_q).
    // So each loop is the decision bit or a register, the select, and the chain, with no
    // load select: with ECP5's carry cells (CARRY_SELECT = 2) the select sits in the
    // cells' LUTs.  With iCE40's slow carry chains (1) every candidate has its own
    // carry-select adder and the selects come after the chains.
    wire [NW-1:0] t_next;
    wire [UW-1:0] p1x_next, g2x_next;
    mux_add #(.WIDTH(NW)) u_t_add (
        .a(t_q), .sel(td), .c({g2x_q, 1'b1}), .d({p1x_q, t0_q}), .sum(t_next));
    mux_add #(.WIDTH(UW), .LOAD(1)) u_p1_add (
        .a(p1x_q), .sel(ld_p_q), .c(p1_load_q), .d(inc1p_q), .sum(p1x_next));
    mux_add #(.WIDTH(UW)) u_g2_add (
        .a(g2x_q), .sel(td), .c(inc2_q), .d(inc1_q), .sum(g2x_next));
    // The octant ends: p' >= 0 (q > 0) or p' + q' >= 0 (q < 0), i.e. p + 1 >= 0, or
    // p + q + 2 >= 0 after a diagonal step and p + q + 1 >= 0 after an axial one.
    // p + q + 1 < 0 <=> p + q + 2 <= 0: its sign and a registered zero flag.
    wire [UW-1:0] p1t = p1x_q ^ {UW{nqo}}, g2t = g2x_q ^ {UW{nqo}};   // p + 1, p + q + 2
    wire p1_neg = p1t[UW-1], g2_neg = g2t[UW-1];
    // p + q + 2 = 0 without a wide compare in the loop: it grows by 1 (axial step) or 2
    // (diagonal) per step, so flags of its values 0, -1, -2 registered with the step give
    // it (p + q + 2 is loaded two cycles before the first step after a reload).
    reg           g2_is0_q, g2_ism1_q, g2_ism2_q;  // p + q + 2 = 0, -1, -2 (a cycle ago)
    wire g2_zero = tok_q ? (td_l_q ? g2_ism2_q : g2_ism1_q) : g2_is0_q;
    wire g1_neg = g2_neg || g2_zero;
    wire bound = qpos_q ? !p1_neg : td ? !g2_neg : !g1_neg;

    // Reload, in six cycles after a step into a new octant (the registers it reads hold
    // still through the first four).  After the step p' = (p + 1) - 1 and q' = (p + q + 2) - (p + 1) - 1,
    // and the new octant's T = E + 2p + q + 1 changes by -2p' - q' + 2p_new + q_new:
    //   TURN (q > 0, b turns; p_new = p', q_new = -q'):  T - 2q', p + 1, 2(p + 1) - (p + q + 2) + 2;
    //   SWAP (q < 0, a and b swap; p_new = q', q_new = p'):  T - p' + q', q' + 1, p + q + 2;
    //   SWAP_TURN (q < 0 and q' = 0; p_new = 0, q_new = -p'):  T - 3p', 1, 2 - p';
    //   LOAD (the start point, E = 0):  2p + q + 1, p + 1, p + q + 2.
    // Each is a + b + c + k (k a constant), complemented for q_new < 0 (~x = ~a + ~b + ~c +
    // 2 - k).  Cycle 1 finds the kind (SWAP_TURN: q = -1 before a diagonal step; with q < 0
    // the registers hold complements, so q + 1 = p1x - g2x, and q = -1 <=> p1x = g2x);
    // cycle 2 registers the operands a, b, c, complemented (the kind fixes both polarities,
    // except LOAD's); cycle 3 sums them with k in carry-save form; cycle 4 resolves the
    // sums, and cycles 5 and 6 load them through the loop's adders (below).
    reg               k_load_q, k_turn_q, k_swap_q, k_st_q;   // the kind, one-hot
    reg               nqn_load_q;                  // LOAD: q < 0
    // q = -1 (q + 1 = p1x - g2x = 0 while q < 0), a cycle old: 4-bit groups of p1x = g2x
    // registered, so the wide compare is two stages.
    localparam integer QG = (UW + 3) / 4;
    function automatic [QG-1:0] equal_groups(input [UW-1:0] a, b);
        integer i;
        reg [4*QG-1:0] x;
        begin
            x = {{(4*QG-UW){1'b0}}, a ^ b};
            for (i = 0; i < QG; i = i + 1) equal_groups[i] = x[4*i +: 4] == 4'd0;
        end
    endfunction
    reg  [QG-1:0]     qm1_g_q;
    wire [QG-1:0]     qm1_g = equal_groups(p1x_q, g2x_q);
    wire              st = &qm1_g_q && td_l_q;     // with q < 0: the step just taken made q' = 0
    function automatic [NW-1:0] sx(input [UW-1:0] x);          // sign-extended
        sx = {x[UW-1], x};
    endfunction
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [NW-1:0] k_n(input integer k);           // a constant (-8 .. 7), NW bits
        k_n = {{(NW-4){k[3]}}, k[3:0]};
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    // One-hot select of the four kinds' operands (functions read only their arguments:
    // continuous assignments re-evaluate them when those change).
    wire [3:0] ksel = {k_st_q, k_swap_q, k_turn_q, k_load_q};
    function automatic [NW-1:0] pick(input [3:0] sel, input [NW-1:0] load_v, turn_v, swap_v, st_v);
        pick = ({NW{sel[0]}} & load_v) | ({NW{sel[1]}} & turn_v) | ({NW{sel[2]}} & swap_v) | ({NW{sel[3]}} & st_v);
    endfunction
    // The operands, complemented where q_new < 0; TURN: q > 0, q_new < 0; SWAP: q < 0, q_new > 0;
    // SWAP_TURN: q < 0, q_new < 0 (the registers hold complements while q < 0).
    wire [NW-1:0] zn = {NW{1'b0}}, ln = {NW{nqn_load_q}};
    wire [NW-1:0] p2w = {p_q, 1'b0}, p1w = {p1x_q, 1'b0}, p1s = sx(p1x_q), g2s = sx(g2x_q);
    wire [NW-1:0] t_a0 = pick(ksel, p2w ^ ln, ~t_q, ~t_q, t_q);
    wire [NW-1:0] t_b0 = pick(ksel, sx(q_q) ^ ln, {g2x_q, 1'b0}, ~g2s, ~p1s);
    wire [NW-1:0] t_c0 = pick(ksel, ln, ~p1w, {p1x_q, 1'b1}, {~p1x_q, 1'b0});
    /* verilator lint_off UNUSEDSIGNAL */        // p + 1 and p + q + 2 are one bit narrower
    wire [NW-1:0] p1_a0 = pick(ksel, sx(p_q) ^ ln, ~p1s, ~g2s, ~zn);
    wire [NW-1:0] p1_b0 = pick(ksel, ln, ~zn, p1s, ~zn);
    wire [NW-1:0] g2_a0 = pick(ksel, sx(p_q) ^ ln, ~p1w, ~g2s, ~p1s);
    wire [NW-1:0] g2_b0 = pick(ksel, sx(q_q) ^ ln, g2s, zn, ~zn);
    /* verilator lint_on UNUSEDSIGNAL */
    // The constants per kind (LOAD: q > 0, q < 0): k, or 2 - k for a complement, less 1 for
    // each zero operand left out of a complement (it would be ~0 = -1).
    function automatic [NW-1:0] pick_k(input [3:0] sel, input nl, input integer kl0, kl1, kt, ks, kst);
        pick_k = pick(sel, nl ? k_n(kl1) : k_n(kl0), k_n(kt), k_n(ks), k_n(kst));
    endfunction
    reg  [NW-1:0] t_a1_q, t_b1_q, t_c1_q;          // cycle 2: the operands
    reg  [NW-1:0] t_k_q, p1_k_q, g2_k_q;           // and the constants
    reg  [UW-1:0] p1_a1_q, p1_b1_q, g2_a1_q, g2_b1_q;
    /* verilator lint_off UNUSEDSIGNAL */        // the carries' top bits
    function automatic [2*NW-1:0] csa(input [NW-1:0] a, b, c);      // {carries, sum} of a + b + c
        reg [NW-1:0] m;
        begin
            m = (a & b) | (a & c) | (b & c);
            csa = {m[NW-2:0], 1'b0, a ^ b ^ c};
        end
    endfunction
    wire [2*NW-1:0] t_cs1 = csa(t_a1_q, t_b1_q, t_c1_q);
    wire [2*NW-1:0] t_cs  = csa(t_cs1[NW-1:0], t_cs1[2*NW-1:NW], t_k_q);
    wire [2*NW-1:0] p1_cs = csa(sx(p1_a1_q), sx(p1_b1_q), p1_k_q);
    wire [2*NW-1:0] g2_cs = csa(sx(g2_a1_q), sx(g2_b1_q), g2_k_q);
    /* verilator lint_on UNUSEDSIGNAL */
    wire          nqn = k_load_q ? nqn_load_q : !k_swap_q;          // q_new < 0
    // Cycle 4 resolves the values: p + q + 2's, and T's high bits for p + 1 (T's low bit
    // needs no sum: the carries' is 0), which takes its own in cycle 5.  One adder for
    // the two, its operands picked as they are registered, so no LUT follows its chain;
    // so also p + q + 2's adder, whose operands are its step (+1 or -1) from cycle 5 on,
    // as the step register inc1_q is its load value in cycle 5.
    // The kind's next value and constants (registered with the kind, from its inputs: no
    // logic shared with the operands' selects behind the kind's registers).
    wire [3:0] ksel_d = {!idle_q && !qpos_q && st, !idle_q && !qpos_q && !st, !idle_q && qpos_q, idle_q};
    wire       nqn_d  = pb_q[UW-1];

    always @(posedge clk) begin
        if (rst) begin
            run_q     <= 1'b0;
            clr_q     <= 1'b1;
            ld_p_q    <= 1'b1;
            ld_t_q    <= 1'b0;
            idle_q    <= 1'b1;
            reload_q  <= 1'b0;
            reload2_q <= 1'b0;
            reload3_q <= 1'b0;
            reload4_q <= 1'b0;
            reload5_q <= 1'b0;
            reloading_q <= 1'b1;
            ok_q      <= 1'b0;
        end else begin
            reload_q  <= go && bound;
            reload2_q <= reload_q;
            reload3_q <= reload2_q;
            reload4_q <= reload3_q || (run && !run_q);   // a start begins here (cleared, resolved)
            reload5_q <= reload4_q;
            ld_t_q    <= reload5_q;
            reloading_q <= (go && bound) || reload_q || reload2_q || reload3_q || reload4_q || !run || !run_q;
            run_q     <= run;
            clr_q     <= !run || reload3_q;
            ld_p_q    <= !run_q || reload4_q || reload5_q;
            idle_q    <= !run;
            ok_q      <= run && !reloading_q;
        end
    end
    always @(posedge clk) begin
        // Every cycle: valid in the reload cycles and (from the start point's p and q) while loading.
        qm1_g_q    <= qm1_g;
        g2_is0_q   <= g2t == zero;
        g2_ism1_q  <= g2t == ~zero;
        g2_ism2_q  <= g2t == ~one;
        if (idle_q || reload_q) begin             // held through the reload
            {k_st_q, k_swap_q, k_turn_q, k_load_q} <= ksel_d;
            t_k_q    <= pick_k(ksel_d, nqn_d, 1, 1, -1, 1, -3);
            p1_k_q   <= pick_k(ksel_d, nqn_d, 1, 0, 1, 1, 0);
            g2_k_q   <= pick_k(ksel_d, nqn_d, 2, -1, -2, 0, -3);
        end
        nqn_load_q <= nqn_d;                        // the sign of q = P.b (loading)
        t_a1_q  <= t_a0;
        t_b1_q  <= t_b0;
        t_c1_q  <= t_c0;
        p1_a1_q <= p1_a0[UW-1:0];
        p1_b1_q <= p1_b0[UW-1:0];
        g2_a1_q <= g2_a0[UW-1:0];
        g2_b1_q <= g2_b0[UW-1:0];
        t0_q    <= !reload5_q || t_cs[0];         // T's low operand bit: 1, T's load value's in cycle 6
        ls_q    <= reload4_q ? p1_cs[UW-1:0] : t_cs[NW-1:1];
        lc_q    <= reload4_q ? p1_cs[NW+UW-1:NW] : t_cs[2*NW-1:NW+1];
        gs_q    <= idle_q || reload3_q ? g2_cs[UW-1:0] : nqn ? ~zero : one;
        gc_q    <= idle_q || reload3_q ? g2_cs[NW+UW-1:NW] : zero;
        // The loop registers: cycle 4 clears T and p + q + 2 and resolves the reload values;
        // cycle 5 loads p + 1 with T's value (its high bits) and p + q + 2 with its own
        // (0 + inc1_q), cycle 6 loads T (0 + {p + 1, low bit}) and p + 1 with its own.  Not
        // running, T and p + q + 2 stay clear and p + 1 holds T's value, so a start is
        // cycles 4 to 6.  (A clear wins over an enable: the flip-flops' reset input.)
        if (clr_q) t_q <= {NW{1'b0}};
        else if (ld_t_q || go) t_q <= t_next;
        if (ld_p_q || go) p1x_q <= p1x_next;
        if (clr_q) g2x_q <= zero;
        else if (reload5_q || go) g2x_q <= g2x_next;
        p1_load_q <= p1_ld;                     // T's high bits in cycle 5, p + 1's own in 6
        inc1_q  <= g2_ld;                       // cycle 5: p + q + 2's value (0 + inc1_q), then its step
        if (reload5_q) begin
            qpos_q  <= !nqn;
            inc2_q  <= nqn ? ~one : two;
            inc1p_q <= nqn ? ~zero : one;
        end
    end

    // ---------------------------------------------------------------- the step stage
    // A cycle behind the decision: the point, the octant, the end test and the outputs.
    wire step = tok_q && !done_q;
    wire last = td_l_q ? last_d_q : last_a_q;
    // At the last step the end point is one step away: D = P - End in -1 .. 1 per axis.
    // Axial step a, diagonal step a + b.
    wire nxa = mjn_q, nxd = xm_q ? mjn_q : mnn_q;   // x step negative (A: when x major)
    wire nya = mjn_q, nyd = xm_q ? mnn_q : mjn_q;
    wire mx = td_l_q || xm_q, my = td_l_q || !xm_q; // the candidate moves x, y
    wire nx = td_l_q ? nxd : nxa, ny = td_l_q ? nyd : nya;
    wire act_x = step && (last ? !zu_q : mx);
    wire act_y = step && (last ? !zv_q : my);
    wire neg_x = last ? pu_q : nx;
    wire neg_y = last ? pv_q : ny;
    // D moves by the step's vector, registered a cycle ahead from the loop's decision and
    // the octant's step vectors, so registers feed the chain and the decision is off D's path.
    reg  [UW-1:0] su_q, sv_q;
    // Not running (idle_q) D takes its load value: x cleared, y the value (mux_add LOAD).
    wire [UW-1:0] du_next, dv_next;
    mux_add #(.WIDTH(UW), .LOAD(1)) u_du_add (.a(du_q), .sel(idle_q), .c(du0_q), .d(su_q), .sum(du_next));
    mux_add #(.WIDTH(UW), .LOAD(1)) u_dv_add (.a(dv_q), .sel(idle_q), .c(dv0_q), .d(sv_q), .sum(dv_next));
    function automatic [UW-1:0] unit(input move, neg);      // -1, 0, +1
        unit = {{(UW-1){move && neg}}, move};
    endfunction
    // The next octants: q > 0: b turns; q < 0: a and b swap (and b turns).
    wire [2:0] oct1 = qpos_l_q ? {xm_q, mjn_q, !mnn_q} : {!xm_q, mnn_q, mjn_q};
    wire [2:0] oct2 = {!xm_q, mnn_q, !mjn_q};
    // The end test's window a step ahead: D's low bits and window move with the decision
    // loop's steps (the step stage's octant and step vectors are the loop's step's: after
    // a step into a new octant the loop reloads while the step stage catches up).
    wire [4:0] eau = near_eq(near_u_q, dau_q), eav = near_eq(near_v_q, dav_q);
    wire mx_f = td || xm_q, my_f = td || !xm_q;
    wire nx_f = td ? nxd : nxa, ny_f = td ? nyd : nya;
    // Inputs of the registers that take a new value every cycle, as continuous
    // assignments (simulators evaluate the functions only when their inputs change).
    wire          last_a_w = hit(wau_q, wav_q, lt_q[8:0]), last_d_w = hit(wau_q, wav_q, lt_q[17:9]);
    wire [4:0]    dau_a = dau_q + ua_q, dau_d = dau_q + ud_q, dav_a = dav_q + va_q, dav_d = dav_q + vd_q;
    wire [4:0]    dau_w = td ? dau_d : dau_a, dav_w = td ? dav_d : dav_a;   // (the decision after the sums)
    wire [UW-1:0] ua_w = unit(xm_q, nxa), ud_w = unit(1'b1, nxd), va_w = unit(!xm_q, nya), vd_w = unit(1'b1, nyd);
    wire          near_u_w = near6(hz_u_q, ho_u_q, lo_u_q), near_v_w = near6(hz_v_q, ho_v_q, lo_v_q);
    // E = T - (p + 1) - (p + q + 2) + 2, from the decision loop, which is a step ahead.
    wire [NW-1:0] tt = t_q ^ {NW{nqo}};
    wire [NW-1:0] e_w = tt - sx(p1t) - sx(g2t) + k_n(2);

    // cross(d, End) for d = 1, 2, 3, 5, 6, 7 as x + y + c (c = 1 with y = ~u1 or ~2u1), registered
    // in two halves while loading: the high half takes the low half's carry of the cycle
    // before (End holds still while loading, so they settle in two cycles).  They read a
    // copy of End of their own (without an enable, so it stays a copy: End's loads span
    // the chip).
    localparam integer RL = UW / 2;
    reg  [UW-1:0]   u1c_q, v1c_q;
    always @(posedge clk) begin
        u1c_q <= u1;
        v1c_q <= v1;
    end
    wire [UW-1:0]   u2 = {u1c_q[UW-2:0], 1'b0}, v2 = {v1c_q[UW-2:0], 1'b0};
    wire [6*UW-1:0] r_x = {v2, v1c_q, v1c_q, v1c_q, v1c_q, v2};   // r7, r6, r5, r3, r2, r1
    wire [6*UW-1:0] r_y = {u1c_q, u1c_q, u2, ~u2, ~u1c_q, ~u1c_q};
    wire [5:0]      r_c = 6'b000111;
    wire [6*UW-1:0] r_all;
    genvar gr;
    generate
        for (gr = 0; gr < 6; gr = gr + 1) begin : g_cross
            reg [UW-1:0] r_q;
            reg          carry_q;
            always @(posedge clk) begin
                if (idle_q) begin
                    {carry_q, r_q[RL-1:0]} <= {1'b0, r_x[gr*UW +: RL]} + {1'b0, r_y[gr*UW +: RL]} +
                                              {{RL{1'b0}}, r_c[gr]};
                    r_q[UW-1:RL] <= r_x[gr*UW+RL +: UW-RL] + r_y[gr*UW+RL +: UW-RL] + {{(UW-RL-1){1'b0}}, carry_q};
                end
            end
            assign r_all[gr*UW +: UW] = r_q;
        end
    endgenerate
    wire [UW-1:0] r1 = r_all[0 +: UW], r2 = r_all[UW +: UW], r3 = r_all[2*UW +: UW],
                  r5 = r_all[3*UW +: UW], r6 = r_all[4*UW +: UW], r7 = r_all[5*UW +: UW];

    always @(posedge clk) begin
        if (rst) begin
            tok_q     <= 1'b0;
            fin       <= 1'b0;
            step_x    <= 1'b0;
            step_y    <= 1'b0;
            dir_x     <= 1'b0;
            dir_y     <= 1'b0;
        end else begin
            tok_q     <= go;
            fin       <= step && last;
            step_x    <= act_x;
            step_y    <= act_y;
            if (act_x) dir_x <= neg_x;
            if (act_y) dir_y <= neg_y;
        end
    end

    // |D| <= 6's first stage: D's bits above 3 all 0, all 1, in 4-bit groups (the low
    // group compares constants), and D's low bits.
    reg  [QG-1:0] hzg_u_q, hog_u_q, hzg_v_q, hog_v_q;
    reg  [QG-1:0] szg_u_q, sog_u_q, szg_v_q, sog_v_q;     // the same for End's bits above 1 (|End| <= 2)
    reg           sz_u_q, so_u_q, sz_v_q, so_v_q;         // and their ANDs
    reg  [QG-1:0] s1z_g_q, s3z_g_q, uz_g_q, vz_g_q;       // u + v = 0, v - u = 0, u = 0, v = 0 (groups of the inputs)
    reg  [3:0]    lo1_u_q, lo1_v_q;
    wire [QG-1:0] hzg_u = equal_groups({du_q[UW-1:4], 4'h0}, zero), hog_u = equal_groups({du_q[UW-1:4], 4'hf}, ~zero),
                  hzg_v = equal_groups({dv_q[UW-1:4], 4'h0}, zero), hog_v = equal_groups({dv_q[UW-1:4], 4'hf}, ~zero);

    // Data registers without reset: they follow the inputs while not running (or in reset).
    always @(posedge clk) begin
        // Registers without an enable: fewer enable nets to route.  The step vectors and
        // the next octants' tables change only with the octant, so they are valid again
        // before the decision loop's reload ends.
        td_l_q    <= td;
        // The last-step flags of the step the step stage takes next, from the window a
        // step ahead (it and the tables hold still until then).
        last_a_q <= last_a_w;
        last_d_q <= last_d_w;
        zu_q  <= wau_q[1];
        zv_q  <= wav_q[1];
        pu_q  <= wau_q[2];
        pv_q  <= wav_q[2];
        if (idle_q) begin                     // (a register in front of the window logic, not a LUT)
            dau_q <= du_q[4:0];
            dav_q <= dv_q[4:0];
            wau_q <= window(1'b0, 1'b0, eau);
            wav_q <= window(1'b0, 1'b0, eav);
        end else if (go) begin
            dau_q <= dau_w;
            dav_q <= dav_w;
            wau_q <= window(mx_f, nx_f, eau);
            wav_q <= window(my_f, ny_f, eav);
        end
        su_q  <= td ? ud_w : ua_w;
        sv_q  <= td ? vd_w : va_w;
        ua_q  <= ua_w[4:0];
        ud_q  <= ud_w[4:0];
        va_q  <= va_w[4:0];
        vd_q  <= vd_w[4:0];
        hzg_u_q <= hzg_u;
        hog_u_q <= hog_u;
        hzg_v_q <= hzg_v;
        hog_v_q <= hog_v;
        lo1_u_q <= du_q[3:0];
        lo1_v_q <= dv_q[3:0];
        hz_u_q <= &hzg_u_q;
        ho_u_q <= &hog_u_q;
        hz_v_q <= &hzg_v_q;
        ho_v_q <= &hog_v_q;
        lo_u_q <= lo1_u_q;
        lo_v_q <= lo1_v_q;
        near_u_q <= near_u_w;
        near_v_q <= near_v_w;
        lt_all_q <= lt_all;
        loaded_q <= loading;
        du0_q <= du0_w;
        dv0_q <= dv0_w;
        dot_small_q <= dot_small_w;
        szg_u_q <= equal_groups({u1_q[UW-1:2], 2'b00}, zero);
        sog_u_q <= equal_groups({u1_q[UW-1:2], 2'b11}, ~zero);
        sz_u_q  <= &szg_u_q;
        so_u_q  <= &sog_u_q;
        sz_v_q  <= &szg_v_q;
        so_v_q  <= &sog_v_q;
        szg_v_q <= equal_groups({v1_q[UW-1:2], 2'b00}, zero);
        sog_v_q <= equal_groups({v1_q[UW-1:2], 2'b11}, ~zero);
        oct1_oh_q <= one_hot(oct1);
        oct2_oh_q <= one_hot(oct2);
        lt0_q <= table_of(oct0_oh_q, lt_all_q);    // the first octant's (loading)
        lt1_q <= table_of(oct1_oh_q, lt_all_q);
        lt2_q <= table_of(oct2_oh_q, lt_all_q);
        if (idle_q || step) begin             // (after the last step u, v show End)
            du_q    <= du_next;
            dv_q    <= dv_next;
        end
        // u + v = 0 without the sum (a carry-free test: u ^ v = (u | v) << 1), v - u = 0,
        // u = 0, v = 0: 4-bit group flags of the inputs (as u_q, v_q take them), ANDed next.
        s1z_g_q <= equal_groups(u0 ^ v0, {u0[UW-2:0] | v0[UW-2:0], 1'b0});
        s3z_g_q <= equal_groups(u0, v0);
        uz_g_q  <= equal_groups(u0, zero);
        vz_g_q  <= equal_groups(v0, zero);
        // What the benches see follows the inputs from a reset on (loading); the rest from
        // the next cycle (idle_q: a register, not the reset's LUT, in front of the enables).
        if (loading) begin
            done_q  <= 1'b0;
            u_q     <= u0;
            v_q     <= v0;
            e_q     <= {NW{1'b0}};
        end else if (step) begin
            done_q  <= last;
            e_q     <= e_w;
        end
        if (idle_q) begin                     // the command's tables; the first octant, p and q
            u1_q    <= u1;
            v1_q    <= v1;
            dneg_q  <= {r7[UW-1], r6[UW-1], r5[UW-1], u1_q[UW-1], r3[UW-1], r2[UW-1], r1[UW-1], v1_q[UW-1]};
            dzero_q <= {r7 == {UW{1'b0}}, r6 == {UW{1'b0}}, r5 == {UW{1'b0}}, u1_q == {UW{1'b0}},
                        r3 == {UW{1'b0}}, r2 == {UW{1'b0}}, r1 == {UW{1'b0}}, v1_q == {UW{1'b0}}};
            small_q <= small2(sz_u_q, so_u_q, u1_q[1:0]) && small2(sz_v_q, so_v_q, v1_q[1:0]);
            pos_q   <= pos_w;
            dot_q   <= dot_w;
            s1_q    <= s1_w;
            s3_q    <= s3_w;
            uz_q    <= &uz_g_q;
            vz_q    <= &vz_g_q;
            s1z_q   <= &s1z_g_q;
            s3z_q   <= &s3z_g_q;
            oct_p_q <= oct_p;
            {xm_q, mjn_q, mnn_q} <= oct_0;
            oct0_oh_q <= one_hot(oct_0);
            pa_q    <= (xm_q ? u_q : v_q) ^ {UW{mjn_q}};
            pb_q    <= (xm_q ? v_q : u_q) ^ {UW{mnn_q}};
            qpos_l_q <= !pb_q[UW-1];            // q = P.b > 0 (never 0)
            p_q     <= p_w;                     // P.a
            q_q     <= q_w;                     // P.b
            lt_q    <= lt0_q[35:18] | lt0_q[17:0];
        end else if (reload3_q) begin
            {xm_q, mjn_q, mnn_q, qpos_l_q} <= oct_n_q;
            lt_q    <= lt_n_q;
        end
        // The new octant, in the third reload cycle (the kind, SWAP_TURN or not, is found
        // in the first, the new values registered in the second); the step stage's next
        // step comes after the reload.
        oct_n_q  <= {k_st_q ? oct2 : oct1, !qpos_l_q && !k_st_q};
        lt_n_q   <= k_st_q ? lt2_q[35:18] | lt2_q[17:0] : lt1_q[35:18] | lt1_q[17:0];
    end
endmodule
`default_nettype wire
