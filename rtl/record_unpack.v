// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Record unpacker of the controller: assembles RECORD_BYTES bytes of the command record
// stream (little-endian fields, each B(bits) = ceil(bits / 8) bytes, in this order:
// head (bits 2:0 kind, 5:4 plane), feed, x y z i j k l, limit, exit, rate, cost, length,
// budget) into motion_top's command fields and pushes them with cmd_valid when motion_top
// has room (cmd_full low): nothing is dropped, the byte stream waits (in_ready low)
// while a whole record waits for room.  A record of kind 6 or 7 is not pushed:
// `record_error` strobes and the record is dropped.  `taken` strobes for every record
// that leaves (pushed or dropped).  `flush` drops the record being assembled.
// Bytes shift in at the top of one register; the fields are read at fixed offsets.
module record_unpack #(
    parameter integer W      = 32,  // command field width (>= 6)
    parameter integer FEED_W = 50,  // speed word width (>= 2)
    parameter integer NW     = 40,  // exit speed width (>= 1)
    parameter integer PF     = 24,  // rate fraction bits: cmd_rate is PF + 1 bits (>= 1)
    parameter integer LEN_W  = 82,  // move length width (>= 1)
    parameter integer ZW     = 108  // braking budget width (>= 1)
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

    reg  [RB-1:0] record;           // byte 0 at bits 7:0 once all bytes are in
    reg  [CW-1:0] count;            // bytes assembled
    wire          whole = count == RECORD_BYTES[CW-1:0];
    wire          bad   = cmd_kind[2] & cmd_kind[1];          // kind 6, 7

    assign in_ready     = ~whole;
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

    always @(posedge clk) begin
        if (rst | flush) begin
            count <= {CW{1'b0}};
        end else if (taken) begin
            count <= {CW{1'b0}};
        end else if (in_valid & in_ready) begin
            count <= count + 1'b1;
        end
    end

    // no reset: only the bytes of a whole record are read
    always @(posedge clk) begin
        if (in_valid & in_ready)
            record <= {in_data, record[RB-1:8]};
    end

    wire unused = &{1'b0, record};      // the unused high bits of the fields
endmodule
`default_nettype wire
