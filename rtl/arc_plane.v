// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Arc in a chosen plane, with a helix: motion_top's arc path.
//   circular arc ........... circ_arc u_arc, in the plane's own axes (u, v):
//                            plane 0 XY (u = x, v = y, w = z), 1 ZX (u = z, v = x,
//                            w = y), 2 YZ (u = y, v = z, w = x)
//   helix .................. the lecture's linear interpolator (motion_top's idle
//                            line core A, a lin_exact) with lead N (the command's
//                            count, which line_pair loads into core A at
//                            `helix_start`) and minor `travel`, advanced once per
//                            arc step: the normal axis w is spread over the arc
//                            by expression (1)
//   synchronization ........ the arc's step is held one cycle (arc_q) so that the
//                            w step of the same arc step, which core A forms a cycle
//                            later, leaves in the SAME step entry
//   tail ................... whatever w travel is left when the arc ends goes out one
//                            step per `tick` (counter left_q), so w always ends at
//                            `travel`, whatever N is
// Step latency: circ_arc's step strobe comes two cycles after its tick, the held
// step a third; motion_top's step_sync counts a tick for two cycles (LATENCY 2), so
// circ_arc gets no tick while a held step waits in arc_q: no step finds the buffer
// full.  A tail step comes one cycle after its tick.
//
// Helix rule: N <= 0 counts as 0.  With N >= |travel| the w steps are spread
// evenly over N arc steps (N = the arc's step count: the last w step comes with
// the last arc step); with N < |travel| core A leads with w and every arc step
// carries a w step until all |travel| are out.  An arc shorter than core A's run
// leaves the rest to the tail; core A is stopped (`helix_abort`) when the arc ends.
// `done` and `error` are combinational strobes (error: circ_arc refused the
// command; no step then).  `start` while busy is ignored (motion_top never does it).
module arc_plane #(
    parameter integer W = 16    // width of the signed command fields (>= 6, circ_arc's limit)
) (
    input  wire         clk,
    input  wire         rst,
    input  wire         start,
    input  wire         tick,           // ~STOP of the synchronization buffer
    input  wire [1:0]   plane,          // 0 XY, 1 ZX, 2 YZ (3: motion_top refuses it)
    input  wire         ccw,
    input  wire [W-1:0] end_u,          // end point relative to the start
    input  wire [W-1:0] end_v,
    input  wire [W-1:0] centre_u,       // centre relative to the start
    input  wire [W-1:0] centre_v,
    input  wire [W-1:0] travel,         // helix travel along w, steps (signed)
    // line core A, lent for the helix
    output wire         helix_start,
    output wire         helix_tick,     // one per arc step
    output wire         helix_abort,    // the arc has ended: core A back to idle
    input  wire         helix_step,     // core A's minor step (w), a cycle after its tick
    input  wire         helix_dir,
    // steps, in machine axes {z, y, x}
    output reg  [2:0]   step,
    output reg  [2:0]   dir,
    output wire         busy,
    output wire         done,
    output wire         error
);
    initial begin
        if (W < 6) $error("%m: W must be at least 6");
    end

    localparam [1:0] P_IDLE = 2'd0, P_ARC = 2'd1, P_TAIL = 2'd2;
    reg  [1:0]   phase;
    reg  [1:0]   plane_q;
    reg          helix_q;       // travel != 0
    reg          w_neg_q;       // travel < 0
    reg  [W-1:0] left_q;        // w steps not yet out
    reg  [3:0]   arc_q;         // the arc's step a cycle late: {dir v, dir u, step v, step u}
    reg          tail_step_q;

    wire load = start & (phase == P_IDLE);
    wire arc_tick = tick & ~(arc_q[0] | arc_q[1]);      // the held step counts as in flight
    wire arc_sx, arc_sy, arc_dx, arc_dy, arc_busy, arc_done, arc_error;
    circ_arc #(.WIDTH(W)) u_arc (
        .clk(clk), .rst(rst), .start(load), .tick(arc_tick),
        .cx(centre_u), .cy(centre_v), .x0({W{1'b0}}), .y0({W{1'b0}}), .x1(end_u), .y1(end_v),
        .ccw(ccw), .full(end_u == {W{1'b0}} && end_v == {W{1'b0}}),
        .step_x(arc_sx), .step_y(arc_sy), .dir_x(arc_dx), .dir_y(arc_dy),
        .busy(arc_busy), .done(arc_done), .error(arc_error)
    );

    wire in_arc  = phase == P_ARC;
    wire in_tail = phase == P_TAIL;
    wire more    = left_q != {W{1'b0}};
    assign helix_start = load & (travel != {W{1'b0}});
    assign helix_tick  = in_arc & (arc_sx | arc_sy);
    assign helix_abort = in_arc & (arc_done | arc_error);
    assign busy  = phase != P_IDLE;
    assign done  = (in_arc & arc_done & ~helix_q) | (in_tail & ~more);
    assign error = in_arc & arc_error;

    // (u, v, w) -> {z, y, x}
    wire w_step = in_arc ? helix_step : in_tail & tail_step_q;
    wire w_dir  = in_arc ? helix_dir : w_neg_q;
    wire [2:0] uvw_step = {w_step, arc_q[1] & in_arc, arc_q[0] & in_arc};
    wire [2:0] uvw_dir  = {w_dir, arc_q[3], arc_q[2]};
    always @* begin
        case (plane_q)
            2'd1:    begin step = {uvw_step[0], uvw_step[2], uvw_step[1]};   // z = u, y = w, x = v
                           dir  = {uvw_dir[0], uvw_dir[2], uvw_dir[1]}; end
            2'd2:    begin step = {uvw_step[1], uvw_step[0], uvw_step[2]};   // z = v, y = u, x = w
                           dir  = {uvw_dir[1], uvw_dir[0], uvw_dir[2]}; end
            default: begin step = uvw_step;                                  // z = w, y = v, x = u
                           dir  = uvw_dir; end
        endcase
    end

    always @(posedge clk) begin
        if (rst) begin
            phase       <= P_IDLE;
            plane_q     <= 2'd0;
            helix_q     <= 1'b0;
            w_neg_q     <= 1'b0;
            left_q      <= {W{1'b0}};
            arc_q       <= 4'b0000;
            tail_step_q <= 1'b0;
        end else begin
            arc_q       <= {arc_dy, arc_dx, arc_sy, arc_sx};
            tail_step_q <= in_tail & tick & more;
            case (phase)
                P_IDLE: if (load) begin
                    phase   <= P_ARC;
                    plane_q <= plane;
                    helix_q <= travel != {W{1'b0}};
                    w_neg_q <= travel[W-1];
                    left_q  <= travel[W-1] ? -travel : travel;
                end
                P_ARC: begin
                    if (helix_step)
                        left_q <= left_q - 1'b1;
                    if (arc_error | (arc_done & ~helix_q))
                        phase <= P_IDLE;
                    else if (arc_done)
                        phase <= P_TAIL;
                end
                default: begin
                    if (~more)
                        phase <= P_IDLE;
                    else if (tick)
                        left_q <= left_q - 1'b1;
                end
            endcase
        end
    end

    wire unused = &{1'b0, arc_busy};
endmodule
`default_nettype wire
