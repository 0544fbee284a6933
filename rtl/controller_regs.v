// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Register block of the controller: a Wishbone B4 classic slave, 32-bit data, byte
// addresses on wb_adr[7:0] (bits 1:0 ignored; byte selects ignored, whole words, except
// at CMD_DATA: the selected bytes are the record bytes).  Every access is acknowledged in
// the cycle after it is seen (wb_ack one cycle), except a write to CMD_DATA, which waits
// until the controller takes its bytes (`data_ready`).
// Unknown addresses read 0 and ignore writes.  The addresses are rtl/controller_regs.vh's
// REG_<NAME> (generated from regs/controller.rdl); the map is in docs/registers.md.
// Read-only registers are composed here from the controller's status inputs; the
// read-write ones (machine settings) are held here and drive the outputs.  CONTROL:
// [0] hold (RW; also set by `hold_set`, a pause event or the probe's touch, which wins
// over a CONTROL write in the same clock), write-1
// strobes [1] abort, [2] clear (registered: high in the ack cycle), [3] probe_arm
// (in the access cycle), [4] enable (RW), [5] fill (RW),
// [6] probe_stop (RW: the armed probe's touch sets hold).  QUANTUM_LO/HI, MOTION and the
// code scales LIMIT_SCALE / RATE_SCALE are
// taken only while `busy` is low, and fill rises only then (or with abort in the same
// write): a write while busy keeps them and sets STATUS.refused (until CONTROL.clear).
// POS_X/Y/Z: a write while not busy sets that position counter (`position_write`, the
// value sign-truncated to POS_W bits; homing) and its STATUS.position_set bit, which
// only the reset clears; a write while busy is refused the same way.
module controller_regs #(
    parameter integer CLK_HZ   = 50000000,  // board clock, Hz (CLOCK_HZ register; >= 1)
    parameter integer W        = 32,        // command field width (VERSION; 6 .. 255)
    parameter integer FEED_W   = 34,        // speed word width (BUILD0; 2 .. 64)
    parameter integer FRAC     = 32,        // fraction bits (BUILD0; 1 .. 64)
    parameter integer NW       = 24,        // speed in quanta width (BUILD0; 1 .. 255)
    parameter integer PF       = 16,        // rate fraction bits (BUILD0; 1 .. 255)
    parameter integer LEN_W    = 66,        // move length width (BUILD1; 1 .. 255)
    parameter integer ZW       = 68,        // braking budget width (BUILD1; 1 .. 255)
    parameter integer MW       = 12,        // S-curve depth (BUILD1; 2 .. 15)
    parameter integer TW       = 16,        // output stage timing width (BUILD1; 1 .. 32)
    parameter integer POS_W    = 32,        // position counter width (VERSION; 2 .. 32)
    parameter integer QUEUE_AW = 12,        // segment queue: 2^QUEUE_AW bytes (QUEUE_SIZE; 4 .. 15)
    parameter integer CURVES   = 1,         // curve core present (QUEUE_SIZE bit 24; 0 or 1)
    parameter integer RECORD_BYTES = 68,    // bytes of a record (VERSION; 1 .. 255)
    parameter integer INPUT_INVERT_RESET  = 0,  // INPUT_INVERT after rst (0 .. 31)
    parameter integer OUTPUT_INVERT_RESET = 0   // OUTPUT_INVERT after rst (0 .. 65535)
) (
    input  wire              clk,
    input  wire              rst,
    // Wishbone B4 classic slave
    input  wire [7:0]        wb_adr,
    input  wire [31:0]       wb_dat_w,
    output reg  [31:0]       wb_dat_r,
    input  wire              wb_we,
    input  wire [3:0]        wb_sel,
    input  wire              wb_stb,
    input  wire              wb_cyc,
    output reg               wb_ack,
    // status
    input  wire [2:0]        state,         // STATUS[2:0]
    input  wire              busy,
    input  wire              stopped,
    input  wire              probe_valid,
    input  wire [7:0]        records,       // records in the queue, saturated
    input  wire [7:0]        error_code,
    input  wire [2:0]        error_limits,
    input  wire [15:0]       free_bytes,
    input  wire [15:0]       free_records,
    input  wire [POS_W-1:0]  pos_x,
    input  wire [POS_W-1:0]  pos_y,
    input  wire [POS_W-1:0]  pos_z,
    input  wire [POS_W-1:0]  probe_x,
    input  wire [POS_W-1:0]  probe_y,
    input  wire [POS_W-1:0]  probe_z,
    input  wire [4:0]        inputs,
    input  wire [15:0]       outputs,       // OUTPUTS[15:0]
    input  wire [15:0]       duty,          // OUTPUTS[31:16]
    input  wire [15:0]       link_frames,
    input  wire [15:0]       link_duplicates,
    input  wire [15:0]       link_errors,
    input  wire [15:0]       link_gaps,
    input  wire [31:0]       executed,
    input  wire              hold_set,      // a pause event or the probe's touch: set CONTROL.hold
    // settings and strobes
    output reg               hold,
    output reg               enable,
    output reg               fill,          // CONTROL.fill: records wait, motion_top at reset
    output reg               probe_stop,    // CONTROL.probe_stop: the probe's touch holds
    output reg               abort_strobe,  // CONTROL write-1 strobes: abort, clear (in the ack cycle),
    output reg               clear_strobe,
    output wire              arm_strobe,    // probe_arm (in the access cycle)
    output reg  [7:0]        override_percent,
    output reg  [TW-1:0]     pulse_width,
    output reg  [TW-1:0]     dir_setup,
    output reg  [TW-1:0]     dir_hold,
    output reg  [FEED_W-1:0] quantum,
    output reg  [3:0]        block_shift,
    output reg  [3:0]        jerk_shift,
    output reg  [31:0]       limit_scale,   // record_unpack's limit code
    output reg  [5:0]        limit_shift,
    output reg  [31:0]       rate_scale,    // ... and rate code
    output reg  [5:0]        rate_shift,
    output reg  [4:0]        input_invert,
    output reg  [15:0]       output_invert,
    output reg  [15:0]       filter_period,     // INPUT_FILTER: clocks a sample of input_filter, 0 = off
    output reg  [4:0]        filter_mask,       // INPUT_FILTER: the inputs filtered
    output reg  [15:0]       spindle_period,
    output reg  [9:0]        spindle_scale,     // SPINDLE_OVERRIDE: the PWM's duty x scale / 256
    output wire [2:0]        position_write, // strobes: set POS_X / POS_Y / POS_Z to position_value
    output wire [POS_W-1:0]  position_value,
    output wire              data_write,    // strobe: data_word's selected bytes for the queue
    output wire [31:0]       data_word,
    output wire [3:0]        data_lanes,    // ... the bytes selected (wb_sel), lowest first
    input  wire              data_ready     // the controller takes a data_word now
);
    initial begin
        if (CLK_HZ < 1) $error("%m: CLK_HZ must be at least 1");
        if (W < 6 || W > 255) $error("%m: W must be 6 .. 255");
        if (FEED_W < 2 || FEED_W > 64) $error("%m: FEED_W must be 2 .. 64");
        if (FRAC < 1 || FRAC > 64) $error("%m: FRAC must be 1 .. 64");
        if (NW < 1 || NW > 255) $error("%m: NW must be 1 .. 255");
        if (PF < 1 || PF > 255) $error("%m: PF must be 1 .. 255");
        if (LEN_W < 1 || LEN_W > 255) $error("%m: LEN_W must be 1 .. 255");
        if (ZW < 1 || ZW > 255) $error("%m: ZW must be 1 .. 255");
        if (MW < 2 || MW > 15) $error("%m: MW must be 2 .. 15");
        if (TW < 1 || TW > 32) $error("%m: TW must be 1 .. 32");
        if (POS_W < 2 || POS_W > 32) $error("%m: POS_W must be 2 .. 32");
        if (QUEUE_AW < 4 || QUEUE_AW > 15) $error("%m: QUEUE_AW must be 4 .. 15");
        if (CURVES < 0 || CURVES > 1) $error("%m: CURVES must be 0 or 1");
        if (RECORD_BYTES < 1 || RECORD_BYTES > 255) $error("%m: RECORD_BYTES must be 1 .. 255");
        if (INPUT_INVERT_RESET < 0 || INPUT_INVERT_RESET > 31) $error("%m: INPUT_INVERT_RESET must be 0 .. 31");
        if (OUTPUT_INVERT_RESET < 0 || OUTPUT_INVERT_RESET > 65535) $error("%m: OUTPUT_INVERT_RESET must be 0 .. 65535");
    end

    /* verilator lint_off UNUSEDPARAM */
    `include "controller_regs.vh"
    /* verilator lint_on UNUSEDPARAM */

    // reset values: 0.5 us of pulse, set-up and hold (at least a clock), 20 kHz PWM
    localparam integer HALF_US = CLK_HZ / 2000000 > 0 ? CLK_HZ / 2000000 : 1;
    localparam integer PWM_CLOCKS = CLK_HZ / 20000 > 0 ? (CLK_HZ / 20000 > 65535 ? 65535 : CLK_HZ / 20000) : 1;
    localparam [31:0] TIMING_RESET = HALF_US;
    localparam [31:0] PERIOD_RESET = PWM_CLOCKS;
    localparam [31:0] ID      = 32'h494E5450;                   // "INTP"
    localparam [31:0] VERSION = {POS_W[7:0], W[7:0], RECORD_BYTES[7:0], 8'd1};
    localparam [31:0] BUILD0  = {PF[7:0], NW[7:0], FRAC[7:0], FEED_W[7:0]};
    localparam [31:0] BUILD1  = {TW[7:0], MW[7:0], ZW[7:0], LEN_W[7:0]};
    localparam [31:0] CLOCK   = CLK_HZ;
    localparam [15:0] QUEUE_BYTES = 16'd1 << QUEUE_AW;
    localparam [31:0] QUEUE_SIZE  = {7'd0, CURVES[0], QUEUE_AW[7:0], QUEUE_BYTES};

    wire [7:0] address = {wb_adr[7:2], 2'b00};
    wire       access  = wb_cyc & wb_stb & ~wb_ack;
    wire       is_data = address == REG_CMD_DATA[7:0];
    wire       done    = access & (~(wb_we & is_data) | data_ready);
    wire       write   = done & wb_we;

    assign data_write = access & wb_we & is_data & data_ready;
    assign data_word  = wb_dat_w;
    assign data_lanes = wb_sel;
    wire   control_write = write && address == REG_CONTROL[7:0];
    wire   clear_now     = control_write & wb_dat_w[2];    // STATUS.refused: a refusal in the same write wins
    assign arm_strobe    = control_write & wb_dat_w[3];    // (the probe latch: a touch in its clock is not taken)
    // QUANTUM and MOTION are taken only while nothing runs (the speed generator and the
    // S-curve filter hold them constant): a write while busy is refused and flagged
    wire   speed_write   = write && (address == REG_QUANTUM_LO[7:0] || address == REG_QUANTUM_HI[7:0] ||
                                     address == REG_MOTION[7:0] || address == REG_LIMIT_SCALE[7:0] ||
                                     address == REG_RATE_SCALE[7:0]);
    // fill would reset motion_top under a running program: it rises only while not busy,
    // or with abort in the same write (which flushes)
    wire   fill_refused  = control_write & wb_dat_w[5] & ~fill & busy & ~wb_dat_w[1];
    wire   speed_refused = speed_write & busy;
    // the position counters are set only at rest (homing), like the speed settings
    wire [2:0] position_address = {address == REG_POS_Z[7:0], address == REG_POS_Y[7:0],
                                   address == REG_POS_X[7:0]};
    wire   position_refused = write & |position_address & busy;
    assign position_write = {3{write & ~busy}} & position_address;
    assign position_value = wb_dat_w[POS_W-1:0];
    reg  [2:0] position_set;                        // STATUS.position_set, until the reset
    wire   refuse        = speed_refused | fill_refused | position_refused;
    reg    refused;                                 // STATUS.refused, until CONTROL.clear

    // positions sign-extended to 32 bits
    function [31:0] extended(input [POS_W-1:0] value);
        extended = {{(33 - POS_W){value[POS_W-1]}}, value[POS_W-2:0]};
    endfunction

    wire [63:0] quantum_wide = {{(64 - FEED_W){1'b0}}, quantum};
    wire [63:0] quantum_lo   = {quantum_wide[63:32], wb_dat_w};
    wire [63:0] quantum_hi   = {wb_dat_w, quantum_wide[31:0]};

    // The read-back table: word n at byte address 4n, 0x00 .. 0xFC (a mux tree on
    // wb_adr[7:2]; the generator keeps the map there); CMD_DATA, which is write-only,
    // and unknown addresses read 0.
    reg [64*32-1:0] words;
    always @* begin
        words = {(64*32){1'b0}};
        words[REG_ID[7:2] * 32 +: 32]             = ID;
        words[REG_VERSION[7:2] * 32 +: 32]        = VERSION;
        words[REG_BUILD0[7:2] * 32 +: 32]         = BUILD0;
        words[REG_BUILD1[7:2] * 32 +: 32]         = BUILD1;
        words[REG_CLOCK_HZ[7:2] * 32 +: 32]       = CLOCK;
        words[REG_QUEUE_SIZE[7:2] * 32 +: 32]     = QUEUE_SIZE;
        words[REG_STATUS[7:2] * 32 +: 32]         = {13'd0, position_set, records, refused, enable, probe_valid, stopped, busy, state};
        words[REG_ERROR[7:2] * 32 +: 32]          = {21'd0, error_limits, error_code};
        words[REG_QUEUE_FREE[7:2] * 32 +: 32]     = {free_records, free_bytes};
        words[REG_POS_X[7:2] * 32 +: 32]          = extended(pos_x);
        words[REG_POS_Y[7:2] * 32 +: 32]          = extended(pos_y);
        words[REG_POS_Z[7:2] * 32 +: 32]          = extended(pos_z);
        words[REG_PROBE_X[7:2] * 32 +: 32]        = extended(probe_x);
        words[REG_PROBE_Y[7:2] * 32 +: 32]        = extended(probe_y);
        words[REG_PROBE_Z[7:2] * 32 +: 32]        = extended(probe_z);
        words[REG_INPUTS[7:2] * 32 +: 32]         = {27'd0, inputs};
        words[REG_CONTROL[7:2] * 32 +: 32]        = {25'd0, probe_stop, fill, enable, 3'd0, hold};
        words[REG_OVERRIDE[7:2] * 32 +: 32]       = {24'd0, override_percent};
        words[REG_PULSE_WIDTH[7:2] * 32 +: 32]    = {{(32 - TW){1'b0}}, pulse_width};
        words[REG_DIR_SETUP[7:2] * 32 +: 32]      = {{(32 - TW){1'b0}}, dir_setup};
        words[REG_DIR_HOLD[7:2] * 32 +: 32]       = {{(32 - TW){1'b0}}, dir_hold};
        words[REG_QUANTUM_LO[7:2] * 32 +: 32]     = quantum_wide[31:0];
        words[REG_QUANTUM_HI[7:2] * 32 +: 32]     = quantum_wide[63:32];
        words[REG_MOTION[7:2] * 32 +: 32]         = {10'd0, rate_shift, 2'd0, limit_shift, jerk_shift, block_shift};
        words[REG_INPUT_INVERT[7:2] * 32 +: 32]   = {27'd0, input_invert};
        words[REG_SPINDLE_PERIOD[7:2] * 32 +: 32] = {16'd0, spindle_period};
        words[REG_OUTPUTS[7:2] * 32 +: 32]        = {duty, outputs};
        words[REG_LINK_FRAMES[7:2] * 32 +: 32]    = {link_duplicates, link_frames};
        words[REG_LINK_ERRORS[7:2] * 32 +: 32]    = {link_gaps, link_errors};
        words[REG_EXECUTED[7:2] * 32 +: 32]       = executed;
        words[REG_OUTPUT_INVERT[7:2] * 32 +: 32]  = {16'd0, output_invert};
        words[REG_INPUT_FILTER[7:2] * 32 +: 32]   = {11'd0, filter_mask, filter_period};
        words[REG_SPINDLE_OVERRIDE[7:2] * 32 +: 32] = {22'd0, spindle_scale};
        words[REG_LIMIT_SCALE[7:2] * 32 +: 32]    = limit_scale;
        words[REG_RATE_SCALE[7:2] * 32 +: 32]     = rate_scale;
    end
    wire [31:0] value = words[address[7:2] * 32 +: 32];

    always @(posedge clk) begin
        if (rst) begin
            wb_ack   <= 1'b0;
            wb_dat_r <= 32'd0;
            abort_strobe <= 1'b0;
            clear_strobe <= 1'b0;
        end else begin
            wb_ack   <= done;
            wb_dat_r <= done & ~wb_we ? value : 32'd0;
            // registered, so that no decode of the bus reaches what they reset (an abort
            // resets motion_top: thousands of flip-flops); clear with it, so that an error
            // in the access cycle is cleared by an abort + clear as one in the ack cycle is
            // discarded by the abort
            abort_strobe <= control_write & wb_dat_w[1];
            clear_strobe <= clear_now;
        end
    end

    always @(posedge clk) begin
        if (rst) begin
            hold             <= 1'b0;
            enable           <= 1'b0;
            fill             <= 1'b0;
            probe_stop       <= 1'b0;
            override_percent <= 8'd100;
            pulse_width      <= TIMING_RESET[TW-1:0];
            dir_setup        <= TIMING_RESET[TW-1:0];
            dir_hold         <= TIMING_RESET[TW-1:0];
            quantum          <= {{(FEED_W-1){1'b0}}, 1'b1};
            block_shift      <= 4'd2;
            jerk_shift       <= 4'd0;
            limit_scale      <= 32'd0;
            limit_shift      <= 6'd0;
            rate_scale       <= 32'd0;
            rate_shift       <= 6'd0;
            input_invert     <= INPUT_INVERT_RESET[4:0];
            output_invert    <= OUTPUT_INVERT_RESET[15:0];
            filter_period    <= 16'd0;
            filter_mask      <= 5'b11111;
            spindle_period   <= PERIOD_RESET[15:0];
            spindle_scale    <= 10'd256;
            refused          <= 1'b0;
            position_set     <= 3'b000;
        end else begin
            refused <= refuse | (refused & ~clear_now);
            position_set <= position_set | position_write;
            if (hold_set)
                hold <= 1'b1;
            if (write & ~speed_refused) begin
                case (address)
                    REG_CONTROL[7:0]: begin
                        hold   <= wb_dat_w[0] | hold_set;   // a touch or pause in this clock wins
                        enable <= wb_dat_w[4];
                        fill   <= wb_dat_w[5] & ~fill_refused;
                        probe_stop <= wb_dat_w[6];
                    end
                    REG_OVERRIDE[7:0]:       override_percent <= wb_dat_w[7:0];
                    REG_PULSE_WIDTH[7:0]:    pulse_width <= wb_dat_w[TW-1:0];
                    REG_DIR_SETUP[7:0]:      dir_setup <= wb_dat_w[TW-1:0];
                    REG_DIR_HOLD[7:0]:       dir_hold <= wb_dat_w[TW-1:0];
                    REG_QUANTUM_LO[7:0]:     quantum <= quantum_lo[FEED_W-1:0];
                    REG_QUANTUM_HI[7:0]:     quantum <= quantum_hi[FEED_W-1:0];
                    REG_MOTION[7:0]: begin
                        {jerk_shift, block_shift} <= wb_dat_w[7:0];
                        limit_shift <= wb_dat_w[13:8];
                        rate_shift  <= wb_dat_w[21:16];
                    end
                    REG_LIMIT_SCALE[7:0]:    limit_scale <= wb_dat_w;
                    REG_RATE_SCALE[7:0]:     rate_scale <= wb_dat_w;
                    REG_INPUT_INVERT[7:0]:   input_invert <= wb_dat_w[4:0];
                    REG_OUTPUT_INVERT[7:0]:  output_invert <= wb_dat_w[15:0];
                    REG_INPUT_FILTER[7:0]:   {filter_mask, filter_period} <= wb_dat_w[20:0];
                    REG_SPINDLE_PERIOD[7:0]: spindle_period <= wb_dat_w[15:0];
                    REG_SPINDLE_OVERRIDE[7:0]: spindle_scale <= wb_dat_w[9:0];
                    default: ;
                endcase
            end
        end
    end

    wire unused = &{1'b0, wb_adr[1:0], quantum_lo, quantum_hi, wb_dat_w};
endmodule
`default_nettype wire
