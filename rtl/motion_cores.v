// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// The interpolator cores of motion_top and the choice of the running core's steps.
//   lines, 2 or 3 axes ...... line_pair u_lines: two SU 1571551 exact cores sharing the
//                             leading axis, the lecture's linear interpolator per pair
//   circular arc, helix ..... arc_plane u_arc: circ_arc (the lecture's circle with SU
//                             1665343's midpoint choice) in the plane's (u, v); the helix
//                             axis w on line core A, lent to it during the arc
//   curve ................... curve_tangent u_curve (the paper's tangent method), only
//                             with CURVES = 1
// motion_top's dispatcher starts one core at a time (start_line / start_arc /
// start_curve, from the geometry queue's head) and says which one runs (run_line /
// run_arc / run_curve, its state); every core takes the synchronization buffer's
// `tick`.  `step` and `dir` are the running core's ({z, y, x}; zero when none
// runs), `done` strobes when it ends or fails, `error` when an arc or curve core
// refused its command (an inconsistent centre: motion_top's fault).
// line_pair takes its command a cycle ahead (next_*: the queue's head, or while the
// queue is empty the command being pushed); the arc and curve cores load the head's
// fields at their start.
module motion_cores #(
    parameter integer W      = 16,  // command field width, signed (>= 6)
    parameter integer CURVES = 1    // 1: curve_tangent present; 0: left out (start_curve never rises)
) (
    input  wire         clk,
    input  wire         rst,
    input  wire         tick,           // ~STOP of the synchronization buffer
    // line_pair's look-ahead: the command a start in the next cycle loads
    input  wire [W-1:0] next_x,
    input  wire [W-1:0] next_y,
    input  wire [W-1:0] next_z,
    input  wire         next_arc,       // ... is an arc (line core A spreads its helix)
    input  wire [W-1:0] next_count,     // ... an arc's N
    // the head's command, for the arc and curve cores
    input  wire [1:0]   plane,          // 0 XY, 1 ZX, 2 YZ
    input  wire         ccw,
    input  wire [W-1:0] cmd_x,          // arc: end u; curve: the ΔX constant
    input  wire [W-1:0] cmd_y,          // arc: end v; curve: the ΔY constant
    input  wire [W-1:0] cmd_z,          // arc: helix travel; curve: steps
    input  wire [W-1:0] cmd_i,          // arc: centre u; curve: dΔX/dx
    input  wire [W-1:0] cmd_j,          // arc: centre v; curve: dΔX/dy
    input  wire [W-1:0] cmd_k,          // curve: dΔY/dx
    input  wire [W-1:0] cmd_l,          // curve: dΔY/dy
    input  wire         start_line,
    input  wire         start_arc,
    input  wire         start_curve,
    input  wire         run_line,       // the core that runs (motion_top's state)
    input  wire         run_arc,
    input  wire         run_curve,
    output reg  [2:0]   step,           // {z, y, x}
    output reg  [2:0]   dir,            // 1 = negative
    output wire         done,           // the running core ended (or failed)
    output wire         error           // the running arc or curve core refused its command
);
    initial begin
        if (W < 6) $error("%m: W must be at least 6");
        if (CURVES < 0 || CURVES > 1) $error("%m: CURVES must be 0 or 1");
    end

    localparam integer CPW = W + 8;         // curve projection width

    // Line core A also spreads an arc's helix axis (arc_plane borrows it).
    wire [2:0] line_step, line_dir;
    wire       line_done, helix_start, helix_tick, helix_abort, helix_step, helix_dir;
    line_pair #(.W(W)) u_lines (
        .clk(clk), .rst(rst), .start(start_line), .tick(tick),
        .next_x(next_x), .next_y(next_y), .next_z(next_z), .next_arc(next_arc), .next_count(next_count),
        .step(line_step), .dir(line_dir), .done(line_done),
        .helix_start(helix_start), .lent(run_arc), .helix_tick(helix_tick),
        .helix_abort(helix_abort), .helix_step(helix_step), .helix_dir(helix_dir)
    );

    wire [2:0] arc_step, arc_dir;
    wire       arc_busy, arc_done, arc_error;
    arc_plane #(.W(W)) u_arc (
        .clk(clk), .rst(rst), .start(start_arc), .tick(tick), .plane(plane),
        .ccw(ccw), .end_u(cmd_x), .end_v(cmd_y), .centre_u(cmd_i), .centre_v(cmd_j),
        .travel(cmd_z),
        .helix_start(helix_start), .helix_tick(helix_tick),
        .helix_abort(helix_abort), .helix_step(helix_step), .helix_dir(helix_dir),
        .step(arc_step), .dir(arc_dir), .busy(arc_busy), .done(arc_done), .error(arc_error)
    );

    wire cv_sx, cv_sy, cv_dx, cv_dy, cv_busy, cv_done, cv_error;
    generate
        if (CURVES != 0) begin : g_curve
            curve_tangent #(.WIDTH(W), .PW(CPW), .CW(W)) u_curve (
                .clk(clk), .rst(rst), .start(start_curve), .tick(tick),
                .x0({W{1'b0}}), .y0({W{1'b0}}),
                .p0({{8{cmd_x[W-1]}}, cmd_x}), .q0({{8{cmd_y[W-1]}}, cmd_y}),
                .dp_dx({{8{cmd_i[W-1]}}, cmd_i}), .dp_dy({{8{cmd_j[W-1]}}, cmd_j}),
                .dq_dx({{8{cmd_k[W-1]}}, cmd_k}), .dq_dy({{8{cmd_l[W-1]}}, cmd_l}),
                .reverse(1'b0), .count(cmd_z), .end_sel(2'd0), .end_coord({W{1'b0}}), .improved(1'b0),
                .e_load(1'b0), .e_init({(CPW+4){1'b0}}),
                .step_x(cv_sx), .step_y(cv_sy), .dir_x(cv_dx), .dir_y(cv_dy),
                .busy(cv_busy), .done(cv_done), .error(cv_error)
            );
        end else begin : g_no_curve     // motion_top refuses kind 3 at the push: never started
            assign {cv_sx, cv_sy, cv_dx, cv_dy, cv_busy, cv_done, cv_error} = 7'd0;
            wire unused_curve = &{1'b0, start_curve, cmd_k, cmd_l};
        end
    endgenerate

    // The running core's steps (the others are idle and show no step).
    always @* begin
        if (run_arc) begin
            step = arc_step;
            dir  = arc_dir;
        end else if (run_curve) begin
            step = {1'b0, cv_sy, cv_sx};
            dir  = {1'b0, cv_dy, cv_dx};
        end else if (run_line) begin
            step = line_step;
            dir  = line_dir;
        end else begin
            step = 3'b000;
            dir  = 3'b000;
        end
    end
    assign done  = (run_line & line_done) | (run_arc & (arc_done | arc_error)) |
                   (run_curve & (cv_done | cv_error));
    assign error = (run_arc & arc_error) | (run_curve & cv_error);

    wire unused = &{1'b0, arc_busy, cv_busy};
endmodule
`default_nettype wire
