// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Run loop of the production arc core circ_arc: the steps of an arc from its start point
// to its end point, one per `tick`, in octant-local counters, so that a step is a
// handful of register + register sums and every decision reads registers.
//
// The algorithm: the lecture's accelerated circular interpolator (a leading axis per
// octant; every step is the axial step a or the diagonal a + b) with the midpoint choice
// of the patent SU 1665343 in all eight octants, and an end test that makes the last
// step go to the end point.  The parts:
//   arc_octant      the start point's octant, p = P.a and q = P.b;
//   arc_loop        the decision loop: T, p + 1, p + q + 2, the octant's end, the reloads;
//   arc_reload      the load values of a new octant (or of the start point);
//   arc_step_stage  a cycle behind: the point (as D = P - End), the octant, the outputs;
//   arc_end_tables  the end test's tables of the command, per octant;
//   arc_end_window  the end test's lookup, a step ahead, with the decision loop.
//
// Timing: `run` is registered: the stepper follows it from the next cycle, loading the
// loop in three cycles (reload cycles 4 to 6).  While not running the registers follow
// the inputs; they settle within 9 cycles.  Running, the loop decides one step per
// `tick` and the step's strobes and dir levels come out a cycle later (registered
// together), plus six reload cycles after each step into a new octant, which take no
// step (`tick` is an enable); `fin` comes with the last step's strobes.  The benches
// read the point and E inside: u_step_stage.position_u, position_v, e_value.
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
    output wire             step_x,
    output wire             step_y,
    output wire             dir_x,  // 1 = negative direction
    output wire             dir_y,
    output wire             fin     // the last step's strobes are out
);
    initial begin
        if (WIDTH < 6) $error("%m: WIDTH must be at least 6");
    end

    // The decision loop and its reloads.
    wire             go, diagonal, idle, q_positive, t_low_operand, new_q_negative, swap_turn;
    wire [5:1]       reload_cycle;
    wire [WIDTH+1:0] t_value, e_next;
    wire [WIDTH:0]   p_plus_1, p_plus_q_plus_2, p_plus_1_load, axial_increment;
    // The start point, its octant, p and q; End.
    wire [WIDTH:0]   start_u, start_v, start_p, start_q, end_u, end_v;
    wire [2:0]       first_octant;
    wire             start_q_negative;
    // The step stage and the end test.
    wire             step_token, diagonal_token, x_major, major_negative, minor_negative;
    wire [2:0]       next_octant, swap_turn_octant;
    wire [WIDTH:0]   offset_u, offset_v;
    wire [17:0]      octant_tables;
    wire             axial_last, diagonal_last, offset_u_zero, offset_v_zero, offset_u_one, offset_v_one;

    arc_loop #(.WIDTH(WIDTH)) u_loop (
        .clk(clk), .rst(rst), .run(run), .tick(tick), .step_token(step_token), .diagonal_token(diagonal_token),
        .p_plus_1_load(p_plus_1_load), .axial_increment(axial_increment), .t_low_operand(t_low_operand),
        .new_q_negative(new_q_negative), .go(go), .diagonal(diagonal), .idle(idle), .reload_cycle(reload_cycle),
        .t_value(t_value), .p_plus_1(p_plus_1), .p_plus_q_plus_2(p_plus_q_plus_2), .q_positive(q_positive),
        .e_next(e_next));

    arc_reload #(.WIDTH(WIDTH)) u_reload (
        .clk(clk), .idle(idle), .reload_cycle_1(reload_cycle[1]), .reload_cycle_3(reload_cycle[3]),
        .reload_cycle_4(reload_cycle[4]), .reload_cycle_5(reload_cycle[5]), .diagonal_token(diagonal_token),
        .q_positive(q_positive), .t_value(t_value), .p_plus_1(p_plus_1), .p_plus_q_plus_2(p_plus_q_plus_2),
        .start_p(start_p), .start_q(start_q), .start_q_negative(start_q_negative),
        .p_plus_1_load(p_plus_1_load), .axial_increment(axial_increment), .t_low_operand(t_low_operand),
        .new_q_negative(new_q_negative), .kind_swap_turn(swap_turn));

    arc_octant #(.WIDTH(WIDTH)) u_octant (
        .clk(clk), .idle(idle), .loading(idle || rst), .u0(u0), .v0(v0), .ccw(ccw),
        .start_u(start_u), .start_v(start_v), .first_octant(first_octant), .start_p(start_p),
        .start_q(start_q), .start_q_negative(start_q_negative));

    arc_step_stage #(.WIDTH(WIDTH)) u_step_stage (
        .clk(clk), .rst(rst), .idle(idle), .go(go), .diagonal(diagonal), .reload_cycle_3(reload_cycle[3]),
        .swap_turn(swap_turn), .first_octant(first_octant), .start_q_negative(start_q_negative),
        .start_u(start_u), .start_v(start_v), .end_u(end_u), .end_v(end_v),
        .axial_last(axial_last), .diagonal_last(diagonal_last), .offset_u_zero(offset_u_zero),
        .offset_v_zero(offset_v_zero), .offset_u_one(offset_u_one), .offset_v_one(offset_v_one),
        .e_next(e_next), .step_token(step_token), .diagonal_token(diagonal_token), .x_major(x_major),
        .major_negative(major_negative), .minor_negative(minor_negative), .next_octant(next_octant),
        .swap_turn_octant(swap_turn_octant), .offset_u(offset_u), .offset_v(offset_v),
        .step_x(step_x), .step_y(step_y), .dir_x(dir_x), .dir_y(dir_y), .fin(fin));

    arc_end_tables #(.WIDTH(WIDTH)) u_end_tables (
        .clk(clk), .idle(idle), .reload_cycle_3(reload_cycle[3]), .u1(u1), .v1(v1), .ccw(ccw),
        .first_octant(first_octant), .next_octant(next_octant), .swap_turn_octant(swap_turn_octant),
        .swap_turn(swap_turn), .end_u(end_u), .end_v(end_v), .octant_tables(octant_tables));

    arc_end_window #(.WIDTH(WIDTH)) u_end_window (
        .clk(clk), .idle(idle), .go(go), .diagonal(diagonal), .x_major(x_major),
        .major_negative(major_negative), .minor_negative(minor_negative), .offset_u(offset_u),
        .offset_v(offset_v), .octant_tables(octant_tables), .axial_last(axial_last),
        .diagonal_last(diagonal_last), .offset_u_zero(offset_u_zero), .offset_v_zero(offset_v_zero),
        .offset_u_one(offset_u_one), .offset_v_one(offset_v_one));

    wire unused = &{1'b0, reload_cycle[2]};
endmodule
`default_nettype wire
