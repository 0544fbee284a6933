// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Frame receiver of the UART link (docs/link-protocol.md): hunts for SYNC
// (0xA5), reads LEN, TYPE, SEQ, the payload and the CRC-16/CCITT-FALSE
// (over LEN .. payload, high byte first), and applies the sequencing rules.
// A DATA payload is written into an LMAX-byte buffer (block RAM, read
// synchronously) and released byte by byte on cmd_valid/cmd_ready only after
// the frame was accepted: CRC good, SEQ equal to the expected number E, LEN
// within the free bytes of the segment queue (`queue_free`), and nothing else
// busy (the previous payload released, no Wishbone access pending).  READ
// and WRITE payloads are held in registers and handed to the link's
// Wishbone master (read_req, write_req).  Every complete or dropped frame
// gives one `rsp_valid` with the answer: reason 0 = ACK, 1..4 = NAK reason
// (a READ that is executed gives no answer here: the link sends a REPLY).
// Dropped frames: LEN > LMAX (at once), a byte with a framing error, no next
// byte within TIMEOUT_CLOCKS, a bad CRC.  The hunt resumes after the dropped
// part; bytes before the next SYNC are skipped.
module frame_rx #(
    parameter integer LMAX           = 128,     // largest payload, bytes (1 .. 255)
    parameter integer TIMEOUT_CLOCKS = 33280    // clocks without a byte that drop a frame (>= 2)
) (
    input  wire        clk,
    input  wire        rst,
    input  wire        in_valid,        // one clock: `in_data` is the next byte of the line
    input  wire [7:0]  in_data,
    input  wire        in_error,        // one clock: a byte was lost (framing error)
    input  wire [15:0] queue_free,      // free bytes of the segment queue (the credit)
    input  wire        wb_busy,         // the link's Wishbone access is not finished
    output wire        cmd_valid,       // the released record byte stream
    output wire [7:0]  cmd_data,
    input  wire        cmd_ready,
    output wire [7:0]  expected,        // E: the next sequence number expected
    output wire        rsp_valid,       // one clock: answer the frame just ended
    output wire [2:0]  rsp_reason,      // 0 ACK, 1 bad CRC/LEN/truncated, 2 gap, 3 no credit, 4 bad TYPE/LEN
    output wire        read_req,        // one clock: READ of req_addr (answer with a REPLY, SEQ req_seq)
    output wire        write_req,       // one clock: WRITE of req_value to req_addr
    output wire [15:0] req_addr,
    output wire [31:0] req_value,
    output wire [7:0]  req_seq,
    output wire        ev_executed,     // one clock each: a frame executed (HELLO, READ, new DATA/WRITE),
    output wire        ev_duplicate,    // a duplicate (ACKed, not executed),
    output wire        ev_error,        // a frame dropped or refused for CRC, LEN, TYPE, framing or timeout,
    output wire        ev_gap           // a sequence gap or a frame refused for credit/busy
);
    localparam integer AW = LMAX > 1 ? $clog2(LMAX) : 1;
    localparam integer TW = $clog2(TIMEOUT_CLOCKS + 1);
    initial begin
        if (LMAX < 1 || LMAX > 255) $error("%m: LMAX must be 1 .. 255");
        if (TIMEOUT_CLOCKS < 2) $error("%m: TIMEOUT_CLOCKS must be at least 2");
    end

    localparam [7:0] SYNC = 8'hA5;
    localparam [7:0] T_HELLO = 8'h01, T_DATA = 8'h02, T_READ = 8'h03, T_WRITE = 8'h04;
    localparam [2:0] HUNT = 3'd0, LEN = 3'd1, TYPE = 3'd2, SEQ = 3'd3, PAYLOAD = 3'd4,
                     CRC_HI = 3'd5, CRC_LO = 3'd6, CHECK = 3'd7;
    localparam [2:0] ACK = 3'd0, NAK_FRAME = 3'd1, NAK_GAP = 3'd2, NAK_CREDIT = 3'd3, NAK_TYPE = 3'd4;

    reg [2:0]    state_q;
    reg [7:0]    len_q, type_q, seq_q, index_q, expected_q;
    reg          refused_q;                 // a payload byte came while the buffer was draining
    reg [15:0]   addr_q;
    reg [31:0]   value_q;
    reg [TW-1:0] idle_q;                    // clocks since the last byte of the frame
    reg [7:0]    mem [0:(1<<AW)-1];         // DATA payload buffer (no reset: block RAM)
    reg [AW-1:0] rd_ptr_q;
    reg [7:0]    rd_data_q;
    reg [7:0]    remaining_q;               // payload bytes still to release
    reg          primed_q;                  // rd_data_q holds mem[rd_ptr_q]
    reg          rsp_q, read_q, write_q, exec_q, dup_q, err_q, gap_q;
    reg [2:0]    reason_q;

    wire [15:0] crc;
    wire in_frame   = state_q != HUNT && state_q != CHECK;
    wire sync_seen  = !in_frame && in_valid && in_data == SYNC;
    wire byte_in    = in_frame && in_valid;
    wire timed_out  = in_frame && !in_valid && idle_q == TIMEOUT_CLOCKS[TW-1:0] - 1'b1;
    wire draining   = remaining_q != 8'd0;
    wire take       = cmd_valid && cmd_ready;
    wire [AW-1:0] rd_next = take ? rd_ptr_q + 1'b1 : rd_ptr_q;

    crc16 u_crc (.clk(clk), .rst(rst), .clear(sync_seen), .valid(byte_in), .data(in_data), .crc(crc));

    assign cmd_valid    = primed_q && draining;
    assign cmd_data     = rd_data_q;
    assign expected     = expected_q;
    assign rsp_valid    = rsp_q;
    assign rsp_reason   = reason_q;
    assign read_req     = read_q;
    assign write_req    = write_q;
    assign req_addr     = addr_q;
    assign req_value    = value_q;
    assign req_seq      = seq_q;
    assign ev_executed  = exec_q;
    assign ev_duplicate = dup_q;
    assign ev_error     = err_q;
    assign ev_gap       = gap_q;

    // The decision on a frame whose CRC is good (in CHECK).
    wire [7:0] distance  = seq_q - expected_q;
    wire       type_ok   = (type_q == T_HELLO && len_q == 8'd0) || type_q == T_DATA
                        || (type_q == T_READ && len_q == 8'd2) || (type_q == T_WRITE && len_q == 8'd6);
    wire       busy      = draining || wb_busy || refused_q;
    wire       no_credit = busy || (type_q == T_DATA && {8'd0, len_q} > queue_free);
    wire       crc_ok    = crc == 16'd0;

    // Payload buffer: written only for a DATA frame, and only while nothing drains.
    always @(posedge clk) begin
        if (state_q == PAYLOAD && in_valid && type_q == T_DATA && !draining)
            mem[index_q[AW-1:0]] <= in_data;
        rd_data_q <= mem[rd_next];
    end

    always @(posedge clk) begin
        if (rst) begin
            state_q     <= HUNT;
            len_q       <= 8'd0;
            type_q      <= 8'd0;
            seq_q       <= 8'd0;
            index_q     <= 8'd0;
            expected_q  <= 8'd0;
            refused_q   <= 1'b0;
            addr_q      <= 16'd0;
            value_q     <= 32'd0;
            idle_q      <= {TW{1'b0}};
            rd_ptr_q    <= {AW{1'b0}};
            remaining_q <= 8'd0;
            primed_q    <= 1'b0;
            rsp_q       <= 1'b0;
            reason_q    <= ACK;
            read_q      <= 1'b0;
            write_q     <= 1'b0;
            exec_q      <= 1'b0;
            dup_q       <= 1'b0;
            err_q       <= 1'b0;
            gap_q       <= 1'b0;
        end else begin
            rsp_q   <= 1'b0;
            read_q  <= 1'b0;
            write_q <= 1'b0;
            exec_q  <= 1'b0;
            dup_q   <= 1'b0;
            err_q   <= 1'b0;
            gap_q   <= 1'b0;

            // release of an accepted DATA payload
            rd_ptr_q <= rd_next;
            primed_q <= draining;
            if (take)
                remaining_q <= remaining_q - 1'b1;

            idle_q <= byte_in ? {TW{1'b0}} : idle_q + 1'b1;

            case (state_q)
                HUNT, CHECK: begin
                    if (sync_seen)
                        state_q <= LEN;
                    else if (state_q == CHECK)
                        state_q <= HUNT;
                    idle_q <= {TW{1'b0}};
                end
                LEN:
                    if (in_valid) begin
                        len_q   <= in_data;
                        state_q <= TYPE;
                    end
                TYPE:
                    if (in_valid) begin
                        type_q  <= in_data;
                        state_q <= SEQ;
                    end
                SEQ:
                    if (in_valid) begin
                        seq_q     <= in_data;
                        index_q   <= 8'd0;
                        refused_q <= 1'b0;
                        state_q   <= len_q == 8'd0 ? CRC_HI : PAYLOAD;
                    end
                PAYLOAD:
                    if (in_valid) begin
                        index_q <= index_q + 1'b1;
                        if (type_q == T_DATA && draining)
                            refused_q <= 1'b1;
                        case (index_q)
                            8'd0: addr_q[7:0]    <= in_data;
                            8'd1: addr_q[15:8]   <= in_data;
                            8'd2: value_q[7:0]   <= in_data;
                            8'd3: value_q[15:8]  <= in_data;
                            8'd4: value_q[23:16] <= in_data;
                            8'd5: value_q[31:24] <= in_data;
                            default: ;
                        endcase
                        if (index_q == len_q - 1'b1)
                            state_q <= CRC_HI;
                    end
                CRC_HI:
                    if (in_valid)
                        state_q <= CRC_LO;
                default:                            // CRC_LO
                    if (in_valid)
                        state_q <= CHECK;
            endcase

            // Frames dropped on the way: over-long LEN, framing error, timeout.
            if ((state_q == LEN && in_valid && in_data > LMAX[7:0]) || (in_frame && in_error) || timed_out) begin
                state_q  <= HUNT;
                rsp_q    <= 1'b1;
                reason_q <= NAK_FRAME;
                err_q    <= 1'b1;
            end

            if (state_q == CHECK) begin
                rsp_q <= 1'b1;
                if (!crc_ok) begin
                    reason_q <= NAK_FRAME;
                    err_q    <= 1'b1;
                end else if (!type_ok) begin
                    reason_q <= NAK_TYPE;
                    err_q    <= 1'b1;
                end else if (type_q == T_HELLO) begin
                    reason_q <= ACK;
                    exec_q   <= 1'b1;
                end else if (type_q == T_READ) begin
                    if (busy) begin
                        reason_q <= NAK_CREDIT;
                        gap_q    <= 1'b1;
                    end else begin
                        rsp_q    <= 1'b0;          // answered by the REPLY
                        read_q   <= 1'b1;
                        exec_q   <= 1'b1;
                    end
                end else if (distance[7]) begin
                    reason_q <= ACK;                // an old frame: acknowledged, not executed
                    dup_q    <= 1'b1;
                end else if (distance != 8'd0) begin
                    reason_q <= NAK_GAP;
                    gap_q    <= 1'b1;
                end else if (no_credit) begin
                    reason_q <= NAK_CREDIT;
                    gap_q    <= 1'b1;
                end else begin
                    reason_q   <= ACK;
                    exec_q     <= 1'b1;
                    expected_q <= expected_q + 1'b1;
                    write_q    <= type_q == T_WRITE;
                    if (type_q == T_DATA) begin
                        remaining_q <= len_q;
                        rd_ptr_q    <= {AW{1'b0}};
                        primed_q    <= 1'b0;
                    end
                end
            end
        end
    end
endmodule
`default_nettype wire
