// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// The end test's lookup (arc_stepper, circ_arc's run loop): is the step the step stage
// takes next the last one?  (arc_end_tables explains the test and builds its tables.)
//
// The tables are read at D's window: D = P - End in -1 .. 1 per axis, one-hot per axis
// (or none: D is farther away).  The window runs a step ahead, with the decision loop:
// D's low five bits move by the step vectors of the loop's decision, and a |D| <= 6 flag
// four steps old (D moves by at most 1 per step, so D is then within -10 .. 10 and its
// low five bits tell D = -2 .. 2 without a wide compare) gives D's values -2 .. 2, from
// which the window of D + s (s the decided step) is a select.  So the last-step flags
// are a registered lookup of a registered window in registered tables.  While idle the
// window follows D's load value.
module arc_end_window #(
    parameter integer WIDTH = 32            // circ_arc's coordinate width (>= 6)
) (
    input  wire           clk,
    input  wire           idle,             // not running (registered): follow D
    input  wire           go,               // the loop decides a step in this cycle
    input  wire           diagonal,         // and it is diagonal
    input  wire           x_major,          // the octant: x major, a < 0, b < 0
    input  wire           major_negative,
    input  wire           minor_negative,
    input  wire [WIDTH:0] offset_u,         // D = P - End (the step stage's)
    input  wire [WIDTH:0] offset_v,
    input  wire [17:0]    octant_tables,    // {diagonal, axial} last-step tables
    output reg            axial_last,       // the axial / diagonal step the step stage takes next is the last
    output reg            diagonal_last,
    output reg            offset_u_zero,    // D = 0, D = 1 per axis at that step
    output reg            offset_v_zero,
    output reg            offset_u_one,
    output reg            offset_v_one
);
    initial begin
        if (WIDTH < 6) $error("%m: WIDTH must be at least 6");
    end

    localparam integer UW = WIDTH + 1;
    localparam integer GROUPS = (UW + 3) / 4;

    function automatic [GROUPS-1:0] equal_groups(input [UW-1:0] a, b);   // per 4-bit group
        integer i;
        reg [4*GROUPS-1:0] x;
        begin
            x = {{(4*GROUPS-UW){1'b0}}, a ^ b};
            for (i = 0; i < GROUPS; i = i + 1) equal_groups[i] = x[4*i +: 4] == 4'd0;
        end
    endfunction
    // x == k for k = -2 .. 2 (bit k + 2), from x's low five bits and |x| <= 6 four steps ago.
    function automatic [4:0] near_equal(input near, input [4:0] x);
        integer k;
        begin
            for (k = -2; k <= 2; k = k + 1)
                near_equal[k+2] = near && x == k[4:0];
        end
    endfunction
    function automatic near6(input high_zero, high_ones, input [3:0] low);    // -6 <= x <= 6 from x's parts
        near6 = (high_zero && low <= 4'd6) || (high_ones && low >= 4'd10);
    endfunction
    // The window -1 .. 1 of x + s (s = -1, 0, +1: move, negative) from the flags x == -2 .. 2.
    function automatic [2:0] window(input move, negative, input [4:0] equal);
        window = !move ? equal[3:1] : negative ? equal[4:2] : equal[2:0];
    endfunction
    // OR over the 3x3 grid of window AND table (the window: one-hot per axis, or none).
    function automatic hit(input [2:0] window_u, window_v, input [8:0] table_bits);
        hit = |({{3{window_u[2]}}, {3{window_u[1]}}, {3{window_u[0]}}} & {3{window_v}} & table_bits);
    endfunction
    function automatic [4:0] unit(input move, negative);      // -1, 0, +1
        unit = {{4{move && negative}}, move};
    endfunction

    reg  [4:0]        ahead_u, ahead_v;         // D's low bits at the next step the step stage takes
    reg  [2:0]        window_u, window_v;       // and its window
    reg  [4:0]        axial_u, diagonal_u, axial_v, diagonal_v;   // the octant's step vectors' low bits
    reg  [GROUPS-1:0] high_zero_groups_u, high_ones_groups_u, high_zero_groups_v, high_ones_groups_v;
    reg  [3:0]        low_bits_1_u, low_bits_1_v;
    reg               high_zero_u, high_ones_u, high_zero_v, high_ones_v;   // D's bits above 3 all 0, all 1
    reg  [3:0]        low_bits_u, low_bits_v;   // and D's low bits
    reg               near_u, near_v;           // |D| <= 6 per axis, three cycles ago

    // The axial step a, the diagonal step a + b: x, y negative.
    wire x_axial_negative = major_negative, x_diagonal_negative = x_major ? major_negative : minor_negative;
    wire y_axial_negative = major_negative, y_diagonal_negative = x_major ? minor_negative : major_negative;
    wire move_x = diagonal || x_major, move_y = diagonal || !x_major;
    wire x_negative = diagonal ? x_diagonal_negative : x_axial_negative;
    wire y_negative = diagonal ? y_diagonal_negative : y_axial_negative;
    // Inputs of the registers that take a new value every cycle, as continuous assignments
    // (simulators evaluate the functions only when their inputs change).
    wire [4:0] equal_u = near_equal(near_u, ahead_u), equal_v = near_equal(near_v, ahead_v);
    wire       axial_last_w = hit(window_u, window_v, octant_tables[8:0]);
    wire       diagonal_last_w = hit(window_u, window_v, octant_tables[17:9]);
    wire [4:0] ahead_u_axial = ahead_u + axial_u, ahead_u_diagonal = ahead_u + diagonal_u;
    wire [4:0] ahead_v_axial = ahead_v + axial_v, ahead_v_diagonal = ahead_v + diagonal_v;
    wire       near_u_w = near6(high_zero_u, high_ones_u, low_bits_u);
    wire       near_v_w = near6(high_zero_v, high_ones_v, low_bits_v);
    wire [GROUPS-1:0] high_zero_u_w = equal_groups({offset_u[UW-1:4], 4'h0}, {UW{1'b0}});
    wire [GROUPS-1:0] high_ones_u_w = equal_groups({offset_u[UW-1:4], 4'hf}, {UW{1'b1}});
    wire [GROUPS-1:0] high_zero_v_w = equal_groups({offset_v[UW-1:4], 4'h0}, {UW{1'b0}});
    wire [GROUPS-1:0] high_ones_v_w = equal_groups({offset_v[UW-1:4], 4'hf}, {UW{1'b1}});

    always @(posedge clk) begin
        axial_last    <= axial_last_w;
        diagonal_last <= diagonal_last_w;
        offset_u_zero <= window_u[1];
        offset_v_zero <= window_v[1];
        offset_u_one  <= window_u[2];
        offset_v_one  <= window_v[2];
        if (idle) begin                     // (a register in front of the window logic, not a LUT)
            ahead_u  <= offset_u[4:0];
            ahead_v  <= offset_v[4:0];
            window_u <= window(1'b0, 1'b0, equal_u);
            window_v <= window(1'b0, 1'b0, equal_v);
        end else if (go) begin              // (the decision after the sums)
            ahead_u  <= diagonal ? ahead_u_diagonal : ahead_u_axial;
            ahead_v  <= diagonal ? ahead_v_diagonal : ahead_v_axial;
            window_u <= window(move_x, x_negative, equal_u);
            window_v <= window(move_y, y_negative, equal_v);
        end
        axial_u    <= unit(x_major, x_axial_negative);
        diagonal_u <= unit(1'b1, x_diagonal_negative);
        axial_v    <= unit(!x_major, y_axial_negative);
        diagonal_v <= unit(1'b1, y_diagonal_negative);
        high_zero_groups_u <= high_zero_u_w;
        high_ones_groups_u <= high_ones_u_w;
        high_zero_groups_v <= high_zero_v_w;
        high_ones_groups_v <= high_ones_v_w;
        low_bits_1_u <= offset_u[3:0];
        low_bits_1_v <= offset_v[3:0];
        high_zero_u  <= &high_zero_groups_u;
        high_ones_u  <= &high_ones_groups_u;
        high_zero_v  <= &high_zero_groups_v;
        high_ones_v  <= &high_ones_groups_v;
        low_bits_u   <= low_bits_1_u;
        low_bits_v   <= low_bits_1_v;
        near_u       <= near_u_w;
        near_v       <= near_v_w;
    end
endmodule
`default_nettype wire
