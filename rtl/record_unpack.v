// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Record unpacker of the controller: assembles RECORD_BYTES bytes of the command record
// stream (little-endian fields, each B(bits) = ceil(bits / 8) bytes, in this order:
// head (bits 2:0 kind, 5:4 plane, 7 compact), feed, x y z i j k l, limit, exit, rate,
// cost, length, budget) into motion_top's command fields and pushes them with cmd_valid
// when motion_top has room (cmd_full low): nothing is dropped, the byte stream waits
// (in_ready low) while a whole record waits for room.  A record of kind 6 or 7 is not
// pushed: `record_error` strobes and the record is dropped.  `taken` strobes for every
// record that leaves (pushed or dropped).  `flush` drops the record being assembled.
// A compact record (head bit 7 set) carries each field as a difference from the same
// field of the previous record (zero after rst or flush): after the head, 7 bytes of
// nibbles give each field's difference length n (field 2t in the low nibble of byte t),
// then come the n bytes of each field (two's complement, little-endian, sign-extended
// to the field's bytes and added modulo 2^(8 B)); n > B(field) is an error like kinds
// 6 and 7.  The register rotates one byte a clock: the byte leaving at the bottom is the
// previous record's byte of the position entering at the top.
module record_unpack #(
    parameter integer W      = 32,  // command field width (>= 6)
    parameter integer FEED_W = 34,  // speed word width (>= 2)
    parameter integer NW     = 24,  // exit speed width (>= 1)
    parameter integer PF     = 16,  // rate fraction bits: cmd_rate is PF + 1 bits (>= 1)
    parameter integer LEN_W  = 66,  // move length width (>= 1)
    parameter integer ZW     = 68   // braking budget width (>= 1)
) (
    input  wire              clk,
    input  wire              rst,
    input  wire              flush,         // drop the record being assembled
    input  wire              in_valid,
    input  wire [7:0]        in_data,
    output wire              in_ready,
    output wire              cmd_valid,     // to motion_top: a whole record, motion_top not full
    output wire [2:0]        cmd_kind,
    output wire [1:0]        cmd_plane,
    output wire [FEED_W-1:0] cmd_feed,
    output wire [W-1:0]      cmd_x,
    output wire [W-1:0]      cmd_y,
    output wire [W-1:0]      cmd_z,
    output wire [W-1:0]      cmd_i,
    output wire [W-1:0]      cmd_j,
    output wire [W-1:0]      cmd_k,
    output wire [W-1:0]      cmd_l,
    output wire [FEED_W-1:0] cmd_limit,
    output wire [NW-1:0]     cmd_exit,
    output wire [PF:0]       cmd_rate,
    output wire [FEED_W-1:0] cmd_cost,
    output wire [LEN_W-1:0]  cmd_length,
    output wire [ZW-1:0]     cmd_budget,
    input  wire              cmd_full,      // motion_top's queues are full
    output wire              record_error,  // strobe: a record of kind 6 or 7 was dropped
    output wire              taken,         // strobe: a record left (pushed or dropped)
    output wire              assembling     // a record is partly or wholly here
);
    initial begin
        if (W < 6) $error("%m: W must be at least 6");
        if (FEED_W < 2) $error("%m: FEED_W must be at least 2");
        if (NW < 1) $error("%m: NW must be at least 1");
        if (PF < 1) $error("%m: PF must be at least 1");
        if (LEN_W < 1) $error("%m: LEN_W must be at least 1");
        if (ZW < 1) $error("%m: ZW must be at least 1");
    end

    // bytes of each field and its offset in the record
    localparam integer BF = (FEED_W + 7) / 8, BW = (W + 7) / 8, BN = (NW + 7) / 8;
    localparam integer BR = (PF + 1 + 7) / 8, BL = (LEN_W + 7) / 8, BZ = (ZW + 7) / 8;
    localparam integer O_FEED = 1, O_X = O_FEED + BF;
    localparam integer O_LIMIT = O_X + 7 * BW, O_EXIT = O_LIMIT + BF, O_RATE = O_EXIT + BN;
    localparam integer O_COST = O_RATE + BR, O_LENGTH = O_COST + BF, O_BUDGET = O_LENGTH + BL;
    localparam integer RECORD_BYTES = O_BUDGET + BZ;
    localparam integer RB = 8 * RECORD_BYTES;
    localparam integer CW = 8;      // byte counter width: RECORD_BYTES < 256
    initial begin
        if (RECORD_BYTES > 255) $error("%m: a record must be at most 255 bytes");
    end

    localparam integer TB = 7;      // nibble table bytes of a compact record (14 fields)
    localparam [2:0]   TB3 = 3'd7;

    // B(field) when a field starts at byte `at` of the record, else 0
    function [7:0] field_bytes;
        input [CW-1:0] at;
        integer f, a;
        begin
            a = {{(32-CW){1'b0}}, at};
            field_bytes = 8'd0;
            for (f = 0; f < 7; f = f + 1)
                if (a == O_X + f * BW) field_bytes = BW[7:0];
            if (a == O_FEED || a == O_LIMIT || a == O_COST) field_bytes = BF[7:0];
            if (a == O_EXIT) field_bytes = BN[7:0];
            if (a == O_RATE) field_bytes = BR[7:0];
            if (a == O_LENGTH) field_bytes = BL[7:0];
            if (a == O_BUDGET) field_bytes = BZ[7:0];
        end
    endfunction

    reg  [RB-1:0]   record;         // byte 0 at bits 7:0 once all bytes are in
    reg  [CW-1:0]   count;          // bytes assembled (the head included)
    reg             compact;        // the record being assembled is compact
    reg  [2:0]      table_count;    // nibble table bytes taken
    reg  [8*TB-1:0] nibbles;        // the table; the next field's length at bits 3:0
    reg  [3:0]      left;           // difference bytes still to come in this field
    reg             carry, sign;    // the field's byte-serial sum: carry, difference sign
    reg             bad_length;     // a difference longer than its field
    wire            whole    = count == RECORD_BYTES[CW-1:0];
    wire            bad      = (cmd_kind[2] & cmd_kind[1]) | bad_length;   // kind 6, 7, a long difference
    wire            in_table = compact & (count == {{(CW-1){1'b0}}, 1'b1}) & (table_count != TB3);
    wire            body     = compact & (count != {CW{1'b0}}) & ~in_table & ~whole;

    // a compact record's next byte: previous byte + difference byte (or its sign) + carry
    wire [7:0] here_bytes  = field_bytes(count);
    wire       field_start = here_bytes != 8'd0;
    wire [3:0] n_here = field_start ? nibbles[3:0] : left;
    wire       use_in = n_here != 4'd0;
    wire [7:0] delta  = use_in ? in_data : field_start ? 8'd0 : {8{sign}};
    wire [8:0] sum    = {1'b0, record[7:0]} + {1'b0, delta} + {8'd0, carry & ~field_start};

    assign in_ready     = ~whole & ~(body & ~use_in);
    assign cmd_valid    = whole & ~bad & ~cmd_full;
    assign record_error = whole & bad;
    assign taken        = cmd_valid | record_error;
    assign assembling   = count != {CW{1'b0}};

    assign cmd_kind   = record[2:0];
    assign cmd_plane  = record[5:4];
    assign cmd_feed   = record[8 * O_FEED   +: FEED_W];
    assign cmd_x      = record[8 * O_X           +: W];
    assign cmd_y      = record[8 * (O_X + BW)    +: W];
    assign cmd_z      = record[8 * (O_X + 2 * BW) +: W];
    assign cmd_i      = record[8 * (O_X + 3 * BW) +: W];
    assign cmd_j      = record[8 * (O_X + 4 * BW) +: W];
    assign cmd_k      = record[8 * (O_X + 5 * BW) +: W];
    assign cmd_l      = record[8 * (O_X + 6 * BW) +: W];
    assign cmd_limit  = record[8 * O_LIMIT  +: FEED_W];
    assign cmd_exit   = record[8 * O_EXIT   +: NW];
    assign cmd_rate   = record[8 * O_RATE   +: PF + 1];
    assign cmd_cost   = record[8 * O_COST   +: FEED_W];
    assign cmd_length = record[8 * O_LENGTH +: LEN_W];
    assign cmd_budget = record[8 * O_BUDGET +: ZW];

    wire take    = in_valid & in_ready;
    wire advance = body ? (take | ~use_in) : take & ~in_table;   // a byte of the record is formed

    always @(posedge clk) begin
        if (rst | flush) begin
            count <= {CW{1'b0}}; record <= {RB{1'b0}}; compact <= 1'b0; table_count <= 3'd0;
            nibbles <= {(8*TB){1'b0}}; left <= 4'd0; carry <= 1'b0; sign <= 1'b0; bad_length <= 1'b0;
        end else if (taken) begin
            count <= {CW{1'b0}};
        end else begin
            if (take & in_table) begin
                nibbles <= {in_data, nibbles[8*TB-1:8]};
                table_count <= table_count + 3'd1;
            end
            if (advance) begin
                count  <= count + 1'b1;
                record <= {body ? sum[7:0] : in_data, record[RB-1:8]};
            end
            if (take && count == {CW{1'b0}}) begin          // the head
                compact <= in_data[7]; table_count <= 3'd0; bad_length <= 1'b0;
            end
            if (body & advance) begin
                carry <= sum[8];
                sign  <= use_in ? in_data[7] : sign & ~field_start;
                left  <= n_here - {3'd0, use_in};
                if (field_start) begin
                    nibbles <= nibbles >> 4;
                    if ({4'd0, nibbles[3:0]} > here_bytes) bad_length <= 1'b1;
                end
            end
        end
    end

    wire unused = &{1'b0, record};      // the unused high bits of the fields
endmodule
`default_nettype wire
