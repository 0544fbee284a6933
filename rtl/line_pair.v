// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Lines on 2 or 3 axes for motion_top: two SU 1571551 exact cores (lin_exact) that
// share the leading axis, the lecture's linear interpolator per pair of axes:
//   leading axis ........... the longest of |x|, |y|, |z| (x first on ties): lead_q
//   core A (u_line_a) ...... (lead, minor 1); x leads: minors (y, z), y: (x, z), z: (x, y)
//   core B (u_line_b) ...... (lead, minor 2)
// Both get every tick, so each lead step is one tick and one step entry; the
// step strobes come a cycle after the tick (lin_exact's timing), mapped to the
// machine axes {z, y, x}.  `done` is core A's (both end on the same tick).
//
// Core A is lent to the arc path for a helix (arc_plane): with `helix_select`
// at the start it loads (helix_lead, helix_travel) instead of the line; while
// `lent` it takes `helix_tick` instead of `tick`; `helix_abort` returns it to
// idle; its minor step and direction are `helix_step`, `helix_dir`.  `step`
// shows only a line's steps (lead_q is the line's), so motion_top reads it
// only while a line runs.
module line_pair #(
    parameter integer W = 16    // width of the signed moves (>= 2)
) (
    input  wire         clk,
    input  wire         rst,
    input  wire         start,          // load the line (x, y, z)
    input  wire         tick,           // ~STOP of the synchronization buffer
    input  wire [W-1:0] x,              // the move, signed; -2^(W-1) not allowed
    input  wire [W-1:0] y,
    input  wire [W-1:0] z,
    output reg  [2:0]   step,           // {z, y, x}
    output reg  [2:0]   dir,            // 1 = negative
    output wire         done,
    // core A lent to the arc path
    input  wire         helix_select,   // the command at the start is an arc
    input  wire         helix_start,
    input  wire [W-1:0] helix_lead,
    input  wire [W-1:0] helix_travel,
    input  wire         lent,
    input  wire         helix_tick,
    input  wire         helix_abort,
    output wire         helix_step,
    output wire         helix_dir
);
    initial begin
        if (W < 2) $error("%m: W must be at least 2");
    end

    reg  [1:0] lead_q;          // leading axis 0 x, 1 y, 2 z
    reg        lead_neg_q;
    wire [W-1:0] ax = x[W-1] ? -x : x;
    wire [W-1:0] ay = y[W-1] ? -y : y;
    wire [W-1:0] az = z[W-1] ? -z : z;
    wire [1:0]   lead = (ax >= ay && ax >= az) ? 2'd0 : (ay >= az) ? 2'd1 : 2'd2;
    wire [W-1:0] lead_len = lead == 2'd0 ? ax : lead == 2'd1 ? ay : az;
    wire         lead_neg = lead == 2'd0 ? x[W-1] : lead == 2'd1 ? y[W-1] : z[W-1];
    wire [W-1:0] minor1 = lead == 2'd0 ? y : x;
    wire [W-1:0] minor2 = lead == 2'd2 ? y : z;

    wire a_sx, a_sy, a_dx, a_dy, a_busy;
    wire b_sx, b_sy, b_dx, b_dy, b_busy, b_done;
    lin_exact #(.WIDTH(W)) u_line_a (
        .clk(clk), .rst(rst | helix_abort), .start(start | helix_start),
        .tick(lent ? helix_tick : tick),
        .x(helix_select ? helix_lead : lead_len), .y(helix_select ? helix_travel : minor1),
        .step_x(a_sx), .step_y(a_sy), .dir_x(a_dx), .dir_y(a_dy), .busy(a_busy), .done(done)
    );
    lin_exact #(.WIDTH(W)) u_line_b (
        .clk(clk), .rst(rst), .start(start), .tick(tick), .x(lead_len), .y(minor2),
        .step_x(b_sx), .step_y(b_sy), .dir_x(b_dx), .dir_y(b_dy), .busy(b_busy), .done(b_done)
    );
    assign helix_step = a_sy;
    assign helix_dir  = a_dy;

    always @* begin
        case (lead_q)
            2'd0: begin
                step = {b_sy, a_sy, a_sx};
                dir  = {b_dy, a_dy, lead_neg_q};
            end
            2'd1: begin
                step = {b_sy, a_sx, a_sy};
                dir  = {b_dy, lead_neg_q, a_dy};
            end
            default: begin
                step = {a_sx, b_sy, a_sy};
                dir  = {lead_neg_q, b_dy, a_dy};
            end
        endcase
    end

    always @(posedge clk) begin
        if (rst) begin
            lead_q     <= 2'd0;
            lead_neg_q <= 1'b0;
        end else if (start) begin
            lead_q     <= lead;
            lead_neg_q <= lead_neg;
        end
    end

    wire unused = &{1'b0, a_dx, a_busy, b_sx, b_dx, b_busy, b_done};
endmodule
`default_nettype wire
