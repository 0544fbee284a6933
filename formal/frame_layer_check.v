// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Formal harness of the link's frame layer (formal/frame_layer.sby): any byte
// sequence at frame_rx's byte interface (any byte in any clock, framing
// errors, reset at any time), any credit, any Wishbone busy, any stalls of the
// record consumer.  A reference parser here splits the byte stream into
// frames as docs/link-protocol.md defines them (SYNC hunt, LEN > LMAX
// dropped, a byte lost or TIMEOUT_CLOCKS without a byte drop the frame) and
// computes each frame's CRC itself.  Properties:
//   accept:  E (`expected`) changes only to E + 1, and only right after a
//            sequenced frame (DATA, or WRITE with LEN 6) whose SEQ is E and
//            whose CRC is good (not checked with FREE_CRC: formal/crc16_free.v); that frame is ACKed; a WRITE then gives exactly
//            one write_req with its address and value;
//   once:    an ACK that does not advance E answers an old frame (SEQ behind
//            E): a duplicate is never executed again;
//   release: the record stream is exactly the accepted DATA payloads, byte
//            for byte and in order: no byte before its frame is accepted, none
//            twice, none invented, and every byte of an accepted frame
//            released before the next frame is accepted (never lost).
module frame_layer_check #(
    parameter integer LMAX           = 6,
    parameter integer TIMEOUT_CLOCKS = 4
) (
    input wire        clk,
    input wire        rst,
    input wire        in_valid,
    input wire [7:0]  in_data,
    input wire        in_error,
    input wire [15:0] queue_free,
    input wire        wb_busy,
    input wire        cmd_ready
);
    localparam integer TW = $clog2(TIMEOUT_CLOCKS + 1);
    localparam integer PW = LMAX > 6 ? LMAX : 6;      // payload bytes held (a WRITE has 6)
    localparam [7:0] T_DATA = 8'h02, T_WRITE = 8'h04;

    wire        cmd_valid, rsp_valid, read_req, write_req;
    wire        ev_executed, ev_duplicate, ev_error, ev_gap;
    wire [7:0]  cmd_data, expected, req_seq;
    wire [2:0]  rsp_reason;
    wire [15:0] req_addr;
    wire [31:0] req_value;

    frame_rx #(.LMAX(LMAX), .TIMEOUT_CLOCKS(TIMEOUT_CLOCKS)) dut (
        .clk(clk), .rst(rst), .in_valid(in_valid), .in_data(in_data), .in_error(in_error),
        .queue_free(queue_free), .wb_busy(wb_busy), .cmd_valid(cmd_valid), .cmd_data(cmd_data),
        .cmd_ready(cmd_ready), .expected(expected), .rsp_valid(rsp_valid), .rsp_reason(rsp_reason),
        .read_req(read_req), .write_req(write_req), .req_addr(req_addr), .req_value(req_value),
        .req_seq(req_seq), .ev_executed(ev_executed), .ev_duplicate(ev_duplicate), .ev_error(ev_error),
        .ev_gap(ev_gap)
    );

`ifdef FORMAL
    function [15:0] crc_step(input [15:0] value, input [7:0] byte_in);
        integer i;
        reg [15:0] c;
        begin
            c = value ^ {byte_in, 8'h00};
            for (i = 0; i < 8; i = i + 1)
                c = c[15] ? {c[14:0], 1'b0} ^ 16'h1021 : {c[14:0], 1'b0};
            crc_step = c;
        end
    endfunction

    reg f_past_valid = 1'b0;
    always @(posedge clk) f_past_valid <= 1'b1;
    always @(*) if (!f_past_valid) assume (rst);
    always @(*) assume (!(in_valid && in_error));       // the UART gives a byte or an error

    // ---- reference parser -------------------------------------------------------------
    localparam [2:0] R_HUNT = 3'd0, R_LEN = 3'd1, R_TYPE = 3'd2, R_SEQ = 3'd3, R_PAYLOAD = 3'd4,
                     R_CRC_HI = 3'd5, R_CRC_LO = 3'd6;
    reg [2:0]        r_state;
    reg [7:0]        r_len, r_type, r_seq, r_index, r_crc_hi;
    reg [15:0]       r_crc;
    reg [TW-1:0]     r_idle;
    reg [8*PW-1:0] r_payload;
    // the frame that ended in the previous clock (frame_rx decides on it now)
    reg              f_check = 1'b0;
    reg [7:0]        f_type, f_seq, f_len;
    reg              f_crc_ok;
    reg [8*PW-1:0] f_payload;
    wire [47:0]      f_write = f_payload[47:0];    // a WRITE's address and value

    wire r_in_frame = r_state != R_HUNT;
    integer b;
    always @(posedge clk) begin
        f_check <= 1'b0;
        if (rst) begin
            r_state <= R_HUNT;
            r_idle  <= {TW{1'b0}};
        end else if (!r_in_frame) begin
            if (in_valid && in_data == 8'hA5) begin
                r_state <= R_LEN;
                r_crc   <= 16'hFFFF;
                r_idle  <= {TW{1'b0}};
            end
        end else if (in_error || (!in_valid && r_idle == TIMEOUT_CLOCKS - 1)) begin
            r_state <= R_HUNT;
        end else if (!in_valid) begin
            r_idle <= r_idle + 1'b1;
        end else begin
            r_idle <= {TW{1'b0}};
            if (r_state <= R_PAYLOAD)
                r_crc <= crc_step(r_crc, in_data);
            case (r_state)
                R_LEN: begin
                    r_len     <= in_data;
                    r_payload <= {8*PW{1'b0}};
                    r_state   <= in_data > LMAX ? R_HUNT : R_TYPE;
                end
                R_TYPE: begin
                    r_type  <= in_data;
                    r_state <= R_SEQ;
                end
                R_SEQ: begin
                    r_seq   <= in_data;
                    r_index <= 8'd0;
                    r_state <= r_len == 8'd0 ? R_CRC_HI : R_PAYLOAD;
                end
                R_PAYLOAD: begin
                    for (b = 0; b < LMAX; b = b + 1)
                        if (r_index == b)
                            r_payload[8*b +: 8] <= in_data;
                    r_index   <= r_index + 1'b1;
                    if (r_index == r_len - 1'b1)
                        r_state <= R_CRC_HI;
                end
                R_CRC_HI: begin
                    r_crc_hi <= in_data;
                    r_state  <= R_CRC_LO;
                end
                default: begin
                    r_state   <= R_HUNT;
                    f_check   <= 1'b1;
                    f_type    <= r_type;
                    f_seq     <= r_seq;
                    f_len     <= r_len;
                    f_payload <= r_payload;
                    f_crc_ok  <= r_crc == {r_crc_hi, in_data};
                end
            endcase
        end
    end

    // ---- ghost of the accepted payload being released -------------------------------
    reg [8*PW-1:0] g_payload;
    reg [7:0]        g_len, g_out;
    reg [3:0]        g_accepts;                        // for the covers
    reg [7:0]        p_expected;                       // the previous clock's values
    reg              p_rst = 1'b1, p_check = 1'b0;
    wire             take     = cmd_valid && cmd_ready;
    reg  [7:0]       g_byte;                           // g_payload's byte number g_out
    always @(*) begin
        g_byte = 8'd0;
        for (b = 0; b < LMAX; b = b + 1)
            if (g_out == b)
                g_byte = g_payload[8*b +: 8];
    end
    wire             advanced = f_past_valid && !p_rst && expected != p_expected;

    always @(posedge clk) begin
        p_expected <= expected;
        p_rst      <= rst;
        p_check    <= f_check;
        if (rst) begin
            g_len     <= 8'd0;
            g_out     <= 8'd0;
            g_accepts <= 4'd0;
        end else begin
            if (take)
                g_out <= g_out + 1'b1;
            if (advanced && f_type == T_DATA) begin
                g_payload <= f_payload;
                g_len     <= f_len;
                g_out     <= 8'd0;
            end
            if (advanced && g_accepts != 4'hF)
                g_accepts <= g_accepts + 1'b1;
        end
    end

    // (f_type .. f_payload still describe the frame decided on in the previous clock:
    // the next frame cannot end within two clocks)
    always @(*) begin
        if (f_past_valid && !rst && !p_rst) begin
            // release: only bytes of the accepted payload, in order, each once
            if (cmd_valid) begin
                assert (g_out < g_len);
                assert (cmd_data == g_byte);
            end
            assert (g_out <= g_len);
            if (advanced) begin
                // accept: only the frame just ended, sequenced, good CRC, SEQ = E
                assert (p_check);
`ifndef FREE_CRC
                assert (f_crc_ok);
`endif
                assert (f_type == T_DATA || (f_type == T_WRITE && f_len == 8'd6));
                assert (f_seq == p_expected);
                assert (expected == p_expected + 8'd1);
                assert (rsp_valid && rsp_reason == 3'd0);
                assert (write_req == (f_type == T_WRITE));
                // never lost: the previous payload was released completely
                assert (g_out == g_len);
                assert (!cmd_valid);
            end
            if (write_req)
                assert (advanced && {req_value, req_addr} == f_write);
            // once: an ACK that does not advance E answers HELLO or an old frame
            if (rsp_valid && rsp_reason == 3'd0 && !advanced)
                assert (p_check && (f_type == 8'h01 || f_seq - expected >= 8'd128));
        end
    end

    // covers: two DATA payloads accepted and released; a duplicate ACKed; a WRITE executed
    always @(posedge clk) begin
        if (!rst) begin
            cover (g_accepts == 4'd2 && g_len == 8'd2 && g_out == 8'd2);
            cover (rsp_valid && rsp_reason == 3'd0 && !advanced && f_type == T_DATA && g_accepts == 4'd1);
            if (LMAX >= 6)
                cover (write_req);                     // (WRITE frames need LMAX >= 6)
        end
    end
`endif
endmodule
`default_nettype wire
