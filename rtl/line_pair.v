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
// The command is taken a cycle ahead: next_* show, in every cycle, the command a
// `start` (or `helix_start`) in the NEXT cycle loads (motion_top: the queue's
// head, or the command pushed into an empty queue), and the leading axis, the
// magnitudes and the cores' operands are chosen from them into registers
// (lead_next_q, a_x_q .. b_y_q).  The cores then load registers, so the choice
// is not in series with their start logic; outputs are as if the cores loaded
// next_* of the cycle before `start`.
//
// Core A is lent to the arc path for a helix (arc_plane): for an arc (next_arc)
// it loads (N, the helix travel next_z), N = next_count or 0 for N <= 0, at
// `helix_start`; while `lent` it takes `helix_tick` instead of `tick`;
// `helix_abort` returns it to idle; its minor step and direction are
// `helix_step`, `helix_dir`.  `step` shows only a line's steps (lead_q is the
// line's), so motion_cores reads it only while a line runs.
module line_pair #(
    parameter integer W = 16    // width of the signed moves (>= 2)
) (
    input  wire         clk,
    input  wire         rst,
    input  wire         start,          // load the line (next_x, next_y, next_z of the cycle before)
    input  wire         tick,           // ~STOP of the synchronization buffer
    input  wire [W-1:0] next_x,         // the next command's move, signed; -2^(W-1) not allowed
    input  wire [W-1:0] next_y,
    input  wire [W-1:0] next_z,         // (an arc's: its helix travel)
    input  wire         next_arc,       // the next command is an arc
    input  wire [W-1:0] next_count,     // an arc's N (signed)
    output reg  [2:0]   step,           // {z, y, x}
    output reg  [2:0]   dir,            // 1 = negative
    output wire         done,
    // core A lent to the arc path
    input  wire         helix_start,
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
    wire [W-1:0] ax = next_x[W-1] ? -next_x : next_x;
    wire [W-1:0] ay = next_y[W-1] ? -next_y : next_y;
    wire [W-1:0] az = next_z[W-1] ? -next_z : next_z;
    wire [1:0]   lead = (ax >= ay && ax >= az) ? 2'd0 : (ay >= az) ? 2'd1 : 2'd2;
    wire [W-1:0] lead_len = lead == 2'd0 ? ax : lead == 2'd1 ? ay : az;
    wire         lead_neg = lead == 2'd0 ? next_x[W-1] : lead == 2'd1 ? next_y[W-1] : next_z[W-1];
    wire [W-1:0] minor1 = lead == 2'd0 ? next_y : next_x;
    wire [W-1:0] minor2 = lead == 2'd2 ? next_y : next_z;
    wire [W-1:0] helix_lead = next_count[W-1] ? {W{1'b0}} : next_count;

    // the operands a start in this cycle loads
    reg  [1:0]   lead_next_q;
    reg          lead_neg_next_q;
    reg  [W-1:0] a_x_q, a_y_q, b_x_q, b_y_q;
    always @(posedge clk) begin
        if (rst) begin
            lead_next_q     <= 2'd0;
            lead_neg_next_q <= 1'b0;
            a_x_q           <= {W{1'b0}};
            a_y_q           <= {W{1'b0}};
            b_x_q           <= {W{1'b0}};
            b_y_q           <= {W{1'b0}};
        end else begin
            lead_next_q     <= lead;
            lead_neg_next_q <= lead_neg;
            a_x_q           <= next_arc ? helix_lead : lead_len;
            a_y_q           <= next_arc ? next_z : minor1;
            b_x_q           <= lead_len;
            b_y_q           <= minor2;
        end
    end

    wire a_sx, a_sy, a_dx, a_dy, a_busy;
    wire b_sx, b_sy, b_dx, b_dy, b_busy, b_done;
    lin_exact #(.WIDTH(W)) u_line_a (
        .clk(clk), .rst(rst | helix_abort), .start(start | helix_start),
        .tick(lent ? helix_tick : tick),
        .x(a_x_q), .y(a_y_q),
        .step_x(a_sx), .step_y(a_sy), .dir_x(a_dx), .dir_y(a_dy), .busy(a_busy), .done(done)
    );
    lin_exact #(.WIDTH(W)) u_line_b (
        .clk(clk), .rst(rst), .start(start), .tick(tick), .x(b_x_q), .y(b_y_q),
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
            lead_q     <= lead_next_q;
            lead_neg_q <= lead_neg_next_q;
        end
    end

    wire unused = &{1'b0, a_dx, a_busy, b_sx, b_dx, b_busy, b_done};
endmodule
`default_nettype wire
