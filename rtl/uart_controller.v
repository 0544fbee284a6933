// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// The portable board-level design: the UART link (uart_link: frames, CRC, sequencing,
// credits, a Wishbone master) and the CNC controller (controller) joined, with eight
// status LEDs.  A board's top adds its clock (PLL) and power-on reset around it.
//   uart_rx -> uart_link -> record bytes -> controller -> step/dir, spindle, coolant
//                        -> Wishbone (READ/WRITE frames) -> controller's registers
//   uart_tx <- ACK/NAK/REPLY frames (queue free bytes, state, error)
// LEDs: [2:0] state (0 IDLE, 1 RUN, 2 HOLDING, 3 HELD, 4 ALARM), [3] moving (RUN or
// HOLDING), [4] alarm, [5] spindle on, [6] enable,
// [7] heartbeat (toggles about twice a second).
module uart_controller #(
    parameter integer CLK_HZ        = 50000000, // clock frequency, Hz (>= 4 * BAUD)
    parameter integer BAUD          = 115200,   // UART bit rate (uart_link: 115200 .. 3000000)
    parameter integer FRAME_TIMEOUT = 32,       // byte-times before a truncated frame is dropped (>= 1)
    parameter integer W        = 32,            // command field width (controller)
    parameter integer FEED_W   = 34,            // speed word width (controller)
    parameter integer FRAC     = 32,            // fraction bits (controller)
    parameter integer NW       = 24,            // speed in quanta width (controller)
    parameter integer PF       = 16,            // rate fraction bits (controller)
    parameter integer LEN_W    = 66,            // move length width (controller)
    parameter integer ZW       = 68,            // braking budget width (controller)
    parameter integer MW       = 12,            // S-curve depth (controller)
    parameter integer TW       = 16,            // step timing width (controller)
    parameter integer POS_W    = 32,            // position counter width (controller)
    parameter integer QDEPTH   = 8,             // motion_top's queue depth (controller)
    parameter integer QLW      = 4,             // motion_top's queue level width (controller)
    parameter integer SDEPTH   = 2,             // motion_top's step buffer depth (controller)
    parameter integer CURVES   = 1,             // curve core present (controller; 0 or 1)
    parameter integer QUEUE_AW = 12,            // segment queue: 2^QUEUE_AW bytes (controller)
    parameter integer INPUT_INVERT_RESET  = 0,  // INPUT_INVERT after rst (controller; 0 .. 31)
    parameter integer OUTPUT_INVERT_RESET = 0   // OUTPUT_INVERT after rst (controller; 0 .. 65535)
) (
    input  wire       clk,
    input  wire       rst,
    input  wire       uart_rx,
    output wire       uart_tx,
    output wire [2:0] step,
    output wire [2:0] dir,
    output wire       enable,
    input  wire       estop,
    input  wire [2:0] limit,
    input  wire       probe,
    output wire       spindle_on,
    output wire       spindle_ccw,
    output wire       spindle_pwm,
    output wire       mist,
    output wire       flood,
    output wire [3:0] dout,
    output wire [7:0] led
);
    initial begin
        if (BAUD < 1 || CLK_HZ < 4 * BAUD) $error("%m: need BAUD >= 1 and CLK_HZ >= 4 * BAUD");
        if (FRAME_TIMEOUT < 1) $error("%m: FRAME_TIMEOUT must be at least 1");
    end

    wire        cmd_valid, cmd_ready;
    wire [7:0]  cmd_data;
    wire [15:0] queue_free;
    wire [7:0]  wb_adr;
    wire [31:0] wb_dat_w, wb_dat_r;
    wire [3:0]  wb_sel;
    wire        wb_we, wb_stb, wb_cyc, wb_ack;
    wire [7:0]  status_state, status_error;
    wire [15:0] link_frames, link_duplicates, link_errors, link_gaps;
    wire        enable_state, spindle_state;    // logical (the LEDs), before OUTPUT_INVERT

    uart_link #(.CLK_HZ(CLK_HZ), .BAUD(BAUD), .LMAX(128), .FRAME_TIMEOUT(FRAME_TIMEOUT)) u_link (
        .clk(clk), .rst(rst), .rx(uart_rx), .tx(uart_tx),
        .cmd_valid(cmd_valid), .cmd_data(cmd_data), .cmd_ready(cmd_ready), .queue_free(queue_free),
        .wbm_adr(wb_adr), .wbm_dat_w(wb_dat_w), .wbm_we(wb_we), .wbm_sel(wb_sel), .wbm_stb(wb_stb),
        .wbm_cyc(wb_cyc), .wbm_dat_r(wb_dat_r), .wbm_ack(wb_ack),
        .status_state(status_state), .status_error(status_error),
        .link_frames(link_frames), .link_duplicates(link_duplicates), .link_errors(link_errors),
        .link_gaps(link_gaps)
    );

    controller #(.CLK_HZ(CLK_HZ), .W(W), .FEED_W(FEED_W), .FRAC(FRAC), .NW(NW), .PF(PF), .LEN_W(LEN_W),
                 .ZW(ZW), .MW(MW), .TW(TW), .POS_W(POS_W), .QDEPTH(QDEPTH), .QLW(QLW), .SDEPTH(SDEPTH),
                 .CURVES(CURVES), .QUEUE_AW(QUEUE_AW), .INPUT_INVERT_RESET(INPUT_INVERT_RESET),
                 .OUTPUT_INVERT_RESET(OUTPUT_INVERT_RESET)) u_controller (
        .clk(clk), .rst(rst), .cmd_valid(cmd_valid), .cmd_data(cmd_data), .cmd_ready(cmd_ready),
        .queue_free(queue_free),
        .wb_adr(wb_adr), .wb_dat_w(wb_dat_w), .wb_dat_r(wb_dat_r), .wb_we(wb_we), .wb_sel(wb_sel),
        .wb_stb(wb_stb), .wb_cyc(wb_cyc), .wb_ack(wb_ack),
        .link_frames(link_frames), .link_duplicates(link_duplicates), .link_errors(link_errors),
        .link_gaps(link_gaps), .status_state(status_state), .status_error(status_error),
        .step(step), .dir(dir), .enable(enable), .estop(estop), .limit(limit), .probe(probe),
        .spindle_on(spindle_on), .spindle_ccw(spindle_ccw), .spindle_pwm(spindle_pwm),
        .mist(mist), .flood(flood), .dout(dout), .enable_state(enable_state), .spindle_state(spindle_state)
    );

    // heartbeat: bit HB of a free-running counter toggles about every 0.25 s
    localparam integer HB = CLK_HZ >= 8 ? $clog2(CLK_HZ / 4) : 1;
    reg [HB:0] beat;
    always @(posedge clk) begin
        if (rst)
            beat <= {(HB+1){1'b0}};
        else
            beat <= beat + 1'b1;
    end

    wire [2:0] state = status_state[2:0];
    wire       moving = state == 3'd1 || state == 3'd2;
    assign led = {beat[HB], enable_state, spindle_state, state == 3'd4, moving, state};
    wire unused = &{1'b0, status_state[7:3]};
endmodule
`default_nettype wire
