// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// CNC controller: the command record stream and a Wishbone register block around
// motion_top, with the machine's inputs and outputs.
//   record bytes (cmd_valid/cmd_data, or CMD_DATA register writes: their selected bytes)
//     -> segment_queue (2^QUEUE_AW bytes of block RAM; queue_free gives the link its credit)
//     -> record_unpack (RECORD_BYTES bytes -> motion_top's command fields)
//     -> motion_top (queues, cores, path-speed profile, step/dir)
//     -> input_guard (e-stop and limit switches gate the steps, probe latch) -> step, dir
//   motion_top's events -> machine_io (spindle, PWM, coolant, digital outputs)
//   every output pin: the logical output XOR its OUTPUT_INVERT bit (active-low drivers)
//   controller_regs: the register map (Wishbone B4 classic slave).
// Positions (POS_X/Y/Z) count the rising edges of the (logical) step pulses, here, so that an abort
// (which resets motion_top) keeps them; a register write at rest sets one (homing).  Any error latched in ERROR puts the controller in
// ALARM: motion_top held in reset (steps stop at once), queue and partial record flushed,
// incoming record bytes taken and dropped, spindle and coolant off, until CONTROL.clear.
// CONTROL.abort does the same for one clock: no error at rest (motion_top `still`), ERROR 19
// if it cut the steps at speed (the motors may have lost steps the counters count).  CONTROL.fill holds motion_top in
// reset and the records in the queue (the unpacker sees motion_top full), so a run starts
// from a filled queue as from a reset.  rst (synchronous, active high)
// returns everything to IDLE with positions 0.
module controller #(
    parameter integer CLK_HZ   = 50000000,  // clock frequency, Hz (CLOCK_HZ register, reset timings)
    parameter integer W        = 32,        // command field width (6 .. 255; record_unpack: max(W, 64 + FEED_W, 65 + PF) + ZW <= 496)
    parameter integer FEED_W   = 34,        // speed word width (motion_top; 2 .. 64)
    parameter integer FRAC     = 32,        // fraction bits of the path units (motion_top)
    parameter integer NW       = 24,        // speed in quanta width (motion_top)
    parameter integer PF       = 16,        // rate fraction bits (motion_top)
    parameter integer LEN_W    = 66,        // move length width (motion_top)
    parameter integer ZW       = 68,        // braking budget width (motion_top)
    parameter integer MW       = 12,        // S-curve filter depth 2^MW blocks (motion_top)
    parameter integer TW       = 16,        // step timing register width (motion_top; 1 .. 32)
    parameter integer POS_W    = 32,        // position counter width (W .. 32)
    parameter integer QDEPTH   = 8,         // commands motion_top's queues hold
    parameter integer QLW      = 4,         // width of motion_top's queue level (2^QLW > QDEPTH)
    parameter integer SDEPTH   = 2,         // steps motion_top's synchronization buffer holds
    parameter integer CURVES   = 1,         // 1: curve core present; 0: left out, kind 3 refused (error 1)
    parameter integer QUEUE_AW = 12,        // segment queue: 2^QUEUE_AW bytes (4 .. 15)
    parameter integer INPUT_INVERT_RESET  = 0,  // INPUT_INVERT after rst: active-low inputs from the start (0 .. 31)
    parameter integer OUTPUT_INVERT_RESET = 0   // OUTPUT_INVERT after rst: active-low pins rest inactive from the start (0 .. 65535)
) (
    input  wire        clk,
    input  wire        rst,
    // record byte stream (from the link)
    input  wire        cmd_valid,
    input  wire [7:0]  cmd_data,
    output wire        cmd_ready,
    output wire [15:0] queue_free,      // free bytes of the segment queue
    // Wishbone B4 classic slave
    input  wire [7:0]  wb_adr,
    input  wire [31:0] wb_dat_w,
    output wire [31:0] wb_dat_r,
    input  wire        wb_we,
    input  wire [3:0]  wb_sel,
    input  wire        wb_stb,
    input  wire        wb_cyc,
    output wire        wb_ack,
    // link counters (LINK_FRAMES, LINK_ERRORS; 0 without a link)
    input  wire [15:0] link_frames,
    input  wire [15:0] link_duplicates,
    input  wire [15:0] link_errors,
    input  wire [15:0] link_gaps,
    output wire [7:0]  status_state,    // STATUS[2:0], for the link's ACK
    output wire [7:0]  status_error,    // ERROR[7:0]
    // machine
    output wire [2:0]  step,            // x, y, z
    output wire [2:0]  dir,             // 1 = negative
    output wire        enable,          // drivers' enable (CONTROL.enable)
    input  wire        estop,
    input  wire [2:0]  limit,
    input  wire        probe,
    output wire        spindle_on,
    output wire        spindle_ccw,
    output wire        spindle_pwm,
    output wire        mist,
    output wire        flood,
    output wire [3:0]  dout,
    output wire        enable_state,    // CONTROL.enable and spindle on, before OUTPUT_INVERT (LEDs)
    output wire        spindle_state
);
    initial begin
        if (W < 6 || W > 255) $error("%m: W must be 6 .. 255");
        if (POS_W < W || POS_W > 32) $error("%m: POS_W must be W .. 32");
        if (CURVES < 0 || CURVES > 1) $error("%m: CURVES must be 0 or 1");
        if (QUEUE_AW < 4 || QUEUE_AW > 15) $error("%m: QUEUE_AW must be 4 .. 15");
        if (INPUT_INVERT_RESET < 0 || INPUT_INVERT_RESET > 31) $error("%m: INPUT_INVERT_RESET must be 0 .. 31");
        if (OUTPUT_INVERT_RESET < 0 || OUTPUT_INVERT_RESET > 65535) $error("%m: OUTPUT_INVERT_RESET must be 0 .. 65535");
        if (RECORD_BYTES > (1 << QUEUE_AW)) $error("%m: the segment queue must hold a record");
    end

    localparam integer RECORD_BYTES = 1 + 3 * ((FEED_W + 7) / 8) + 7 * ((W + 7) / 8) + (NW + 7) / 8
                                      + (PF + 8) / 8 + (LEN_W + 7) / 8 + (ZW + 7) / 8;

    reg  [7:0]  error_code;
    reg  [2:0]  error_limits;
    wire        alarm = error_code != 8'd0;
    wire        abort, clear, probe_arm, hold, hold_set, enabled, fill;
    wire        flush = abort | alarm;          // queue, partial record, motion_top

    // ---------------- record bytes: link stream or CMD_DATA words ----------------
    reg  [31:0] word;                           // a CMD_DATA write's bytes, lowest first
    reg  [3:0]  lanes;                          // ... those still to queue (its byte selects)
    wire        data_write;
    wire [31:0] data_word;
    wire [3:0]  data_lanes;
    wire        data_ready = lanes == 4'd0;
    wire        q_in_valid = data_ready ? cmd_valid : lanes[0];
    wire [7:0]  q_in_data  = data_ready ? cmd_data : word[7:0];
    wire        q_in_ready;
    wire        q_write    = q_in_valid & q_in_ready & ~flush;
    assign cmd_ready = flush | (q_in_ready & data_ready);   // in ALARM bytes are dropped

    always @(posedge clk) begin
        if (rst | flush) begin
            word  <= 32'd0;
            lanes <= 4'd0;
        end else if (data_write) begin
            word  <= data_word;
            lanes <= data_lanes;
        end else if (~data_ready & (q_in_ready | ~lanes[0])) begin   // a lane not selected: skipped
            word  <= {8'd0, word[31:8]};
            lanes <= {1'b0, lanes[3:1]};
        end
    end

    wire        q_valid, q_ready;
    wire [7:0]  q_data;
    wire [QUEUE_AW:0] unused_level, q_free;
    wire [15:0] free_records;
    segment_queue #(.AW(QUEUE_AW), .RECORD_BYTES(RECORD_BYTES)) u_queue (
        .clk(clk), .rst(rst), .flush(flush), .in_valid(q_in_valid), .in_data(q_in_data),
        .in_ready(q_in_ready), .out_valid(q_valid), .out_data(q_data), .out_ready(q_ready),
        .level(unused_level), .free(q_free), .free_records(free_records)
    );
    assign queue_free = {{(15 - QUEUE_AW){1'b0}}, q_free};

    // ---------------- unpacker -> motion_top ----------------
    wire              m_valid, m_full, record_error, taken, unused_assembling;
    wire [2:0]        m_kind;
    wire [1:0]        m_plane;
    wire [FEED_W-1:0] m_feed, m_limit, m_cost;
    wire [W-1:0]      m_x, m_y, m_z, m_i, m_j, m_k, m_l;
    wire [NW-1:0]     m_exit;
    wire [PF:0]       m_rate;
    wire [LEN_W-1:0]  m_length;
    wire [ZW-1:0]     m_budget;
    wire [3:0]        block_shift;
    wire [31:0]       limit_scale, rate_scale;      // the limit and rate codes' scales
    wire [5:0]        limit_shift, rate_shift;
    record_unpack #(.W(W), .FEED_W(FEED_W), .FRAC(FRAC), .NW(NW), .PF(PF), .LEN_W(LEN_W), .ZW(ZW)) u_unpack (
        .clk(clk), .rst(rst), .flush(flush), .block_shift(block_shift),
        .limit_scale(limit_scale), .limit_shift(limit_shift), .rate_scale(rate_scale), .rate_shift(rate_shift),
        .in_valid(q_valid), .in_data(q_data), .in_ready(q_ready),
        .cmd_valid(m_valid), .cmd_kind(m_kind), .cmd_plane(m_plane), .cmd_feed(m_feed),
        .cmd_x(m_x), .cmd_y(m_y), .cmd_z(m_z), .cmd_i(m_i), .cmd_j(m_j), .cmd_k(m_k), .cmd_l(m_l),
        .cmd_limit(m_limit), .cmd_exit(m_exit), .cmd_rate(m_rate), .cmd_cost(m_cost),
        .cmd_length(m_length), .cmd_budget(m_budget), .cmd_full(m_full | fill),
        .record_error(record_error), .taken(taken), .assembling(unused_assembling)
    );

    // records written and not yet taken by the unpacker (STATUS[15:8])
    reg  [15:0] records;
    wire        record_in;
    wire        record_out = taken & ~flush;
    record_bounds #(.RECORD_BYTES(RECORD_BYTES)) u_bounds (
        .clk(clk), .rst(rst), .flush(flush), .write(q_write), .data(q_in_data), .last(record_in));
    always @(posedge clk) begin
        if (rst | flush) begin
            records <= 16'd0;
        end else if (record_in & ~record_out) begin
            records <= records + 1'b1;
        end else if (record_out & ~record_in) begin
            records <= records - 1'b1;
        end
    end

    wire [TW-1:0]     pulse_width, dir_setup, dir_hold;
    wire [FEED_W-1:0] quantum;
    wire [3:0]        jerk_shift;
    wire [7:0]        override_percent;
    wire [2:0]        m_step, m_dir;
    wire [POS_W-1:0]  unused_pos_x, unused_pos_y, unused_pos_z;
    wire [FEED_W-1:0] unused_speed, m_cruise;   // the move's cruise (power_scale)
    wire [FEED_W+MW-1:0] m_step_speed;          // 2^m_speed_shift x the speed of the steps
    wire [3:0]        m_speed_shift;
    wire              stopped, still, m_busy, unused_done, m_error, event_valid;
    wire [3:0]        m_error_code;
    wire [QLW-1:0]    m_level;
    wire [7:0]        event_code;
    wire [W-1:0]      event_value;
    motion_top #(.W(W), .FEED_W(FEED_W), .FRAC(FRAC), .NW(NW), .PF(PF), .LEN_W(LEN_W), .ZW(ZW),
                 .MW(MW), .QDEPTH(QDEPTH), .QLW(QLW), .SDEPTH(SDEPTH), .TW(TW), .POS_W(POS_W),
                 .CURVES(CURVES)) u_motion (
        .clk(clk), .rst(rst | flush | fill),
        .cmd_valid(m_valid), .cmd_kind(m_kind), .cmd_plane(m_plane), .cmd_feed(m_feed),
        .cmd_x(m_x), .cmd_y(m_y), .cmd_z(m_z), .cmd_i(m_i), .cmd_j(m_j), .cmd_k(m_k), .cmd_l(m_l),
        .cmd_limit(m_limit), .cmd_exit(m_exit), .cmd_rate(m_rate), .cmd_cost(m_cost),
        .cmd_length(m_length), .cmd_budget(m_budget), .cmd_full(m_full), .queue_level(m_level),
        .speed_quantum(quantum), .block_shift(block_shift), .jerk_shift(jerk_shift),
        .override(override_percent), .hold(hold),
        .pulse_width(pulse_width), .setup(dir_setup), .hold_time(dir_hold),
        .step_x(m_step[0]), .step_y(m_step[1]), .step_z(m_step[2]),
        .dir_x(m_dir[0]), .dir_y(m_dir[1]), .dir_z(m_dir[2]),
        .pos_x(unused_pos_x), .pos_y(unused_pos_y), .pos_z(unused_pos_z),
        .speed(unused_speed), .cruise(m_cruise), .step_speed(m_step_speed), .speed_shift(m_speed_shift),
        .stopped(stopped), .still(still), .busy(m_busy), .done(unused_done),
        .error(m_error), .error_code(m_error_code),
        .event_valid(event_valid), .event_code(event_code), .event_value(event_value)
    );

    // ---------------- inputs, positions, errors ----------------
    wire [4:0]       inputs, input_invert, filter_mask;
    wire [15:0]      filter_period;
    wire             estop_trip, probe_valid, probe_hit, probe_stop;
    wire [2:0]       limit_trip, steps;       // steps: the gated step pulses (logical)
    reg  [POS_W-1:0] pos_x, pos_y, pos_z;
    wire [POS_W-1:0] probe_x, probe_y, probe_z;
    input_guard #(.POS_W(POS_W)) u_guard (
        .clk(clk), .rst(rst), .estop(estop), .limit(limit), .probe(probe), .invert(input_invert),
        .filter_period(filter_period), .filter_mask(filter_mask), .alarm(alarm),
        .probe_arm(probe_arm), .step_in(m_step), .step_out(steps),
        .inputs(inputs), .estop_trip(estop_trip), .limit_trip(limit_trip),
        .pos_x(pos_x), .pos_y(pos_y), .pos_z(pos_z),
        .probe_valid(probe_valid), .probe_hit(probe_hit), .probe_x(probe_x), .probe_y(probe_y),
        .probe_z(probe_z)
    );
    reg  [2:0] step_q;
    wire [2:0]       position_write;             // a register write sets a counter (homing)
    wire [POS_W-1:0] position_value;
    function [POS_W-1:0] moved(input [POS_W-1:0] pos, input rise, input negative);
        moved = rise ? (negative ? pos - 1'b1 : pos + 1'b1) : pos;
    endfunction

    wire [7:0] code_left = clear ? 8'd0 : error_code;
    always @(posedge clk) begin
        if (rst) begin
            step_q       <= 3'b000;
            pos_x        <= {POS_W{1'b0}};
            pos_y        <= {POS_W{1'b0}};
            pos_z        <= {POS_W{1'b0}};
            error_code   <= 8'd0;
            error_limits <= 3'b000;
        end else begin
            step_q <= steps;
            pos_x  <= position_write[0] ? position_value : moved(pos_x, steps[0] & ~step_q[0], m_dir[0]);
            pos_y  <= position_write[1] ? position_value : moved(pos_y, steps[1] & ~step_q[1], m_dir[1]);
            pos_z  <= position_write[2] ? position_value : moved(pos_z, steps[2] & ~step_q[2], m_dir[2]);
            if (clear)
                error_limits <= 3'b000;
            // the first error wins until CONTROL.clear
            if (code_left == 8'd0) begin
                if (estop_trip)
                    error_code <= 8'd16;
                else if (limit_trip != 3'b000) begin
                    error_code   <= 8'd17;
                    error_limits <= limit_trip;
                end else if (m_error & ~abort)      // (in an abort's clock: what it discards)
                    error_code <= {4'd0, m_error_code};
                else if (record_error & ~abort)
                    error_code <= 8'd18;
                else if (abort & ~still)            // steps cut at speed (Grbl's alarm 3)
                    error_code <= 8'd19;
                else
                    error_code <= 8'd0;
            end else if (error_code == 8'd17) begin
                error_limits <= error_limits | limit_trip;
            end
        end
    end

    // ---------------- outputs, registers ----------------
    wire        halted = stopped | (hold & fill);       // in hold: motion_top at rest, or kept at reset
    wire [15:0] duty, scaled, output_invert;
    wire [9:0]  spindle_scale;          // SPINDLE_OVERRIDE
    power_scale #(.FEED_W(FEED_W), .SPEED_W(FEED_W + MW)) u_power (
        .clk(clk), .rst(rst), .duty(duty), .speed(m_step_speed), .shift(m_speed_shift), .feed(m_cruise),
        .scaled(scaled)
    );
    wire        pause, io_spindle_on, io_spindle_pin, io_spindle_ccw, io_spindle_pwm, io_mist, io_flood;
    wire [3:0]  io_dout;
    machine_io #(.W(W)) u_io (
        .clk(clk), .rst(rst), .event_valid(event_valid), .event_code(event_code),
        .event_value(event_value), .off(flush), .held(halted), .scaled(scaled), .period(spindle_period),
        .scale(spindle_scale),
        .spindle_on(io_spindle_on), .spindle_pin(io_spindle_pin), .spindle_ccw(io_spindle_ccw), .duty(duty), .spindle_pwm(io_spindle_pwm),
        .mist(io_mist), .flood(io_flood), .dout(io_dout), .pause(pause)
    );
    assign hold_set = pause | (probe_hit & probe_stop);     // M0..; the probe's touch (G38.2)

    // records pushed into motion_top minus those still in its queue; a flush (alarm, abort)
    // discards that queue in its first clock (motion_top is then at reset, level 0), and
    // the discarded records were never run
    reg  [31:0] consumed;
    always @(posedge clk) begin
        if (rst)
            consumed <= 32'd0;
        else if (flush)
            consumed <= consumed - {{(32 - QLW){1'b0}}, m_level};
        else if (taken)
            consumed <= consumed + 1'b1;
    end
    wire [31:0] executed = consumed - {{(32 - QLW){1'b0}}, m_level};

    // busy: something to run (a partial record alone, bytes still to come, is not)
    wire        busy = m_busy | records != 16'd0 | ~data_ready;
    wire [2:0]  state = alarm ? 3'd4 : hold ? (halted ? 3'd3 : 3'd2) : busy ? 3'd1 : 3'd0;
    assign status_state = {5'd0, state};
    assign status_error = error_code;
    // the pins: the logical outputs XOR OUTPUT_INVERT (positions and OUTPUTS are logical)
    assign {dout, flood, mist, spindle_pwm, spindle_ccw, spindle_on, enable, dir, step} = output_invert
        ^ {io_dout, io_flood, io_mist, io_spindle_pwm, io_spindle_ccw, io_spindle_pin, enabled, m_dir, steps};
    assign enable_state  = enabled;
    assign spindle_state = io_spindle_on;

    wire [15:0] spindle_period;
    controller_regs #(.CLK_HZ(CLK_HZ), .W(W), .FEED_W(FEED_W), .FRAC(FRAC), .NW(NW), .PF(PF),
                      .LEN_W(LEN_W), .ZW(ZW), .MW(MW), .TW(TW), .POS_W(POS_W), .QUEUE_AW(QUEUE_AW),
                      .CURVES(CURVES), .RECORD_BYTES(RECORD_BYTES), .INPUT_INVERT_RESET(INPUT_INVERT_RESET),
                      .OUTPUT_INVERT_RESET(OUTPUT_INVERT_RESET)) u_regs (
        .clk(clk), .rst(rst), .wb_adr(wb_adr), .wb_dat_w(wb_dat_w), .wb_dat_r(wb_dat_r), .wb_we(wb_we),
        .wb_sel(wb_sel), .wb_stb(wb_stb), .wb_cyc(wb_cyc), .wb_ack(wb_ack),
        .state(state), .busy(busy), .stopped(halted), .probe_valid(probe_valid),
        .records(records > 16'd255 ? 8'd255 : records[7:0]), .error_code(error_code),
        .error_limits(error_limits), .free_bytes(queue_free), .free_records(free_records),
        .pos_x(pos_x), .pos_y(pos_y), .pos_z(pos_z), .probe_x(probe_x), .probe_y(probe_y),
        .probe_z(probe_z), .inputs(inputs),
        .outputs({8'd0, io_dout, io_flood, io_mist, io_spindle_ccw, io_spindle_on}), .duty(duty),
        .link_frames(link_frames), .link_duplicates(link_duplicates), .link_errors(link_errors),
        .link_gaps(link_gaps), .executed(executed), .hold_set(hold_set),
        .hold(hold), .enable(enabled), .fill(fill), .probe_stop(probe_stop), .abort_strobe(abort), .clear_strobe(clear), .arm_strobe(probe_arm),
        .override_percent(override_percent), .pulse_width(pulse_width), .dir_setup(dir_setup),
        .dir_hold(dir_hold), .quantum(quantum), .block_shift(block_shift), .jerk_shift(jerk_shift),
        .limit_scale(limit_scale), .limit_shift(limit_shift), .rate_scale(rate_scale), .rate_shift(rate_shift),
        .input_invert(input_invert), .output_invert(output_invert),
        .filter_period(filter_period), .filter_mask(filter_mask), .spindle_period(spindle_period), .spindle_scale(spindle_scale),
        .position_write(position_write), .position_value(position_value),
        .data_write(data_write), .data_word(data_word), .data_lanes(data_lanes), .data_ready(data_ready)
    );

    wire unused = &{1'b0, unused_pos_x, unused_pos_y, unused_pos_z, unused_speed, unused_done};
endmodule
`default_nettype wire
