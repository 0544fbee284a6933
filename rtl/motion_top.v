// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Motion subsystem: segment queue -> interpolator cores ->
// synchronization buffer -> speed-setting block -> step/dir output stage.
//   segment queue ........... sync_fifo u_queue (commands, QDEPTH entries)
//   line, 2 or 3 axes ....... line_pair u_lines: two lin_exact sharing the leading
//                             axis: core A makes (lead, minor 1), core B (lead,
//                             minor 2); both get every tick, so each lead step is one tick
//   circular arc, helix ..... arc_plane u_arc: circ_arc in the plane's (u, v), the
//                             helix axis w by line core A (lead N, minor cmd_z)
//   curve ................... curve_tangent (the paper's tangent method)
//   synchronization buffer .. step_sync u_sync (lecture: 2 D flip-flops per axis, STOP)
//   speed-setting block ..... feed_rate u_feed (lecture: Δt, x1.41 / x1.73 after
//                             steps on 2 / 3 axes)
//   output stage ............ step_dir u_out (pulse width, dir setup and hold)
//
// Commands (pushed with cmd_valid; fields signed W bits, relative to the
// position where the command starts):
//   kind 0 LINE    cmd_x, cmd_y, cmd_z: the move (cmd_plane ignored)
//   kind 1 ARC_CW, 2 ARC_CCW in plane cmd_plane: 0 XY (u = x, v = y, w = z),
//                  1 ZX (u = z, v = x, w = y), 2 YZ (u = y, v = z, w = x); CCW turns
//                  from +u to +v.  cmd_x, cmd_y end (u, v), cmd_i, cmd_j centre (u, v)
//                  (end = start: full circle); cmd_z helix travel along w, cmd_k N,
//                  the host's count of the arc's steps (see arc_plane.v)
//   kind 3 CURVE   curve_tangent with ΔX = cmd_x + cmd_i·x + cmd_j·y,
//                  ΔY = cmd_y + cmd_k·x + cmd_l·y (x, y from the start), cmd_z steps
//   kind 4 DWELL   wait until the drive has stopped, then cmd_x clock cycles (unsigned)
//   kind 5 EVENT   wait until the drive has stopped, then event_valid for one cycle
//                  with event_code = cmd_x[7:0], event_value = cmd_y
//   kind 6, 7      illegal
// cmd_feed: path speed, steps per clock x 2^FRAC (ignored by DWELL and EVENT).
// Bad commands are dropped with `error` (one-cycle strobe) and `error_code`
// (held until the next error or rst); the queue behind them runs on:
//   1 unknown kind, 2 feed 0, 3 a line coordinate = -2^(W-1), 4 the arc or
//   curve core refused the command (e.g. an inconsistent centre),
//   5 queue overflow (cmd_valid while cmd_full: the new command is refused,
//   the queue is kept), 6 step buffer overflow (never happens; a monitor),
//   7 an arc in plane 3.
// `hold` (feed hold) stops steps from leaving; the cores fill the buffer and
// stop.  pos_x/y/z count the pulses at the drive (rising edges of step_*).
module motion_top #(
    parameter integer W      = 16,  // command field width, signed (>= 6)
    parameter integer FEED_W = 16,  // feed word width (>= 1)
    parameter integer FRAC   = 16,  // feed fraction bits: feed 2^FRAC = 1 step per clock (1 .. 64)
    parameter integer QDEPTH = 4,   // commands the queue holds (>= 1)
    parameter integer QLW    = 3,   // width of queue_level (2^QLW > QDEPTH)
    parameter integer SDEPTH = 2,   // steps the synchronization buffer holds (>= 2)
    parameter integer TW     = 8,   // width of the timing registers of the output stage
    parameter integer POS_W  = 32   // width of the position counters (>= W)
) (
    input  wire              clk,
    input  wire              rst,
    // command input
    input  wire              cmd_valid,
    input  wire [2:0]        cmd_kind,
    input  wire [1:0]        cmd_plane,
    input  wire [FEED_W-1:0] cmd_feed,
    input  wire [W-1:0]      cmd_x,
    input  wire [W-1:0]      cmd_y,
    input  wire [W-1:0]      cmd_z,
    input  wire [W-1:0]      cmd_i,
    input  wire [W-1:0]      cmd_j,
    input  wire [W-1:0]      cmd_k,
    input  wire [W-1:0]      cmd_l,
    output wire              cmd_full,
    output wire [QLW-1:0]    queue_level,
    // machine
    input  wire              hold,          // feed hold: no step leaves
    input  wire [TW-1:0]     pulse_width,   // output stage timing, clock cycles
    input  wire [TW-1:0]     setup,
    input  wire [TW-1:0]     hold_time,
    output wire              step_x,
    output wire              step_y,
    output wire              step_z,
    output wire              dir_x,         // 1 = negative direction
    output wire              dir_y,
    output wire              dir_z,
    output reg  [POS_W-1:0]  pos_x,         // signed absolute position, steps
    output reg  [POS_W-1:0]  pos_y,
    output reg  [POS_W-1:0]  pos_z,
    output wire              busy,          // a command queued or running, or a step not yet out
    output reg               done,          // one-cycle strobe when busy falls
    output reg               error,         // one-cycle strobe: a command was refused
    output reg  [2:0]        error_code,
    output reg               event_valid,   // one-cycle strobe: an EVENT command's turn
    output reg  [7:0]        event_code,    // (both change when an EVENT is accepted)
    output reg  [W-1:0]      event_value
);
    initial begin
        if (W < 6) $error("%m: W must be at least 6");
        if (FEED_W < 1) $error("%m: FEED_W must be at least 1");
        if (FRAC < 1 || FRAC > 64) $error("%m: FRAC must be 1 .. 64");
        if (QDEPTH < 1 || (1 << QLW) <= QDEPTH) $error("%m: need QDEPTH >= 1 and 2^QLW > QDEPTH");
        if (SDEPTH < 2) $error("%m: SDEPTH must be at least 2");
        if (TW < 1) $error("%m: TW must be at least 1");
        if (POS_W < W) $error("%m: POS_W must be at least W");
    end

    localparam [2:0] K_LINE = 3'd0, K_ARC_CW = 3'd1, K_ARC_CCW = 3'd2, K_CURVE = 3'd3, K_DWELL = 3'd4,
                     K_EVENT = 3'd5;
    localparam [2:0] E_KIND = 3'd1, E_FEED = 3'd2, E_RANGE = 3'd3, E_CORE = 3'd4,
                     E_QUEUE = 3'd5, E_SYNC = 3'd6, E_PLANE = 3'd7;
    localparam [2:0] S_IDLE = 3'd0, S_LINE = 3'd1, S_ARC = 3'd2, S_CURVE = 3'd3,
                     S_DRAIN = 3'd4, S_DWELL = 3'd5, S_EVENT = 3'd6;
    localparam integer CMD_W = 5 + FEED_W + 7 * W;
    localparam integer SLW = 4;             // step buffer level width
    localparam integer CPW = W + 8;         // curve projection width

    // ---------------- segment queue ----------------
    wire [CMD_W-1:0] head;
    wire             q_valid, q_overflow, q_pop;
    sync_fifo #(.WIDTH(CMD_W), .DEPTH(QDEPTH), .LW(QLW)) u_queue (
        .clk(clk), .rst(rst), .push(cmd_valid),
        .din({cmd_kind, cmd_plane, cmd_feed, cmd_x, cmd_y, cmd_z, cmd_i, cmd_j, cmd_k, cmd_l}),
        .pop(q_pop), .dout(head), .valid(q_valid), .full(cmd_full), .level(queue_level),
        .overflow(q_overflow)
    );
    wire [2:0]        h_kind;
    wire [1:0]        h_plane;
    wire [FEED_W-1:0] h_feed;
    wire [W-1:0]      h_x, h_y, h_z, h_i, h_j, h_k, h_l;
    assign {h_kind, h_plane, h_feed, h_x, h_y, h_z, h_i, h_j, h_k, h_l} = head;

    // ---------------- dispatcher ----------------
    reg  [2:0] state;
    reg  [FEED_W-1:0] feed_q;
    reg  [W-1:0] dwell_q;

    wire [W-1:0] min_w = {1'b1, {(W-1){1'b0}}};

    wire idle      = state == S_IDLE;
    wire is_move   = h_kind == K_LINE || h_kind == K_ARC_CW || h_kind == K_ARC_CCW || h_kind == K_CURVE;
    wire is_arc    = h_kind == K_ARC_CW || h_kind == K_ARC_CCW;
    wire bad_kind  = h_kind > K_EVENT;
    wire bad_feed  = is_move && h_feed == {FEED_W{1'b0}};
    wire bad_range = h_kind == K_LINE && (h_x == min_w || h_y == min_w || h_z == min_w);
    wire bad_plane = is_arc && h_plane == 2'd3;
    wire dispatch  = idle & q_valid;
    wire accept    = dispatch & ~bad_kind & ~bad_feed & ~bad_range & ~bad_plane;
    assign q_pop   = dispatch;
    wire start_line  = accept && h_kind == K_LINE;
    wire start_arc   = accept && is_arc;
    wire start_curve = accept && h_kind == K_CURVE;

    wire core_tick;             // ~STOP of the synchronization buffer

    // ---------------- cores ----------------
    // Line core A also spreads an arc's helix axis (arc_plane borrows it).
    wire [2:0]   line_step, line_dir;
    wire         line_done, helix_start, helix_tick, helix_abort, helix_step, helix_dir;
    wire [W-1:0] helix_lead;
    line_pair #(.W(W)) u_lines (
        .clk(clk), .rst(rst), .start(start_line), .tick(core_tick), .x(h_x), .y(h_y), .z(h_z),
        .step(line_step), .dir(line_dir), .done(line_done),
        .helix_select(is_arc), .helix_start(helix_start), .helix_lead(helix_lead), .helix_travel(h_z),
        .lent(state == S_ARC), .helix_tick(helix_tick), .helix_abort(helix_abort),
        .helix_step(helix_step), .helix_dir(helix_dir)
    );

    wire [2:0] arc_step, arc_dir;
    wire       arc_busy, arc_done, arc_error;
    arc_plane #(.W(W)) u_arc (
        .clk(clk), .rst(rst), .start(start_arc), .tick(core_tick), .plane(h_plane),
        .ccw(h_kind == K_ARC_CCW), .end_u(h_x), .end_v(h_y), .centre_u(h_i), .centre_v(h_j),
        .travel(h_z), .count(h_k),
        .helix_start(helix_start), .helix_lead(helix_lead), .helix_tick(helix_tick),
        .helix_abort(helix_abort), .helix_step(helix_step), .helix_dir(helix_dir),
        .step(arc_step), .dir(arc_dir), .busy(arc_busy), .done(arc_done), .error(arc_error)
    );

    wire cv_sx, cv_sy, cv_dx, cv_dy, cv_busy, cv_done, cv_error;
    curve_tangent #(.WIDTH(W), .PW(CPW), .CW(W)) u_curve (
        .clk(clk), .rst(rst), .start(start_curve), .tick(core_tick),
        .x0({W{1'b0}}), .y0({W{1'b0}}),
        .p0({{8{h_x[W-1]}}, h_x}), .q0({{8{h_y[W-1]}}, h_y}),
        .dp_dx({{8{h_i[W-1]}}, h_i}), .dp_dy({{8{h_j[W-1]}}, h_j}),
        .dq_dx({{8{h_k[W-1]}}, h_k}), .dq_dy({{8{h_l[W-1]}}, h_l}),
        .reverse(1'b0), .count(h_z), .end_sel(2'd0), .end_coord({W{1'b0}}), .improved(1'b0),
        .e_load(1'b0), .e_init({(CPW+4){1'b0}}),
        .step_x(cv_sx), .step_y(cv_sy), .dir_x(cv_dx), .dir_y(cv_dy),
        .busy(cv_busy), .done(cv_done), .error(cv_error)
    );

    // The running core's steps (the others are idle and show no step).
    reg [2:0] core_step, core_dir;
    always @* begin
        case (state)
            S_ARC:   begin core_step = arc_step;               core_dir = arc_dir;                end
            S_CURVE: begin core_step = {1'b0, cv_sy, cv_sx};   core_dir = {1'b0, cv_dy, cv_dx};   end
            S_LINE:  begin core_step = line_step;               core_dir = line_dir;               end
            default: begin core_step = 3'b000;                  core_dir = 3'b000;                 end
        endcase
    end

    // ---------------- synchronization buffer, speed, output ----------------
    wire [2:0]        out_step, out_dir;
    wire [FEED_W-1:0] out_feed;
    wire              out_valid, stop, sync_overflow, feed_tick, drive_ready;
    wire [SLW-1:0]    sync_level;
    wire              release_ok = feed_tick & drive_ready & ~hold;
    wire              fire = release_ok & out_valid;
    step_sync #(.AXES(3), .DEPTH(SDEPTH), .LATENCY(2), .DATA_W(FEED_W), .LW(SLW)) u_sync (
        .clk(clk), .rst(rst), .in_step(core_step), .in_dir(core_dir), .in_data(feed_q),
        .stop(stop), .tick(release_ok), .out_valid(out_valid), .out_step(out_step),
        .out_dir(out_dir), .out_data(out_feed), .level(sync_level), .overflow(sync_overflow)
    );
    assign core_tick = ~stop;

    wire [1:0] out_axes = {1'b0, out_step[0]} + {1'b0, out_step[1]} + {1'b0, out_step[2]};
    feed_rate #(.FEED_W(FEED_W), .FRAC(FRAC)) u_feed (
        .clk(clk), .rst(rst), .feed(out_feed), .axes(out_axes), .take(fire), .tick(feed_tick)
    );

    wire [2:0] drv_step, drv_dir;
    step_dir #(.AXES(3), .TW(TW)) u_out (
        .clk(clk), .rst(rst), .pulse_width(pulse_width), .setup(setup), .hold(hold_time),
        .valid(fire), .step_in(out_step), .dir_in(out_dir), .ready(drive_ready),
        .step(drv_step), .dir(drv_dir)
    );
    assign {step_z, step_y, step_x} = drv_step;
    assign {dir_z, dir_y, dir_x}    = drv_dir;

    // ---------------- state, position, errors ----------------
    wire core_done  = (state == S_LINE  && line_done) ||
                      (state == S_ARC   && (arc_done | arc_error)) ||
                      (state == S_CURVE && (cv_done | cv_error));
    wire core_error = (state == S_ARC && arc_error) || (state == S_CURVE && cv_error);
    wire drained    = ~out_valid & drive_ready;
    reg  sync_overflow_q, busy_q;
    reg  [2:0] step_q;

    assign busy = ~idle | q_valid | out_valid | ~drive_ready;

    function [POS_W-1:0] moved(input [POS_W-1:0] pos, input rise, input neg);
        moved = rise ? (neg ? pos - 1'b1 : pos + 1'b1) : pos;
    endfunction

    always @(posedge clk) begin
        if (rst) begin
            state      <= S_IDLE;
            feed_q     <= {FEED_W{1'b0}};
            dwell_q    <= {W{1'b0}};
            event_valid <= 1'b0;
            event_code  <= 8'd0;
            event_value <= {W{1'b0}};
            pos_x      <= {POS_W{1'b0}};
            pos_y      <= {POS_W{1'b0}};
            pos_z      <= {POS_W{1'b0}};
            step_q     <= 3'b000;
            busy_q     <= 1'b0;
            done       <= 1'b0;
            error      <= 1'b0;
            error_code <= 3'd0;
            sync_overflow_q <= 1'b0;
        end else begin
            case (state)
                S_IDLE: if (accept) begin
                    feed_q <= h_feed;
                    case (h_kind)
                        K_LINE:  state <= S_LINE;
                        K_CURVE: state <= S_CURVE;
                        K_DWELL: begin
                            state   <= S_DRAIN;
                            dwell_q <= h_x;
                        end
                        K_EVENT: begin
                            state       <= S_EVENT;
                            event_code  <= h_x[7:0];
                            event_value <= h_y;
                        end
                        default: state <= S_ARC;
                    endcase
                end
                S_LINE, S_ARC, S_CURVE: if (core_done) state <= S_IDLE;
                S_DRAIN: if (drained) state <= S_DWELL;
                S_EVENT: if (drained) state <= S_IDLE;
                S_DWELL: begin
                    if (dwell_q == {W{1'b0}})
                        state <= S_IDLE;
                    else
                        dwell_q <= dwell_q - 1'b1;
                end
                default: state <= S_IDLE;
            endcase

            event_valid <= state == S_EVENT && drained;
            step_q <= drv_step;
            pos_x  <= moved(pos_x, drv_step[0] & ~step_q[0], drv_dir[0]);
            pos_y  <= moved(pos_y, drv_step[1] & ~step_q[1], drv_dir[1]);
            pos_z  <= moved(pos_z, drv_step[2] & ~step_q[2], drv_dir[2]);

            busy_q <= busy;
            done   <= busy_q & ~busy;

            sync_overflow_q <= sync_overflow;
            error <= 1'b1;
            if (dispatch & bad_kind)                    error_code <= E_KIND;
            else if (dispatch & bad_feed)               error_code <= E_FEED;
            else if (dispatch & bad_range)              error_code <= E_RANGE;
            else if (dispatch & bad_plane)              error_code <= E_PLANE;
            else if (core_error)                        error_code <= E_CORE;
            else if (q_overflow)                        error_code <= E_QUEUE;
            else if (sync_overflow & ~sync_overflow_q)  error_code <= E_SYNC;
            else                                        error <= 1'b0;
        end
    end

    wire unused = &{1'b0, arc_busy, cv_busy, sync_level};
endmodule
`default_nettype wire
