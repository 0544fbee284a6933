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
// field of its base (zero after rst or flush): the previous record of its class, arcs
// (kinds 1 and 2) or the others (a CAM program's arcs and lines alternate, and each
// repeats its own feed, limit and rate).  After the head, 7 bytes of
// nibbles give each field's difference length n (field 2t in the low nibble of byte t),
// then come the n bytes of each field (two's complement, little-endian, sign-extended
// to the field's bytes and added modulo 2^(8 B)); n > B(field) is an error like kinds
// 6 and 7, except codes that send no bytes and have the unpacker form the field:
//   cost n = 12:           cost = 0 (a flat arc's),
//   cost n = 13, 14, 15:   cost = round(2^FRAC sqrt(x^2 + y^2 + z^2) / |x|, |y|, |z|)
//                          mod 2^FEED_W (a line's true length per step event: line_cost),
//   limit n = 14:          limit = feed,
//   limit n = 15:          limit = floor(cost x limit_scale / 2^limit_shift) mod 2^FEED_W
//                          (a line's axis ceiling: its axes' top speed per unit of cost),
//   rate n = 15:           rate = floor(cost x rate_scale / 2^rate_shift) mod 2^(PF + 1)
//                          (its acceleration),
//   length n = 13, 14, 15: length = |x|, |y|, |z| x cost (a line's step events x cost),
//   budget n = 15:         budget = floor(rate x length / 2^(block_shift - 1))
//                          (= 2 rate length / (A 2^block_shift) for a speed quantum A = 1).
// A compact head with bit 6 set also says i, j, k and l are zero (a line's, an event's):
// the table then has 5 bytes (none for those four fields: the table's bytes 2 and 3 are
// zero, formed in the clocks they would have taken) and those fields' bytes are zero.
// The register rotates one byte a clock: the byte leaving at the bottom is the base's
// byte of the position entering at the top (a limit = feed byte is the feed's, a fixed
// number of bytes above it); the last record of the other class waits in a second
// register, and a head of the other class swaps the two.  After the last byte of a
// compact record come DERIVE_CLOCKS = C + T + ZW + 15 clocks (C = 4 W + FRAC + 7,
// T = max(W, 64 + max(FEED_W, PF + 1))), the same for every compact record: first
// line_cost's C clocks for the cost (its result taken the clock after), then the
// length's shift-and-add multiplication in place in its bytes (W clocks, the axis's magnitude formed
// bit-serially) and beside it the limit's and the rate's (the scale in parallel, the
// cost's bits serially by index; the product's bits from bit `shift` on shifted into the
// field's bytes, ending at clock 64 + the field's width), then the budget's (rate in
// parallel, the length's bits serially, rotated back into place; the product's bits from
// bit block_shift - 1 on shifted into the budget's bytes), so a record is pushed
// RECORD_BYTES + 8 + DERIVE_CLOCKS clocks after the previous one from a stream without
// gaps (plain records RECORD_BYTES + 1).
module record_unpack #(
    parameter integer W      = 32,  // command field width (>= 6)
    parameter integer FEED_W = 34,  // speed word width (2 .. 88: cost codes 12 .. 15)
    parameter integer FRAC   = 32,  // fraction bits of the path units: an axial step costs 2^FRAC (1 .. 64)
    parameter integer NW     = 24,  // exit speed width (>= 1)
    parameter integer PF     = 16,  // rate fraction bits: cmd_rate is PF + 1 bits (>= 1)
    parameter integer LEN_W  = 66,  // move length width (2 .. 96; W + FEED_W <= 8 B(LEN_W))
    parameter integer ZW     = 68   // braking budget width (LEN_W .. 112)
) (
    input  wire              clk,
    input  wire              rst,
    input  wire              flush,         // drop the record being assembled
    input  wire [3:0]        block_shift,   // a derived budget's scale: 2^(block_shift - 1) (>= 1)
    input  wire [31:0]       limit_scale,   // a derived limit's: cost x limit_scale / 2^limit_shift
    input  wire [5:0]        limit_shift,
    input  wire [31:0]       rate_scale,    // a derived rate's: cost x rate_scale / 2^rate_shift
    input  wire [5:0]        rate_shift,
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
        if (FEED_W < 2 || FEED_W > 88) $error("%m: FEED_W must be 2 .. 88 (cost codes 12 .. 15)");
        if (FRAC < 1 || FRAC > 64) $error("%m: FRAC must be 1 .. 64");
        if (NW < 1) $error("%m: NW must be at least 1");
        if (PF < 1) $error("%m: PF must be at least 1");
        if (LEN_W < 2 || LEN_W > 96) $error("%m: LEN_W must be 2 .. 96 (length codes 13 .. 15)");
        if (ZW < LEN_W || ZW > 112) $error("%m: ZW must be LEN_W .. 112 (budget code 15)");
    end

    // bytes of each field and its offset in the record
    localparam integer BF = (FEED_W + 7) / 8, BW = (W + 7) / 8, BN = (NW + 7) / 8;
    localparam integer BR = (PF + 1 + 7) / 8, BL = (LEN_W + 7) / 8, BZ = (ZW + 7) / 8;
    localparam integer O_FEED = 1, O_X = O_FEED + BF;
    localparam integer O_I = O_X + 3 * BW, O_LIMIT = O_X + 7 * BW, O_EXIT = O_LIMIT + BF, O_RATE = O_EXIT + BN;
    localparam integer O_COST = O_RATE + BR, O_LENGTH = O_COST + BF, O_BUDGET = O_LENGTH + BL;
    localparam integer RECORD_BYTES = O_BUDGET + BZ;
    localparam integer RB = 8 * RECORD_BYTES;
    localparam integer CW = 8;      // byte counter width: RECORD_BYTES < 256
    localparam integer SPAN = 64;   // clock at which a scaled field's first bit is formed (shift <= 63)
    localparam integer SCALED_END = SPAN + (FEED_W > PF + 1 ? FEED_W : PF + 1);  // ... and its last one + 1
    localparam integer T = W > SCALED_END ? W : SCALED_END;         // the budget's start at block_shift 16
    localparam integer SL = 8 * O_LENGTH, SB = 8 * O_BUDGET;      // the length's, budget's bits
    localparam integer PB = W + FEED_W;                          // |axis| x cost
    // DERIVE_CLOCKS = 4 W + FRAC + 7 (line_cost's, and one to take its cost) + FORM_CLOCKS
    localparam integer FORM_CLOCKS = T + ZW + 15;                   // the other codes' clocks
    localparam integer FEED_SLOT = 8 * (RECORD_BYTES - O_LIMIT + O_FEED);   // a new feed byte, as a limit byte enters
    localparam integer SL_LIMIT = 8 * O_LIMIT, SL_RATE = 8 * O_RATE;  // the limit's, rate's bits
    initial begin
        if (RECORD_BYTES > 255) $error("%m: a record must be at most 255 bytes");
        if (PB > 8 * BL) $error("%m: W + FEED_W must be at most 8 B(LEN_W)");
        if (FORM_CLOCKS > 511) $error("%m: max(W, 64 + FEED_W, 65 + PF) + ZW must be at most 496");
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
    reg  [RB-9:0]   other;          // the last record of the other class, but its head
    reg             arc_class;      // the class of `record`'s: 1 arcs (kinds 1, 2), 0 the others
    reg  [CW-1:0]   count;          // bytes assembled (the head included)
    reg             compact;        // the record being assembled is compact
    reg             zero_ijkl;      // ... with head bit 6: i, j, k, l zero, no table bytes for them
    reg  [2:0]      table_count;    // nibble table bytes taken
    reg  [8*TB-1:0] nibbles;        // the table; the next field's length at bits 3:0
    reg  [3:0]      left;           // difference bytes still to come in this field
    reg             carry, sign;    // the field's byte-serial sum: carry, difference sign
    reg             bad_length;     // a difference longer than its field
    reg  [1:0]      length_axis;    // length code: 1, 2, 3 = |x|, |y|, |z| x cost; 0 none
    reg             budget_code;    // budget code
    reg  [1:0]      cost_axis;      // cost code: 1, 2, 3 = |x|, |y|, |z| is the step events; 0 none
    reg  [1:0]      fill;           // this field's bytes: 0 the sums, 1 zero (cost 12), 2 the feed's (limit 14)
    reg             cost_started;   // line_cost runs for this record
    reg             costed;         // ... and its cost is taken: the other codes' clocks
    reg  [8:0]      clock_count;    // clocks of the derivation
    reg             derived;        // the derivation is over (a compact record)
    reg             negative, seen; // the axis's sign; a one bit has gone (its magnitude)
    reg  [PF:0]     partial;        // the budget's multiplication: the product's high part
    reg             limit_code, rate_code;          // limit, rate codes
    reg  [31:0]     limit_partial, rate_partial;    // their multiplications' high parts
    wire            whole    = count == RECORD_BYTES[CW-1:0];
    wire            ready    = whole & (~compact | derived);
    wire            bad      = (cmd_kind[2] & cmd_kind[1]) | bad_length;   // kind 6, 7, a long difference
    wire            in_table = compact & (count == {{(CW-1){1'b0}}, 1'b1}) & (table_count != TB3);
    wire            skip     = in_table & zero_ijkl & (table_count[2:1] == 2'd1);   // table bytes 2, 3
    wire            ijkl     = count >= O_I[CW-1:0] && count < O_LIMIT[CW-1:0];     // a byte of i .. l
    wire            body     = compact & (count != {CW{1'b0}}) & ~in_table & ~whole;

    // a compact record's next byte: previous byte + difference byte (or its sign) + carry
    wire [7:0] here_bytes  = field_bytes(count);
    wire       field_start = here_bytes != 8'd0;
    wire [3:0] code        = nibbles[3:0];
    wire       length_here = count == O_LENGTH[CW-1:0] && code >= 4'd13;
    wire       budget_here = count == O_BUDGET[CW-1:0] && code == 4'd15;
    wire       limit_here  = count == O_LIMIT[CW-1:0] && code == 4'd15;
    wire       feed_here   = count == O_LIMIT[CW-1:0] && code == 4'd14;
    wire       rate_here   = count == O_RATE[CW-1:0] && code == 4'd15;
    wire       zero_here   = count == O_COST[CW-1:0] && code == 4'd12;
    wire       cost_here   = count == O_COST[CW-1:0] && code >= 4'd13;
    wire       code_here   = length_here | budget_here | limit_here | feed_here | rate_here | zero_here | cost_here;
    wire [1:0] fill_now    = field_start ? {feed_here, zero_here} : fill;
    wire [3:0] n_here = field_start ? (code_here ? 4'd0 : code) : left;
    wire       use_in = n_here != 4'd0;
    wire [7:0] delta  = use_in ? in_data : field_start ? 8'd0 : {8{sign}};
    wire [8:0] sum    = {1'b0, record[7:0]} + {1'b0, delta} + {8'd0, carry & ~field_start};

    assign in_ready     = ~whole & ~(body & ~use_in) & ~skip;
    assign cmd_valid    = ready & ~bad & ~cmd_full;
    assign record_error = ready & bad;
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
    assign cmd_length = record[SL +: LEN_W];
    assign cmd_budget = record[SB +: ZW];

    // The derivation after line_cost's (its cost taken, 4 W + FRAC + 7 clocks after the
    // last byte), clock c of FORM_CLOCKS.  c = 0: the length's bytes take the axis;
    // c = 1 .. W: a shift-and-add step, its multiplier bit the axis's magnitude's (a
    // two's complement negated bit-serially: inverted after the first one bit).
    // c = SPAN - shift + j, j = 0 .. shift + width - 1: the limit's (rate's) step j, the
    // cost's bit j times the scale, product bit j shifted into the field from j = shift on.
    // c = T + 15 - s + j, j = 0 .. s + ZW - 1 (s = block_shift - 1): the budget's step j,
    // the length's bit j (j < LEN_W, its bits rotated back into place) times the rate,
    // product bit j shifted into the budget's bytes from j = s on.
    wire [3:0]      scale    = block_shift == 4'd0 ? 4'd0 : block_shift - 4'd1;
    wire            deriving = whole & compact & ~derived & costed;    // the other codes' clocks
    wire            cost_done;
    wire [FEED_W-1:0] line_cost_value;
    wire [W-1:0]    axis     = length_axis == 2'd1 ? cmd_x : length_axis == 2'd2 ? cmd_y : cmd_z;
    wire            load     = deriving & (length_axis != 2'd0) & (clock_count == 9'd0);
    wire            multiply = deriving & (length_axis != 2'd0) & (clock_count != 9'd0)
                               & (clock_count <= W[8:0]);
    wire [PB-1:0]   product  = record[SL +: PB];
    wire            bit_m    = product[0] ^ (negative & seen);
    wire [FEED_W:0] step_sum = {1'b0, product[PB-1:W]} + (bit_m ? {1'b0, cmd_cost} : {(FEED_W+1){1'b0}});
    wire [8:0]      budget_at = T[8:0] + 9'd15 - {5'd0, scale};
    wire [8:0]      j        = clock_count - budget_at;
    wire            budget_step = deriving & budget_code & (clock_count >= budget_at);
    wire            bit_l    = j < LEN_W[8:0] ? record[SL] : 1'b0;
    wire [PF+1:0]   budget_sum = {1'b0, partial} + (bit_l ? {1'b0, cmd_rate} : {(PF+2){1'b0}});
    // the limit's and the rate's steps: j = c + shift - SPAN, the product's bit into the field at c >= SPAN
    wire [9:0]      limit_j  = {1'b0, clock_count} + {4'd0, limit_shift} - SPAN[9:0];
    wire [9:0]      rate_j   = {1'b0, clock_count} + {4'd0, rate_shift} - SPAN[9:0];
    wire            limit_step = deriving & limit_code & ~limit_j[9] & (clock_count < SPAN[8:0] + FEED_W[8:0]);
    wire            rate_step  = deriving & rate_code & ~rate_j[9] & (clock_count < SPAN[8:0] + PF[8:0] + 9'd1);
    wire            emit     = clock_count >= SPAN[8:0];
    wire [FEED_W-1:0] cost_l = cmd_cost >> limit_j;      // the cost's bit j at bit 0 (0 from j = FEED_W on)
    wire [FEED_W-1:0] cost_r = cmd_cost >> rate_j;
    wire            bit_lc   = cost_l[0];
    wire            bit_rc   = cost_r[0];
    wire [32:0]     limit_sum = {1'b0, limit_partial} + (bit_lc ? {1'b0, limit_scale} : 33'd0);
    wire [32:0]     rate_sum = {1'b0, rate_partial} + (bit_rc ? {1'b0, rate_scale} : 33'd0);

    // the cost code's arithmetic, first after a compact record's last byte (whatever its codes)
    wire cost_start = whole & compact & ~cost_started;
    line_cost #(.W(W), .FEED_W(FEED_W), .FRAC(FRAC)) u_cost (
        .clk(clk), .rst(rst | flush), .start(cost_start),
        .x(cmd_x), .y(cmd_y), .z(cmd_z), .axis(cost_axis), .cost(line_cost_value), .done(cost_done));

    integer b;                      // (the fields' bytes' bits above their widths)
    wire take    = in_valid & in_ready;
    wire advance = body ? (take | ~use_in) : take & ~in_table;   // a byte of the record is formed
    wire head_arc = in_data[2:0] == 3'd1 || in_data[2:0] == 3'd2;
    wire swap    = take && count == {CW{1'b0}} && head_arc != arc_class;   // a head of the other class
    wire [RB-9:0] base = swap ? other : record[RB-1:8];   // the base, rotated

    always @(posedge clk) begin
        if (rst | flush) begin
            count <= {CW{1'b0}}; record <= {RB{1'b0}}; other <= {(RB-8){1'b0}}; arc_class <= 1'b0;
            compact <= 1'b0; zero_ijkl <= 1'b0; table_count <= 3'd0;
            nibbles <= {(8*TB){1'b0}}; left <= 4'd0; carry <= 1'b0; sign <= 1'b0; bad_length <= 1'b0;
            length_axis <= 2'd0; budget_code <= 1'b0; clock_count <= 9'd0; derived <= 1'b0;
            negative <= 1'b0; seen <= 1'b0; partial <= {(PF+1){1'b0}};
            limit_code <= 1'b0; rate_code <= 1'b0; limit_partial <= 32'd0; rate_partial <= 32'd0;
            cost_axis <= 2'd0; fill <= 2'd0; cost_started <= 1'b0; costed <= 1'b0;
        end else if (taken) begin
            count <= {CW{1'b0}}; clock_count <= 9'd0; derived <= 1'b0; partial <= {(PF+1){1'b0}};
            cost_started <= 1'b0; costed <= 1'b0;
            limit_partial <= 32'd0; rate_partial <= 32'd0;
        end else begin
            if ((take & in_table) | skip) begin
                nibbles <= {skip ? 8'd0 : in_data, nibbles[8*TB-1:8]};
                table_count <= table_count + 3'd1;
            end
            if (advance) begin
                count  <= count + 1'b1;
                record <= {~body ? in_data : (zero_ijkl & ijkl) | fill_now[0] ? 8'd0
                                   : fill_now[1] ? record[FEED_SLOT +: 8] : sum[7:0], base};
            end
            if (swap) begin
                other     <= record[RB-1:8];
                arc_class <= head_arc;
            end
            if (take && count == {CW{1'b0}}) begin          // the head
                compact <= in_data[7]; zero_ijkl <= in_data[7] & in_data[6];
                table_count <= 3'd0; bad_length <= 1'b0;
                length_axis <= 2'd0; budget_code <= 1'b0; limit_code <= 1'b0; rate_code <= 1'b0;
                cost_axis <= 2'd0; fill <= 2'd0;
            end
            if (body & advance) begin
                carry <= sum[8];
                sign  <= use_in ? in_data[7] : sign & ~field_start;
                left  <= n_here - {3'd0, use_in};
                if (field_start) begin
                    nibbles <= nibbles >> 4;
                    fill    <= fill_now;
                    if (cost_here) cost_axis <= code[1:0];
                    if (length_here) length_axis <= code[1:0];
                    if (budget_here) budget_code <= 1'b1;
                    if (limit_here) limit_code <= 1'b1;
                    if (rate_here) rate_code <= 1'b1;
                    if (!code_here && {4'd0, code} > here_bytes) bad_length <= 1'b1;
                end
            end
            if (cost_start) cost_started <= 1'b1;
            if (cost_done) begin
                costed <= 1'b1;
                if (cost_axis != 2'd0) begin
                    record[8 * O_COST +: FEED_W] <= line_cost_value;
                    for (b = FEED_W; b < 8 * BF; b = b + 1) record[8 * O_COST + b] <= 1'b0;
                end
            end
            if (deriving) begin
                clock_count <= clock_count + 9'd1;
                if (clock_count == FORM_CLOCKS[8:0] - 9'd1) derived <= 1'b1;
            end
            if (load) begin
                record[SL +: 8 * BL] <= {{(8 * BL - W){1'b0}}, axis};       // 8 B(LEN_W) > W
                negative <= axis[W-1];
                seen     <= 1'b0;
            end
            if (multiply) begin
                record[SL +: PB] <= {step_sum, product[W-1:1]};
                seen <= seen | product[0];
            end
            if (limit_step) begin
                limit_partial <= limit_sum[32:1];
                if (emit) begin
                    record[SL_LIMIT +: FEED_W] <= {limit_sum[0], record[SL_LIMIT + 1 +: FEED_W - 1]};
                    for (b = FEED_W; b < 8 * BF; b = b + 1) record[SL_LIMIT + b] <= 1'b0;
                end
            end
            if (rate_step) begin
                rate_partial <= rate_sum[32:1];
                if (emit) begin
                    record[SL_RATE +: PF + 1] <= {rate_sum[0], record[SL_RATE + 1 +: PF]};
                    for (b = PF + 1; b < 8 * BR; b = b + 1) record[SL_RATE + b] <= 1'b0;
                end
            end
            if (budget_step) begin
                partial <= budget_sum[PF+1:1];
                if (j < LEN_W[8:0]) record[SL +: LEN_W] <= {record[SL], record[SL + 1 +: LEN_W - 1]};
                if (j >= {5'd0, scale}) begin
                    record[SB +: ZW] <= {budget_sum[0], record[SB + 1 +: ZW - 1]};
                    for (b = ZW; b < 8 * BZ; b = b + 1) record[SB + b] <= 1'b0;   // the bytes' high bits
                end
            end
        end
    end

    wire unused = &{1'b0, record, cost_l[FEED_W-1:1], cost_r[FEED_W-1:1]};   // the unused high bits of the fields
endmodule
`default_nettype wire
