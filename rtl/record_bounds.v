// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Record bounds of the controller's command record stream, on the side that writes the
// segment queue: `last` marks the byte that ends a record, so that the controller counts
// the whole records waiting (STATUS.records).  A record whose head has bit 7 clear is
// RECORD_BYTES bytes; a compact one (bit 7 set, see record_unpack) is the head, 7 bytes
// of nibbles (5 with head bit 6 set: i, j, k, l zero), and as many more bytes as its
// nibbles add up to, less the codes that send no bytes (the table's last byte but two:
// a limit nibble, low, of 14 or 15; the last but one: a rate nibble, low, of 15, a cost
// nibble, high, of 12 .. 15; the last: a length nibble, low, of 13 .. 15, a budget
// nibble, high, of 15).
// `flush` (and rst) make the next byte a head.
module record_bounds #(
    parameter integer RECORD_BYTES = 68    // bytes of a whole record (9 .. 255)
) (
    input  wire       clk,
    input  wire       rst,
    input  wire       flush,      // the next byte is a head
    input  wire       write,      // a byte of the stream is written ...
    input  wire [7:0] data,       // ... this one
    output wire       last        // ... and it ends a record
);
    initial begin
        if (RECORD_BYTES < 9 || RECORD_BYTES > 255) $error("%m: RECORD_BYTES must be 9 .. 255");
    end

    localparam [31:0] RB32 = RECORD_BYTES;

    reg  [7:0] at;                // bytes of this record written
    reg  [7:0] length;            // its length as known so far
    reg        compact;
    reg        zero_ijkl;         // a compact record's table of 5 bytes
    wire       head     = at == 8'd0;
    wire [7:0] table_end = zero_ijkl ? 8'd5 : 8'd7;  // the last table byte
    wire       in_table = compact & (at != 8'd0) & (at <= table_end);
    wire       codes    = at == table_end;            // the length's and budget's nibbles
    wire       limits   = at == table_end - 8'd2;     // the limit's (low) and exit's
    wire       rates    = at == table_end - 8'd1;     // the rate's (low) and cost's
    wire [3:0] low      = (codes && data[3:0] >= 4'd13) || (limits && data[3:0] >= 4'd14)
                          || (rates && data[3:0] == 4'd15) ? 4'd0 : data[3:0];
    wire [3:0] high     = (codes && data[7:4] == 4'd15) || (rates && data[7:4] >= 4'd12) ? 4'd0 : data[7:4];
    wire [7:0] length_now = head ? (data[7] ? (data[6] ? 8'd6 : 8'd8) : RB32[7:0])
                          : length + (in_table ? {4'd0, low} + {4'd0, high} : 8'd0);
    assign last = write & (at + 8'd1 == length_now);

    always @(posedge clk) begin
        if (rst | flush) begin
            at <= 8'd0; length <= 8'd0; compact <= 1'b0; zero_ijkl <= 1'b0;
        end else if (write) begin
            at     <= last ? 8'd0 : at + 8'd1;
            length <= length_now;
            if (head) begin
                compact   <= data[7];
                zero_ijkl <= data[7] & data[6];
            end
        end
    end
endmodule
`default_nettype wire
