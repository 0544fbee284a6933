// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// The start point's octant and its midpoint counters p and q (arc_stepper, circ_arc's
// run loop; the lecture's accelerated circular interpolator: a leading axis per octant).
//
// The arc runs octant by octant.  In an octant the leading (major) step a is along the
// axis in which the tangent is larger, the minor step b along the other, each with the
// tangent's sign, so that every step is a or a + b.  For the start point P = (u, v)
// (relative to the centre) the tangent is (-v, u) counter-clockwise, (v, -u) clockwise:
//   x major  <=>  |v| > |u|  <=>  (v + u)(v - u) > 0;
// on a diagonal (|u| = |v|, v + u = 0 or v - u = 0) the leading axis is the one of the
// octant the arc enters next, and a zero minor component steps inwards.  The loop then
// needs p = P.a and q = P.b (the projections of P on the unit steps).
//
// While the stepper is idle (`idle`, registered) everything here follows the inputs:
// the start point registers from `loading` (idle or reset) on, the zero flags of
// u, v, u + v and v - u in two stages (4-bit groups, then their AND), the octant in
// two (both versions of the signs, then the select), p and q in two more; all settle
// within the stepper's nine idle cycles.  The octant's flags are registered here a
// second time (the stepper's own copy follows the reloads), for p and q.
module arc_octant #(
    parameter integer WIDTH = 32            // circ_arc's coordinate width (>= 6)
) (
    input  wire           clk,
    input  wire           idle,             // not running (registered): follow the inputs
    input  wire           loading,          // idle or reset: the start point follows u0, v0
    input  wire [WIDTH:0] u0,               // start point relative to the centre (signed)
    input  wire [WIDTH:0] v0,
    input  wire           ccw,              // 1 = counter-clockwise
    output reg  [WIDTH:0] start_u,          // the start point, registered
    output reg  [WIDTH:0] start_v,
    output wire [2:0]     first_octant,     // {x major, a < 0, b < 0} of the start point
    output reg  [WIDTH:0] start_p,          // P.a
    output reg  [WIDTH:0] start_q,          // P.b (never 0)
    output wire           start_q_negative  // q < 0, a cycle before start_q
);
    initial begin
        if (WIDTH < 6) $error("%m: WIDTH must be at least 6");
    end

    localparam integer UW = WIDTH + 1;      // coordinates, p and q
    localparam integer GROUPS = (UW + 3) / 4;

    function automatic [GROUPS-1:0] equal_groups(input [UW-1:0] a, b);   // per 4-bit group
        integer i;
        reg [4*GROUPS-1:0] x;
        begin
            x = {{(4*GROUPS-UW){1'b0}}, a ^ b};
            for (i = 0; i < GROUPS; i = i + 1) equal_groups[i] = x[4*i +: 4] == 4'd0;
        end
    endfunction
    // {x major; a < 0, b < 0 if x major; a < 0, b < 0 if not}
    function automatic [4:0] octant(input u_negative, u_zero, v_negative, v_zero, sum_negative, sum_zero,
                                    difference_negative, difference_zero, counter_clockwise);
        reg x_major, u_positive, v_positive;
        begin
            x_major = (!sum_zero && !difference_zero && sum_negative == difference_negative) ||
                      ((sum_zero || difference_zero) && ((u_negative == v_negative) == counter_clockwise));
            u_positive = !u_negative && !u_zero;
            v_positive = !v_negative && !v_zero;
            // Tangent (-v, u) for CCW, (v, -u) for CW; a zero minor component steps inwards.
            octant = {x_major, counter_clockwise ? v_positive : v_negative,
                      u_zero ? v_positive : (counter_clockwise ? u_negative : u_positive),
                      counter_clockwise ? u_negative : u_positive,
                      v_zero ? u_positive : (counter_clockwise ? v_positive : v_negative)};
        end
    endfunction

    reg  [UW-1:0]     start_sum, start_difference;      // u + v, v - u
    reg  [GROUPS-1:0] sum_zero_groups, difference_zero_groups, u_zero_groups, v_zero_groups;
    reg               sum_zero, difference_zero, u_zero, v_zero;
    reg  [4:0]        octant_both;                      // octant(): both versions of the signs
    reg  [2:0]        octant_flags;                     // first_octant, registered
    reg  [UW-1:0]     p_uncorrected, q_uncorrected;     // P.a, P.b less the + 1 of a negation

    wire [UW-1:0] sum_w, difference_w, p_w, q_w;
    wire [3:0]    unused_carries;
    chain_add #(.WIDTH(UW)) u_sum_add (
        .a(start_u), .b(start_v), .cin(1'b0), .sum(sum_w), .cout(unused_carries[0]));
    chain_add #(.WIDTH(UW), .SUBTRACT(1)) u_difference_add (
        .a(start_v), .b(start_u), .cin(1'b1), .sum(difference_w), .cout(unused_carries[1]));
    chain_add #(.WIDTH(UW)) u_p_add (
        .a(p_uncorrected), .b({UW{1'b0}}), .cin(octant_flags[1]), .sum(p_w), .cout(unused_carries[2]));
    chain_add #(.WIDTH(UW)) u_q_add (
        .a(q_uncorrected), .b({UW{1'b0}}), .cin(octant_flags[0]), .sum(q_w), .cout(unused_carries[3]));

    wire [4:0] octant_w = octant(start_u[UW-1], u_zero, start_v[UW-1], v_zero, start_sum[UW-1], sum_zero,
                                 start_difference[UW-1], difference_zero, ccw);
    assign first_octant = {octant_both[4], octant_both[4] ? octant_both[3:2] : octant_both[1:0]};
    assign start_q_negative = q_uncorrected[UW-1];

    always @(posedge clk) begin
        // u + v = 0 without the sum (a carry-free test: u ^ v = (u | v) << 1), v - u = 0,
        // u = 0, v = 0: 4-bit group flags of the inputs (as start_u, start_v take them).
        sum_zero_groups        <= equal_groups(u0 ^ v0, {u0[UW-2:0] | v0[UW-2:0], 1'b0});
        difference_zero_groups <= equal_groups(u0, v0);
        u_zero_groups          <= equal_groups(u0, {UW{1'b0}});
        v_zero_groups          <= equal_groups(v0, {UW{1'b0}});
        if (loading) begin
            start_u <= u0;
            start_v <= v0;
        end
        if (idle) begin
            start_sum        <= sum_w;
            start_difference <= difference_w;
            u_zero           <= &u_zero_groups;
            v_zero           <= &v_zero_groups;
            sum_zero         <= &sum_zero_groups;
            difference_zero  <= &difference_zero_groups;
            octant_both      <= octant_w;
            octant_flags     <= first_octant;
            p_uncorrected    <= (octant_flags[2] ? start_u : start_v) ^ {UW{octant_flags[1]}};
            q_uncorrected    <= (octant_flags[2] ? start_v : start_u) ^ {UW{octant_flags[0]}};
            start_p          <= p_w;
            start_q          <= q_w;
        end
    end

    wire unused = &{1'b0, unused_carries};
endmodule
`default_nettype wire
