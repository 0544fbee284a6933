// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Frame transmitter of the UART link (docs/link-protocol.md): sends the
// controller's answers as frames SYNC 0xA5 | LEN | TYPE | SEQ | payload |
// CRC-16/CCITT-FALSE (over LEN .. payload, high byte first), one byte at a
// time to the UART transmitter (out_valid/out_ready).
//   ACK   0x81, SEQ = E:    free bytes (2, LE), state, error
//   NAK   0x82, SEQ = E:    reason, free bytes (2, LE)
//   REPLY 0x83, SEQ echoed: address (2, LE), value (4, LE)
// Answers are coalesced: one ACK/NAK is pending at most (a newer one replaces
// it) plus one REPLY (a newer one replaces it); when the line is free the
// REPLY goes first, then the ACK/NAK.  E, the free bytes, state and error are
// taken when the frame starts, so an answer reports the newest state.
module frame_tx (
    input  wire        clk,
    input  wire        rst,
    input  wire        ans_valid,       // one clock: answer with an ACK (reason 0) or a NAK
    input  wire [2:0]  ans_reason,      // 0 ACK, 1 .. 4 NAK reason
    input  wire        reply_valid,     // one clock: answer a READ
    input  wire [15:0] reply_addr,
    input  wire [31:0] reply_value,
    input  wire [7:0]  reply_seq,       // the READ's SEQ
    input  wire [7:0]  expected,        // E, sent as the SEQ of ACK and NAK
    input  wire [15:0] queue_free,
    input  wire [7:0]  status_state,
    input  wire [7:0]  status_error,
    output wire        out_valid,       // byte stream to the UART transmitter
    output wire [7:0]  out_data,
    input  wire        out_ready
);
    localparam [7:0] SYNC = 8'hA5;
    localparam [7:0] T_ACK = 8'h81, T_NAK = 8'h82, T_REPLY = 8'h83;

    reg        ans_pend_q, reply_pend_q;
    reg [2:0]  ans_reason_q;
    reg [15:0] reply_addr_q;
    reg [31:0] reply_value_q;
    reg [7:0]  reply_seq_q;

    reg        sending_q;
    reg [3:0]  index_q;                 // byte of the frame on out_data
    reg [7:0]  len_q, type_q, seq_q;
    reg [47:0] payload_q;               // payload bytes, first in bits 7:0

    wire [15:0] crc;
    wire [3:0]  last_payload = 4'd3 + len_q[3:0];   // index of the last payload byte
    wire        taken        = sending_q && out_ready;
    wire        start        = !sending_q && (reply_pend_q || ans_pend_q);
    wire        start_reply  = start && reply_pend_q;
    wire        start_ans    = start && !reply_pend_q;

    reg [7:0] byte_out;
    always @(*) begin
        if (index_q == 4'd0)
            byte_out = SYNC;
        else if (index_q == 4'd1)
            byte_out = len_q;
        else if (index_q == 4'd2)
            byte_out = type_q;
        else if (index_q == 4'd3)
            byte_out = seq_q;
        else if (index_q <= last_payload)
            byte_out = payload_q[7:0];
        else if (index_q == last_payload + 4'd1)
            byte_out = crc[15:8];
        else
            byte_out = crc[7:0];
    end

    assign out_valid = sending_q;
    assign out_data  = byte_out;

    crc16 u_crc (.clk(clk), .rst(rst), .clear(start), .valid(taken && index_q != 4'd0 && index_q <= last_payload),
                 .data(byte_out), .crc(crc));

    always @(posedge clk) begin
        if (rst) begin
            ans_pend_q    <= 1'b0;
            reply_pend_q  <= 1'b0;
            ans_reason_q  <= 3'd0;
            reply_addr_q  <= 16'd0;
            reply_value_q <= 32'd0;
            reply_seq_q   <= 8'd0;
            sending_q     <= 1'b0;
            index_q       <= 4'd0;
            len_q         <= 8'd0;
            type_q        <= 8'd0;
            seq_q         <= 8'd0;
            payload_q     <= 48'd0;
        end else begin
            if (start_reply) begin
                reply_pend_q <= 1'b0;
                len_q        <= 8'd6;
                type_q       <= T_REPLY;
                seq_q        <= reply_seq_q;
                payload_q    <= {reply_value_q, reply_addr_q};
            end
            if (start_ans) begin
                ans_pend_q <= 1'b0;
                seq_q      <= expected;
                if (ans_reason_q == 3'd0) begin
                    len_q     <= 8'd4;
                    type_q    <= T_ACK;
                    payload_q <= {16'd0, status_error, status_state, queue_free};
                end else begin
                    len_q     <= 8'd3;
                    type_q    <= T_NAK;
                    payload_q <= {24'd0, queue_free, 5'd0, ans_reason_q};
                end
            end
            if (start) begin
                sending_q <= 1'b1;
                index_q   <= 4'd0;
            end
            if (taken) begin
                index_q <= index_q + 1'b1;
                if (index_q >= 4'd4 && index_q <= last_payload)
                    payload_q <= {8'd0, payload_q[47:8]};
                if (index_q == last_payload + 4'd2)
                    sending_q <= 1'b0;
            end
            if (ans_valid) begin
                ans_pend_q   <= 1'b1;
                ans_reason_q <= ans_reason;
            end
            if (reply_valid) begin
                reply_pend_q  <= 1'b1;
                reply_addr_q  <= reply_addr;
                reply_value_q <= reply_value;
                reply_seq_q   <= reply_seq;
            end
        end
    end
endmodule
`default_nettype wire
