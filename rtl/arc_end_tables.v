// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// The end test's tables (arc_stepper, circ_arc's run loop): which step from a point near
// the end point is the last one.
//
// The arc's last step goes to the end point End when the next point P' reaches or
// passes the ray from the centre through End with dot(P', End) > 0; this happens only
// with P within one step of End.  With D = P - End and a step s:
//   last = pos(D) and not pos(D + s) and dot(End + D + s, End) > 0,
//   pos(D) = turn * cross(D, End) > 0  (turn = +1 counter-clockwise, -1 clockwise).
// Near End, D lies on the 5x5 grid -2 .. 2 per axis, whose points point in one of
// eight directions d (or the opposite ones), so pos() on the grid is given by the signs
// and zeros of cross(d, End) for the eight d: a 25-bit table of the command.  So is the
// dot test, which holds for every grid point when |End|^2 > 8 and is otherwise a
// function of End's low three bits per axis.  Per octant (its steps a and a + b) the two
// tables give 9-bit last-step tables for the axial and the diagonal step, read at D's
// window -1 .. 1 per axis (arc_end_window).
//
// While idle the command's tables follow the inputs (the cross products in two halves
// with a registered carry, then their signs; they settle within nine cycles); every
// octant's tables are then wiring, picked by a one-hot select.  The octant's tables load
// with the first octant while idle and with the new octant in a reload's third cycle
// (the new octant is the next one or, SWAP_TURN, the one after).
module arc_end_tables #(
    parameter integer WIDTH = 32            // circ_arc's coordinate width (>= 6)
) (
    input  wire           clk,
    input  wire           idle,             // not running (registered): follow the inputs
    input  wire           reload_cycle_3,   // a reload's third cycle: the new octant's tables load
    input  wire [WIDTH:0] u1,               // end point relative to the centre (signed)
    input  wire [WIDTH:0] v1,
    input  wire           ccw,              // 1 = counter-clockwise
    input  wire [2:0]     first_octant,     // {x major, a < 0, b < 0}
    input  wire [2:0]     next_octant,      // the current octant's next (turn or swap)
    input  wire [2:0]     swap_turn_octant, // and the one after it (SWAP_TURN)
    input  wire           swap_turn,        // the reload is a SWAP_TURN
    output reg  [WIDTH:0] end_u,            // End, registered while idle
    output reg  [WIDTH:0] end_v,
    output reg  [17:0]    octant_tables     // {diagonal, axial} last-step tables of the octant
);
    initial begin
        if (WIDTH < 6) $error("%m: WIDTH must be at least 6");
    end

    localparam integer UW = WIDTH + 1;
    localparam integer GROUPS = (UW + 3) / 4;

    // The eight directions d of the grid (upper half plane) and cross(d, End) = du v1 - dv u1:
    //   0 (1,0): v1      1 (2,1): 2v1 - u1   2 (1,1): v1 - u1    3 (1,2): v1 - 2u1
    //   4 (0,1): -u1     5 (-1,2): -(v1 + 2u1)  6 (-1,1): -(v1 + u1)  7 (-2,1): -(2v1 + u1)
    // Index of the direction of a grid point, + 8 when it points the other way.
    function integer direction(input integer du, dv);
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
            direction = flip + (pv == 0 ? 0 : pv == 2 ? (pu == 1 ? 3 : 5) : pu == 2 ? 1 : pu == 1 ? 2 :
                                pu == 0 ? 4 : pu == -1 ? 6 : 7);
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
    // Last-step tables for the steps a, a + b (unit vectors (au, av), (bu, bv)): bit
    // 3 (du + 1) + (dv + 1) for D in -1 .. 1 per axis, {diagonal step, axial step}.
    function automatic [17:0] tables_for(input integer au, av, bu, bv, input [24:0] positive, dot);
        integer i, j, k;
        begin
            for (i = -1; i <= 1; i = i + 1)
                for (j = -1; j <= 1; j = j + 1) begin
                    k = 3 * (i + 1) + j + 1;
                    tables_for[k] = positive[5 * (i + 2) + j + 2] && !positive[5 * (i + au + 2) + j + av + 2] &&
                                    dot[5 * (i + au + 2) + j + av + 2];
                    tables_for[9 + k] = positive[5 * (i + 2) + j + 2] &&
                                        !positive[5 * (i + au + bu + 2) + j + av + bv + 2] &&
                                        dot[5 * (i + au + bu + 2) + j + av + bv + 2];
                end
        end
    endfunction
    function automatic [7:0] one_hot(input [2:0] o);
        one_hot = 8'd1 << o;
    endfunction
    // An octant's tables by a one-hot select: two halves of four octants, each an AND-OR
    // of two LUT levels, ORed where they are taken.  {octants 4-7, octants 0-3}
    function automatic [35:0] table_of(input [7:0] select, input [8*18-1:0] all);
        integer i;
        begin
            table_of = 36'd0;
            for (i = 0; i < 8; i = i + 1)
                table_of[18 * (i / 4) +: 18] = table_of[18 * (i / 4) +: 18] | ({18{select[i]}} & all[18 * i +: 18]);
        end
    endfunction
    // |x| <= 2 from x's parts: its bits above 1 all 0 or all 1, and its low bits.
    function automatic small2(input high_zero, high_ones, input [1:0] low);
        small2 = (high_zero && low != 2'd3) || (high_ones && low[1]);
    endfunction
    function automatic [GROUPS-1:0] equal_groups(input [UW-1:0] a, b);   // per 4-bit group
        integer i;
        reg [4*GROUPS-1:0] x;
        begin
            x = {{(4*GROUPS-UW){1'b0}}, a ^ b};
            for (i = 0; i < GROUPS; i = i + 1) equal_groups[i] = x[4*i +: 4] == 4'd0;
        end
    endfunction

    reg  [7:0]        cross_negative, cross_zero;       // cross(d, End) < 0, == 0
    reg               end_small;                        // |u1|, |v1| <= 2
    reg  [24:0]       positive_grid, dot_grid;          // pos(D), dot(End + D, End) > 0 on the grid
    reg  [24:0]       small_dot_grid;                   // dot > 0 for |End|^2 <= 8
    reg  [GROUPS-1:0] end_u_high_zero_groups, end_u_high_ones_groups, end_v_high_zero_groups,
                      end_v_high_ones_groups;           // End's bits above 1 all 0, all 1 (groups)
    reg               end_u_high_zero, end_u_high_ones, end_v_high_zero, end_v_high_ones;
    reg  [8*18-1:0]   all_tables;                       // every octant's, registered
    reg  [7:0]        first_select, next_select, swap_turn_select;   // one-hot octants (a cycle old)
    reg  [35:0]       first_tables, next_tables, swap_turn_tables;   // as two halves to OR
    reg  [17:0]       new_tables;                       // the new octant's (a reload's third cycle)

    // cross(d, End) for d = 1, 2, 3, 5, 6, 7 as x + y + c (c = 1 with y = ~u1 or ~2u1), registered
    // in two halves while idle: the high half takes the low half's carry of the cycle
    // before (End holds still while idle, so they settle in two cycles).  They read a
    // copy of End of their own (without an enable, so it stays a copy: End's loads span
    // the chip).
    localparam integer HALF = UW / 2;
    reg  [UW-1:0]   end_u_copy, end_v_copy;
    always @(posedge clk) begin
        end_u_copy <= u1;
        end_v_copy <= v1;
    end
    wire [UW-1:0]   u2 = {end_u_copy[UW-2:0], 1'b0}, v2 = {end_v_copy[UW-2:0], 1'b0};
    wire [6*UW-1:0] cross_x = {v2, end_v_copy, end_v_copy, end_v_copy, end_v_copy, v2};   // 7, 6, 5, 3, 2, 1
    wire [6*UW-1:0] cross_y = {end_u_copy, end_u_copy, u2, ~u2, ~end_u_copy, ~end_u_copy};
    wire [5:0]      cross_c = 6'b000111;
    wire [6*UW-1:0] cross_all;
    genvar gr;
    generate
        for (gr = 0; gr < 6; gr = gr + 1) begin : g_cross
            reg [UW-1:0] product;
            reg          carry;
            always @(posedge clk) begin
                if (idle) begin
                    {carry, product[HALF-1:0]} <= {1'b0, cross_x[gr*UW +: HALF]} + {1'b0, cross_y[gr*UW +: HALF]} +
                                                {{HALF{1'b0}}, cross_c[gr]};
                    product[UW-1:HALF] <= cross_x[gr*UW+HALF +: UW-HALF] + cross_y[gr*UW+HALF +: UW-HALF] +
                                        {{(UW-HALF-1){1'b0}}, carry};
                end
            end
            assign cross_all[gr*UW +: UW] = product;
        end
    endgenerate
    wire [UW-1:0] cross1 = cross_all[0 +: UW], cross2 = cross_all[UW +: UW], cross3 = cross_all[2*UW +: UW],
                  cross5 = cross_all[3*UW +: UW], cross6 = cross_all[4*UW +: UW], cross7 = cross_all[5*UW +: UW];

    // turn * cross(d, End) > 0 and < 0 (directions 4 .. 7 hold -cross).
    wire [7:0] flip = {{4{ccw}}, {4{!ccw}}};
    wire [7:0] turn_positive = (cross_negative & flip) | (~cross_negative & ~cross_zero & ~flip);
    wire [7:0] turn_negative = (cross_negative & ~flip) | (~cross_negative & ~cross_zero & flip);
    wire [24:0] positive_w, dot_w, small_dot_w;
    genvar gi;
    generate
        for (gi = 0; gi < 25; gi = gi + 1) begin : g_grid        // grid point D = (gi / 5 - 2, gi % 5 - 2)
            localparam integer DU = gi / 5 - 2, DV = gi % 5 - 2;
            localparam integer DIR = (DU == 0 && DV == 0) ? 0 : direction(DU, DV);
            if (DU == 0 && DV == 0) begin : g_centre
                assign positive_w[gi] = 1'b0;
            end else if (DIR >= 8) begin : g_back
                assign positive_w[gi] = turn_negative[DIR-8];
            end else begin : g_fore
                assign positive_w[gi] = turn_positive[DIR];
            end
            // dot(End + D, End) = |End|^2 + D.End > 0: true when |End|^2 > 8 (|D| <= 2 sqrt 2),
            // else a function of End's low three bits per axis.
            localparam [63:0] DOT_SMALL = dot_table(DU, DV);
            assign small_dot_w[gi] = DOT_SMALL[{end_u[2:0], end_v[2:0]}];
            assign dot_w[gi] = !end_small || small_dot_grid[gi];
        end
    endgenerate
    // Per octant {x major, a < 0, b < 0} the tables are plain wiring of the command's
    // (continuous assignments: simulators re-evaluate them only when those change).
    wire [8*18-1:0] all_tables_w;              // octant o at bits 18 o
    genvar go;
    generate
        for (go = 0; go < 8; go = go + 1) begin : g_octant
            localparam integer XM = go / 4, MJ = go / 2 % 2, MN = go % 2;
            localparam integer AU = XM != 0 ? (MJ != 0 ? -1 : 1) : 0, AV = XM != 0 ? 0 : (MJ != 0 ? -1 : 1);
            localparam integer BU = XM != 0 ? 0 : (MN != 0 ? -1 : 1), BV = XM != 0 ? (MN != 0 ? -1 : 1) : 0;
            assign all_tables_w[18 * go +: 18] = tables_for(AU, AV, BU, BV, positive_grid, dot_grid);
        end
    endgenerate

    always @(posedge clk) begin
        small_dot_grid         <= small_dot_w;
        end_u_high_zero_groups <= equal_groups({end_u[UW-1:2], 2'b00}, {UW{1'b0}});
        end_u_high_ones_groups <= equal_groups({end_u[UW-1:2], 2'b11}, {UW{1'b1}});
        end_v_high_zero_groups <= equal_groups({end_v[UW-1:2], 2'b00}, {UW{1'b0}});
        end_v_high_ones_groups <= equal_groups({end_v[UW-1:2], 2'b11}, {UW{1'b1}});
        end_u_high_zero        <= &end_u_high_zero_groups;
        end_u_high_ones        <= &end_u_high_ones_groups;
        end_v_high_zero        <= &end_v_high_zero_groups;
        end_v_high_ones        <= &end_v_high_ones_groups;
        all_tables       <= all_tables_w;
        next_select      <= one_hot(next_octant);
        swap_turn_select <= one_hot(swap_turn_octant);
        first_tables     <= table_of(first_select, all_tables);
        next_tables      <= table_of(next_select, all_tables);
        swap_turn_tables <= table_of(swap_turn_select, all_tables);
        new_tables       <= swap_turn ? swap_turn_tables[35:18] | swap_turn_tables[17:0]
                                      : next_tables[35:18] | next_tables[17:0];
        if (idle) begin
            end_u          <= u1;
            end_v          <= v1;
            cross_negative <= {cross7[UW-1], cross6[UW-1], cross5[UW-1], end_u[UW-1], cross3[UW-1], cross2[UW-1],
                               cross1[UW-1], end_v[UW-1]};
            cross_zero     <= {cross7 == {UW{1'b0}}, cross6 == {UW{1'b0}}, cross5 == {UW{1'b0}}, end_u == {UW{1'b0}},
                               cross3 == {UW{1'b0}}, cross2 == {UW{1'b0}}, cross1 == {UW{1'b0}}, end_v == {UW{1'b0}}};
            end_small      <= small2(end_u_high_zero, end_u_high_ones, end_u[1:0]) &&
                              small2(end_v_high_zero, end_v_high_ones, end_v[1:0]);
            positive_grid  <= positive_w;
            dot_grid       <= dot_w;
            first_select   <= one_hot(first_octant);
            octant_tables  <= first_tables[35:18] | first_tables[17:0];
        end else if (reload_cycle_3) begin
            octant_tables  <= new_tables;
        end
    end
endmodule
`default_nettype wire
