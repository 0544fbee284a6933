// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// The controller's serial link (docs/link-protocol.md): UART 8N1 at BAUD,
// frames with CRC-16, sequence numbers and credits.  Accepted DATA payloads
// leave as the record byte stream (cmd_valid/cmd_data/cmd_ready); READ and
// WRITE frames become Wishbone B4 classic accesses (one at a time; WRITE
// executed exactly once, READ answered with a REPLY); every frame is
// answered with ACK, NAK or REPLY (frame_tx).  Addresses above 0xFF read 0
// and ignore writes without a bus access.  The counters are the LINK_FRAMES
// and LINK_ERRORS registers' fields (16 bits, wrapping).
module uart_link #(
    parameter integer CLK_HZ        = 12000000,  // clock frequency, Hz
    parameter integer BAUD          = 115200,    // bits per second (115200 .. 3000000; CLK_HZ / BAUD >= 4)
    parameter integer LMAX          = 128,       // largest payload of a received frame, bytes (1 .. 255)
    parameter integer FRAME_TIMEOUT = 32         // byte times without a byte that drop a frame (>= 1)
) (
    input  wire        clk,
    input  wire        rst,
    input  wire        rx,
    output wire        tx,
    output wire        cmd_valid,               // record byte stream to the controller
    output wire [7:0]  cmd_data,
    input  wire        cmd_ready,
    input  wire [15:0] queue_free,              // free bytes of the segment queue
    output wire [7:0]  wbm_adr,                 // Wishbone master
    output wire [31:0] wbm_dat_w,
    output wire        wbm_we,
    output wire [3:0]  wbm_sel,
    output wire        wbm_stb,
    output wire        wbm_cyc,
    input  wire [31:0] wbm_dat_r,
    input  wire        wbm_ack,
    input  wire [7:0]  status_state,            // for the ACK's payload
    input  wire [7:0]  status_error,
    output wire [15:0] link_frames,             // frames executed
    output wire [15:0] link_duplicates,         // duplicates (acknowledged, not executed)
    output wire [15:0] link_errors,             // bad CRC, LEN, TYPE, truncated
    output wire [15:0] link_gaps                // sequence gaps and frames refused for credit
);
    localparam integer CLKS_PER_BIT   = (CLK_HZ + BAUD / 2) / BAUD;
    localparam integer TIMEOUT_CLOCKS = FRAME_TIMEOUT * 10 * CLKS_PER_BIT;
    initial begin
        if (BAUD < 115200 || BAUD > 3000000) $error("%m: BAUD must be 115200 .. 3000000");
        if (CLKS_PER_BIT < 4) $error("%m: CLK_HZ / BAUD must be at least 4");
        if (LMAX < 1 || LMAX > 255) $error("%m: LMAX must be 1 .. 255");
        if (FRAME_TIMEOUT < 1) $error("%m: FRAME_TIMEOUT must be at least 1");
    end

    wire [7:0]  rx_data, tx_data, expected, req_seq;
    wire        rx_valid, rx_error, tx_valid, tx_ready;
    wire        rsp_valid, read_req, write_req;
    wire        ev_executed, ev_duplicate, ev_error, ev_gap;
    wire [2:0]  rsp_reason;
    wire [15:0] req_addr;
    wire [31:0] req_value;

    reg         cyc_q, we_q, reply_q;
    reg [15:0]  addr_q;
    reg [31:0]  dat_w_q, reply_value_q;
    reg [7:0]   seq_q;
    reg [15:0]  frames_q, duplicates_q, errors_q, gaps_q;

    uart_rx #(.CLKS_PER_BIT(CLKS_PER_BIT)) u_rx (
        .clk(clk), .rst(rst), .rx(rx), .data(rx_data), .valid(rx_valid), .frame_error(rx_error)
    );

    frame_rx #(.LMAX(LMAX), .TIMEOUT_CLOCKS(TIMEOUT_CLOCKS)) u_frame_rx (
        .clk(clk), .rst(rst), .in_valid(rx_valid), .in_data(rx_data), .in_error(rx_error),
        .queue_free(queue_free), .wb_busy(cyc_q),
        .cmd_valid(cmd_valid), .cmd_data(cmd_data), .cmd_ready(cmd_ready), .expected(expected),
        .rsp_valid(rsp_valid), .rsp_reason(rsp_reason), .read_req(read_req), .write_req(write_req),
        .req_addr(req_addr), .req_value(req_value), .req_seq(req_seq),
        .ev_executed(ev_executed), .ev_duplicate(ev_duplicate), .ev_error(ev_error), .ev_gap(ev_gap)
    );

    frame_tx u_frame_tx (
        .clk(clk), .rst(rst), .ans_valid(rsp_valid), .ans_reason(rsp_reason),
        .reply_valid(reply_q), .reply_addr(addr_q), .reply_value(reply_value_q), .reply_seq(seq_q),
        .expected(expected), .queue_free(queue_free), .status_state(status_state),
        .status_error(status_error), .out_valid(tx_valid), .out_data(tx_data), .out_ready(tx_ready)
    );

    uart_tx #(.CLKS_PER_BIT(CLKS_PER_BIT)) u_tx (
        .clk(clk), .rst(rst), .data(tx_data), .valid(tx_valid), .ready(tx_ready), .tx(tx)
    );

    assign wbm_adr   = addr_q[7:0];
    assign wbm_dat_w = dat_w_q;
    assign wbm_we    = we_q;
    assign wbm_sel   = 4'hF;
    assign wbm_stb   = cyc_q;
    assign wbm_cyc   = cyc_q;

    assign link_frames     = frames_q;
    assign link_duplicates = duplicates_q;
    assign link_errors     = errors_q;
    assign link_gaps       = gaps_q;

    // Wishbone master: one access at a time (frame_rx refuses READ/WRITE while cyc is high).
    wire on_bus = req_addr[15:8] == 8'd0;
    always @(posedge clk) begin
        if (rst) begin
            cyc_q         <= 1'b0;
            we_q          <= 1'b0;
            reply_q       <= 1'b0;
            addr_q        <= 16'd0;
            dat_w_q       <= 32'd0;
            reply_value_q <= 32'd0;
            seq_q         <= 8'd0;
        end else begin
            reply_q <= 1'b0;
            if (read_req || write_req) begin
                addr_q  <= req_addr;
                dat_w_q <= req_value;
                seq_q   <= req_seq;
                we_q    <= write_req;
                cyc_q   <= on_bus;
                if (read_req && !on_bus) begin
                    reply_value_q <= 32'd0;         // off the 8-bit bus: reads 0
                    reply_q       <= 1'b1;
                end
            end else if (cyc_q && wbm_ack) begin
                cyc_q <= 1'b0;
                if (!we_q) begin
                    reply_value_q <= wbm_dat_r;
                    reply_q       <= 1'b1;
                end
            end
        end
    end

    always @(posedge clk) begin
        if (rst) begin
            frames_q     <= 16'd0;
            duplicates_q <= 16'd0;
            errors_q     <= 16'd0;
            gaps_q       <= 16'd0;
        end else begin
            frames_q     <= frames_q + {15'd0, ev_executed};
            duplicates_q <= duplicates_q + {15'd0, ev_duplicate};
            errors_q     <= errors_q + {15'd0, ev_error};
            gaps_q       <= gaps_q + {15'd0, ev_gap};
        end
    end
endmodule
`default_nettype wire
