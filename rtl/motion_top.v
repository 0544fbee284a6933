// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Motion subsystem: command queues -> interpolator cores ->
// synchronization buffer -> speed-setting block -> step/dir output stage.
//   geometry queue .......... sync_fifo u_queue (commands, QDEPTH entries)
//   interpolator cores ...... motion_cores u_cores: lines on two SU 1571551 exact cores
//                             (line_pair), arcs and helices in any plane on circ_arc (the
//                             lecture's circle with SU 1665343's midpoint choice, in
//                             arc_plane), curves by the paper's tangent method
//   synchronization buffer .. step_sync u_sync (lecture: 2 D flip-flops per axis, STOP);
//                             each step carries its command's cost
//   speed-setting block ..... path_profile u_profile (lecture: "БЗС"): the profile
//                             queue, speed_ramp (acceleration, braking, hold, override),
//                             jerk_filter (S-curve), step_pacer (releases the steps)
//   output stage ............ step_dir u_out (pulse width, dir setup and hold)
// The dispatcher (state) pops the geometry queue's head when idle and starts its core,
// or runs a DWELL (kind 4) or EVENT (kind 5) once the speed is 0 and the drive has
// stopped; an inline EVENT (plane bit 0 set: a laser's power) runs as soon as it is the
// head, without a stop, and takes no profile queue entry.  Commands (kinds 0 LINE, 1 ARC_CW, 2 ARC_CCW, 3 CURVE, 4, 5; fields signed
// W bits relative to where the command starts) and their profiles (cmd_feed .. cmd_budget)
// are documented in docs/cores/motion_top.md with the error codes: every check is made
// at the push, so a refused command never enters a queue (`error` strobes the cycle
// after, `error_code` held: 1 kind, 2 feed, 3 range, 5 queue full, 7 plane, 8 profile);
// at run time 4 a core refused its command (FAULT until rst: queues flushed, speed block
// stopped), 6 step buffer overflow (a monitor), 9 `late` (a segment ended above its
// target speed), 10 the step pacer overran (steps asked faster than the output stage
// makes them for so long that its phase saturated: distance lost; FAULT until rst).
// A DWELL or EVENT waits while `hold` is high.  `hold` decelerates the path to speed 0
// (`stopped`, once the S-curve filter is empty too) and resumes on release; no step is lost.  `still`: no speed in the
// ramp or the filter, so no step comes (a stop now loses nothing).  pos_x/y/z count the pulses at the drive (rising edges of
// step_*).
module motion_top #(
    parameter integer W      = 16,  // command field width, signed (>= 6)
    parameter integer FEED_W = 16,  // speed word width, path units per clock (>= 2)
    parameter integer FRAC   = 16,  // fraction bits: an axial step is 2^FRAC path units (1 .. 64)
    parameter integer NW     = 16,  // speed in quanta, width (1 .. FEED_W)
    parameter integer PF     = 12,  // rate fraction bits: cmd_rate 2^PF = a quantum per block (>= 1)
    parameter integer LEN_W  = 34,  // segment length width, path units (>= FEED_W)
    parameter integer ZW     = 48,  // braking budget width (>= LEN_W)
    parameter integer MW     = 6,   // S-curve filter depth 2^MW blocks (2 .. 15)
    parameter integer QDEPTH = 4,   // commands the queues hold (>= 1)
    parameter integer QLW    = 3,   // width of queue_level (2^QLW > QDEPTH)
    parameter integer SDEPTH = 2,   // steps the synchronization buffer holds (>= 2)
    parameter integer TW     = 8,   // width of the timing registers of the output stage
    parameter integer POS_W  = 32,  // width of the position counters (>= W)
    parameter integer CURVES = 1    // 1: curve_tangent present; 0: left out, kind 3 refused (error 1)
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
    input  wire [FEED_W-1:0] cmd_limit,
    input  wire [NW-1:0]     cmd_exit,
    input  wire [PF:0]       cmd_rate,
    input  wire [FEED_W-1:0] cmd_cost,
    input  wire [LEN_W-1:0]  cmd_length,
    input  wire [ZW-1:0]     cmd_budget,
    output wire              cmd_full,
    output wire [QLW-1:0]    queue_level,   // entries of the geometry queue
    // machine
    input  wire [FEED_W-1:0] speed_quantum, // A: path units per clock per quantum (constant while busy)
    input  wire [3:0]        block_shift,   // a block is 2^block_shift clocks
    input  wire [3:0]        jerk_shift,    // S-curve: 2^jerk_shift blocks (0 .. MW; 0 trapezoid)
    /* verilator lint_off SYMRSVDWORD */   // `override` is a C++ word, not a Verilog one
    input  wire [7:0]        override,      // percent of cmd_feed, 1 .. 200 (clamped)
    /* verilator lint_on SYMRSVDWORD */
    input  wire              hold,          // feed hold: decelerate to 0, resume on release
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
    output wire [FEED_W-1:0] speed,         // virtual path speed v, path units per clock
    output wire [FEED_W-1:0] cruise,        // the feed of the move the speed is for
    output wire [FEED_W+MW-1:0] step_speed, // 2^speed_shift x the speed of the steps (the S-curve filter's sum)
    output wire [3:0]        speed_shift,
    output wire              stopped,       // hold has brought the speed to 0 (or nothing moves)
    output wire              still,         // no speed anywhere in the profile: no step comes
    output wire              busy,          // a command queued or running, or a step not yet out
    output reg               done,          // one-cycle strobe when busy falls
    output reg               error,         // one-cycle strobe: a command was refused
    output reg  [3:0]        error_code,
    output reg               event_valid,   // one-cycle strobe: an EVENT command's turn
    output reg  [7:0]        event_code,    // (both change when an EVENT is accepted)
    output reg  [W-1:0]      event_value
);
    initial begin
        if (W < 6) $error("%m: W must be at least 6");
        if (FEED_W < 2) $error("%m: FEED_W must be at least 2");
        if (FRAC < 1 || FRAC > 64) $error("%m: FRAC must be 1 .. 64");
        if (NW < 1 || NW > FEED_W) $error("%m: NW must be 1 .. FEED_W");
        if (PF < 1) $error("%m: PF must be at least 1");
        if (LEN_W < FEED_W) $error("%m: LEN_W must be at least FEED_W");
        if (ZW < LEN_W) $error("%m: ZW must be at least LEN_W");
        if (MW < 2 || MW > 15) $error("%m: MW must be 2 .. 15");
        if (QDEPTH < 1 || (1 << QLW) <= QDEPTH) $error("%m: need QDEPTH >= 1 and 2^QLW > QDEPTH");
        if (SDEPTH < 2) $error("%m: SDEPTH must be at least 2");
        if (TW < 1) $error("%m: TW must be at least 1");
        if (POS_W < W) $error("%m: POS_W must be at least W");
        if (CURVES < 0 || CURVES > 1) $error("%m: CURVES must be 0 or 1");
    end

    localparam [2:0] K_LINE = 3'd0, K_ARC_CW = 3'd1, K_ARC_CCW = 3'd2, K_CURVE = 3'd3, K_DWELL = 3'd4,
                     K_EVENT = 3'd5;
    localparam [3:0] E_KIND = 4'd1, E_FEED = 4'd2, E_RANGE = 4'd3, E_CORE = 4'd4,
                     E_QUEUE = 4'd5, E_SYNC = 4'd6, E_PLANE = 4'd7, E_PROFILE = 4'd8,
                     E_LATE = 4'd9, E_OVERRUN = 4'd10;
    localparam [2:0] S_IDLE = 3'd0, S_LINE = 3'd1, S_ARC = 3'd2, S_CURVE = 3'd3,
                     S_DRAIN = 3'd4, S_DWELL = 3'd5, S_EVENT = 3'd6, S_FAULT = 3'd7;
    localparam integer CMD_W = 5 + FEED_W + 7 * W;
    localparam integer SLW = 4;             // step buffer level width

    reg  [2:0] state;
    wire       fault = state == S_FAULT;
    wire       flush = rst | fault;         // a fault empties the queues and stops the speed block

    // ---------------- checks at the push ----------------
    wire [W-1:0] min_w = {1'b1, {(W-1){1'b0}}};
    wire [PF:0]  rate_top = {1'b1, {PF{1'b0}}};
    wire p_move    = cmd_kind <= K_CURVE;
    wire p_arc     = cmd_kind == K_ARC_CW || cmd_kind == K_ARC_CCW;
    wire p_inline  = cmd_kind == K_EVENT && cmd_plane[0];   // no stop: not in the profile queue
    wire bad_kind  = cmd_kind > K_EVENT || (CURVES == 0 && cmd_kind == K_CURVE);
    wire bad_feed  = p_move && cmd_feed == {FEED_W{1'b0}};
    wire bad_range = cmd_kind == K_LINE && (cmd_x == min_w || cmd_y == min_w || cmd_z == min_w);
    wire bad_plane = p_arc && cmd_plane == 2'd3;
    wire bad_profile = p_move && (cmd_rate == {(PF+1){1'b0}} || cmd_rate > rate_top ||
                                  cmd_length == {LEN_W{1'b0}} || cmd_limit < cmd_feed ||
                                  block_shift < 4'd2);
    wire bad_cmd   = bad_kind | bad_feed | bad_range | bad_plane | bad_profile;
    wire geo_full, prof_full;
    assign cmd_full = geo_full | prof_full;
    wire push = cmd_valid & ~fault & ~bad_cmd & ~cmd_full;

    // ---------------- geometry queue ----------------
    wire [CMD_W-1:0] head;
    wire             q_valid, q_pop, unused_overflow;
    sync_fifo #(.WIDTH(CMD_W), .DEPTH(QDEPTH), .LW(QLW)) u_queue (
        .clk(clk), .rst(flush), .push(push),
        .din({cmd_kind, cmd_plane, cmd_cost, cmd_x, cmd_y, cmd_z, cmd_i, cmd_j, cmd_k, cmd_l}),
        .pop(q_pop), .dout(head), .valid(q_valid), .full(geo_full), .level(queue_level),
        .overflow(unused_overflow)
    );
    wire [2:0]        h_kind;
    wire [1:0]        h_plane;
    wire [FEED_W-1:0] h_cost;
    wire [W-1:0]      h_x, h_y, h_z, h_i, h_j, h_k, h_l;
    assign {h_kind, h_plane, h_cost, h_x, h_y, h_z, h_i, h_j, h_k, h_l} = head;

    // ---------------- dispatcher ----------------
    reg  [FEED_W-1:0] cost_q;
    reg  [W-1:0] dwell_q;

    reg  inline_q;                          // an inline EVENT was popped at the last edge
    wire idle      = state == S_IDLE;
    wire is_arc    = h_kind == K_ARC_CW || h_kind == K_ARC_CCW;
    // every queued command was checked at its push; after an inline EVENT a clock passes
    // before the next pop, so line_pair sees the next head a cycle ahead (below)
    wire dispatch  = idle & q_valid & ~inline_q;
    wire inline_go = dispatch && h_kind == K_EVENT && h_plane[0];
    assign q_pop   = dispatch;
    wire start_line  = dispatch && h_kind == K_LINE;
    wire start_arc   = dispatch && is_arc;
    wire start_curve = dispatch && h_kind == K_CURVE;

    wire core_tick;             // ~STOP of the synchronization buffer

    // ---------------- cores ----------------
    // line_pair takes its command a cycle ahead: the head, or while the queue is empty the
    // command being pushed (the head of the next cycle if it is taken).  The head changes
    // only at a pop (which leaves S_IDLE: no start in the next cycle) or at a push into the
    // empty queue, so at every start these registers hold the head's command.
    wire [2:0] core_step, core_dir;
    wire       core_done, core_error;
    wire [2:0] next_kind = q_valid ? h_kind : cmd_kind;
    motion_cores #(.W(W), .CURVES(CURVES)) u_cores (
        .clk(clk), .rst(rst), .tick(core_tick),
        .next_x(q_valid ? h_x : cmd_x), .next_y(q_valid ? h_y : cmd_y), .next_z(q_valid ? h_z : cmd_z),
        .next_arc(next_kind == K_ARC_CW || next_kind == K_ARC_CCW), .next_count(q_valid ? h_k : cmd_k),
        .plane(h_plane), .ccw(h_kind == K_ARC_CCW), .cmd_x(h_x), .cmd_y(h_y), .cmd_z(h_z),
        .cmd_i(h_i), .cmd_j(h_j), .cmd_k(h_k), .cmd_l(h_l),
        .start_line(start_line), .start_arc(start_arc), .start_curve(start_curve),
        .run_line(state == S_LINE), .run_arc(state == S_ARC), .run_curve(state == S_CURVE),
        .step(core_step), .dir(core_dir), .done(core_done), .error(core_error)
    );

    // ---------------- synchronization buffer, speed, output ----------------
    wire [2:0]        out_step, out_dir;
    wire [FEED_W-1:0] out_cost;
    wire              out_valid, stop, sync_overflow, drive_ready, fire, moving, late, overrun, ramp_stopped, profile_still;
    wire [SLW-1:0]    sync_level;
    step_sync #(.AXES(3), .DEPTH(SDEPTH), .LATENCY(2), .DATA_W(FEED_W), .LW(SLW)) u_sync (
        .clk(clk), .rst(flush), .in_step(core_step), .in_dir(core_dir), .in_data(cost_q),
        .stop(stop), .tick(fire), .out_valid(out_valid), .out_step(out_step),
        .out_dir(out_dir), .out_data(out_cost), .level(sync_level), .overflow(sync_overflow)
    );
    assign core_tick = ~stop;

    wire [1:0] out_axes = {1'b0, out_step[0]} + {1'b0, out_step[1]} + {1'b0, out_step[2]};
    wire       drained  = ~out_valid & drive_ready & ~moving;   // speed 0, every step out
    // an EVENT or DWELL waits while `hold` is high (a feed hold holds the program, as Grbl's
    // suspends a dwell): a pause event holds the machine (the controller's M0), so the next
    // one runs only after the release and two pauses stay two
    wire       event_go = drained & ~hold;
    wire       barrier_done = (state == S_DWELL && dwell_q == {W{1'b0}} && ~hold) || (state == S_EVENT && event_go);
    // At rest (not busy, no push) the speed block is held in reset: the ramp's overshoot of
    // the last stop and the pacer's phase left over from it cancel exactly, and a new
    // jerk_shift or speed_quantum starts from a clean state.
    wire rest = ~busy & ~cmd_valid;
    wire [QLW-1:0] profile_level;
    path_profile #(.FEED_W(FEED_W), .FRAC(FRAC), .NW(NW), .PF(PF), .LEN_W(LEN_W), .ZW(ZW), .MW(MW),
                   .QDEPTH(QDEPTH), .QLW(QLW)) u_profile (
        .clk(clk), .rst(flush | rest), .push(push & ~p_inline), .push_barrier(~p_move), .push_feed(cmd_feed),
        .push_limit(cmd_limit), .push_exit(cmd_exit), .push_rate(cmd_rate), .push_length(cmd_length),
        .push_budget(cmd_budget), .full(prof_full), .level(profile_level), .barrier_done(barrier_done),
        .speed_quantum(speed_quantum), .block_shift(block_shift), .jerk_shift(jerk_shift),
        .override(override), .hold(hold), .step_valid(out_valid), .step_axes(out_axes),
        .step_cost(out_cost), .drive_ready(drive_ready), .fire(fire), .speed(speed), .cruise(cruise), .step_speed(step_speed),
        .speed_shift(speed_shift), .moving(moving),
        .stopped(ramp_stopped), .still(profile_still), .late(late), .overrun(overrun)
    );
    assign stopped = ramp_stopped | (hold & ~busy);
    assign still   = profile_still & drive_ready;     // (and no pulse or direction timing under way)

    wire [2:0] drv_step, drv_dir;
    step_dir #(.AXES(3), .TW(TW)) u_out (
        .clk(clk), .rst(rst), .pulse_width(pulse_width), .setup(setup), .hold(hold_time),
        .valid(fire), .step_in(out_step), .dir_in(out_dir), .ready(drive_ready),
        .step(drv_step), .dir(drv_dir)
    );
    assign {step_z, step_y, step_x} = drv_step;
    assign {dir_z, dir_y, dir_x}    = drv_dir;

    // ---------------- state, position, errors ----------------
    reg  sync_overflow_q, busy_q;
    reg  [2:0] step_q;

    assign busy = (~idle & ~fault) | q_valid | profile_level != {QLW{1'b0}} | out_valid | ~drive_ready
                  | moving;

    function [POS_W-1:0] moved(input [POS_W-1:0] pos, input rise, input neg);
        moved = rise ? (neg ? pos - 1'b1 : pos + 1'b1) : pos;
    endfunction

    always @(posedge clk) begin
        if (rst) begin
            state      <= S_IDLE;
            cost_q     <= {FEED_W{1'b0}};
            dwell_q    <= {W{1'b0}};
            event_valid <= 1'b0;
            inline_q    <= 1'b0;
            event_code  <= 8'd0;
            event_value <= {W{1'b0}};
            pos_x      <= {POS_W{1'b0}};
            pos_y      <= {POS_W{1'b0}};
            pos_z      <= {POS_W{1'b0}};
            step_q     <= 3'b000;
            busy_q     <= 1'b0;
            done       <= 1'b0;
            error      <= 1'b0;
            error_code <= 4'd0;
            sync_overflow_q <= 1'b0;
        end else begin
            case (state)
                S_IDLE: if (dispatch) begin
                    cost_q <= h_cost;
                    case (h_kind)
                        K_LINE:  state <= S_LINE;
                        K_CURVE: state <= S_CURVE;
                        K_DWELL: begin
                            state   <= S_DRAIN;
                            dwell_q <= h_x;
                        end
                        K_EVENT: begin
                            state       <= h_plane[0] ? S_IDLE : S_EVENT;   // inline: at once
                            event_code  <= h_x[7:0];
                            event_value <= h_y;
                        end
                        default: state <= S_ARC;
                    endcase
                end
                S_LINE, S_ARC, S_CURVE: if (core_error) state <= S_FAULT;
                                        else if (core_done) state <= S_IDLE;
                S_DRAIN: if (event_go) state <= S_DWELL;
                S_EVENT: if (event_go) state <= S_IDLE;
                S_DWELL: if (~hold) begin
                    if (dwell_q == {W{1'b0}})
                        state <= S_IDLE;
                    else
                        dwell_q <= dwell_q - 1'b1;
                end
                default: state <= S_FAULT;      // until rst
            endcase
            if (overrun & ~fault) state <= S_FAULT;    // distance lost: stop (until rst)

            event_valid <= (state == S_EVENT && event_go) || inline_go;
            inline_q    <= inline_go;
            step_q <= drv_step;
            pos_x  <= moved(pos_x, drv_step[0] & ~step_q[0], drv_dir[0]);
            pos_y  <= moved(pos_y, drv_step[1] & ~step_q[1], drv_dir[1]);
            pos_z  <= moved(pos_z, drv_step[2] & ~step_q[2], drv_dir[2]);

            busy_q <= busy;
            done   <= busy_q & ~busy;

            sync_overflow_q <= sync_overflow;
            error <= 1'b1;
            if (core_error)                             error_code <= E_CORE;
            else if (cmd_valid & fault)                 error_code <= E_CORE;
            else if (cmd_valid & bad_kind)              error_code <= E_KIND;
            else if (cmd_valid & bad_feed)              error_code <= E_FEED;
            else if (cmd_valid & bad_range)             error_code <= E_RANGE;
            else if (cmd_valid & bad_plane)             error_code <= E_PLANE;
            else if (cmd_valid & bad_profile)           error_code <= E_PROFILE;
            else if (cmd_valid & cmd_full)              error_code <= E_QUEUE;
            else if (sync_overflow & ~sync_overflow_q)  error_code <= E_SYNC;
            else if (overrun & ~fault)                  error_code <= E_OVERRUN;
            else if (late)                              error_code <= E_LATE;
            else                                        error <= 1'b0;
        end
    end

    wire unused = &{1'b0, sync_level, unused_overflow};
endmodule
`default_nettype wire
