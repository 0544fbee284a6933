// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Decision pipeline of the path-speed profile generator (speed_ramp): the braking
// criterion of the speed-setting block ("БЗС" of the lecture) and its cap, formed over
// the three clocks before a DDA tick so that the tick decides on registered bits.
//
// A tick's thresholds are R << bs for n and n + 1 (braking_need, R(n, u) = n^2 + n -
// f^2 - f + 2 n (p - u)), taken with the phase acc' = acc + rate - 2^PF the tick
// leaves; the rate then drops out:
//   R(n) 2^PF     = (q - f_sq + 2 n) 2^PF - 2 na,
//   R(n + 1) 2^PF = (q - f_sq + 4 (n + 1)) 2^PF - 2 (na + acc),
// q = n (n + 1), na = n acc, f_sq = f (f + 1).  With blocks of 4 clocks or more
// (block_shift >= 2) none of n, q, na, acc, p or the segment's registers changes in the
// three clocks before a tick unless a segment switches, loads or ends there (`event`,
// which the block end also is).  Stage 1 forms the bracketed sums, the floor
// comparisons and Zx - 8 p, the budget projected to the tick (Zx falls by 2 p a clock,
// less the refinement's give-back, so the projection is a little low); stage 2 the
// thresholds, the shifted budget floor((Zx - 8 p) / 2^bs) (>= R <=> Zx >= R << bs for an
// integer R) and 100 v, 100 (v + A); stage 3 the comparisons and the cap against
// feed * override.  `valid`: the three clocks before this one had no event and the
// successor seen by stage 1 is still there, so the bits belong to a tick in this clock.
module speed_ramp_decide #(
    parameter integer FEED_W = 16,  // speed word (>= 2)
    parameter integer NW     = 16,  // speed in quanta n (2 .. 64)
    parameter integer PF     = 12,  // fraction bits of the rate (1 .. 64)
    parameter integer ZW     = 48   // budget Z0 (>= 2)
) (
    input  wire                  clk,
    input  wire                  rst,
    input  wire                  event_now,   // a block end, switch, load or end at this edge
    input  wire                  succ,        // the successor is known (f_sq, floor_n its)
    input  wire [NW-1:0]         n,
    input  wire [2*NW-1:0]       q,           // n (n + 1)
    input  wire [2*NW-1:0]       f_sq,        // f (f + 1)
    input  wire [NW-1:0]         floor_n,     // f
    input  wire [NW+PF-1:0]      na,          // n acc
    input  wire [PF-1:0]         acc,         // DDA phase
    input  wire [PF+NW-1:0]      p,           // rate n
    input  wire signed [(ZW > 2*NW+PF+3 ? ZW : 2*NW+PF+3)+16:0] budget_x,  // Zx
    input  wire [3:0]            bs,          // block_shift as registered
    input  wire [FEED_W-1:0]     speed,       // v
    input  wire [FEED_W:0]       va,          // v + A
    input  wire [FEED_W-1:0]     limit,
    input  wire [FEED_W+7:0]     fo,          // feed * override
    input  wire                  fo_valid,
    output wire                  valid,       // the bits below are this clock's tick's
    output wire                  ok_hold,     // Zx >= R(n) << bs, or n <= f
    output wire                  ok_up,       // Zx >= R(n + 1) << bs, or n < f
    output reg                   over,        // v above the cap
    output reg                   room         // v + A within the cap, n below its top
);
    initial begin
        if (FEED_W < 2) $error("%m: FEED_W must be at least 2");
        if (NW < 2 || NW > 64) $error("%m: NW must be 2 .. 64");
        if (PF < 1 || PF > 64) $error("%m: PF must be 1 .. 64");
        if (ZW < 2) $error("%m: ZW must be at least 2");
    end

    localparam integer QW  = 2 * NW;
    localparam integer PW  = PF + NW;
    localparam integer NAW = NW + PF;
    localparam integer RW  = 2 * NW + PF + 3;
    localparam integer ZXW = (ZW > RW ? ZW : RW) + 17;
    localparam [NW-1:0] NMAX = {NW{1'b1}};

    reg  [1:0]            fresh;           // clocks since the last event, up to 3
    reg  signed [QW+1:0]  s1_dh, s1_du;    // q - f_sq + 2 n, q - f_sq + 4 (n + 1)
    reg  [NAW:0]          s1_naa;          // na + acc
    reg  signed [ZXW-1:0] s1_zx;           // Zx - 8 p
    reg                   s1_succ, s2_succ, s3_succ;
    reg                   s1_le, s1_lt, s2_le, s2_lt, s3_le, s3_lt;   // n <= f, n < f
    reg  signed [RW-1:0]  s2_hold, s2_up;  // R(n) 2^PF, R(n + 1) 2^PF
    reg  signed [ZXW-1:0] s2_zx;           // floor((Zx - 8 p) / 2^bs)
    reg  [FEED_W+7:0]     s2_v100, s2_va100;
    reg                   s2_above, s2_fit; // v > limit; v + A fits the word and the limit
    reg                   s3_hold, s3_up;

    wire [QW+1:0] n2 = {{(QW+1-NW){1'b0}}, n, 1'b0};
    wire [QW+1:0] n4 = {{(QW-NW-1){1'b0}}, {1'b0, n} + {{NW{1'b0}}, 1'b1}, 2'b00};
    wire [QW+1:0] dh = {2'b00, q} - {2'b00, f_sq} + n2;
    wire [QW+1:0] du = {2'b00, q} - {2'b00, f_sq} + n4;
    wire [RW-1:0] dh_x = {{(RW-QW-2){s1_dh[QW+1]}}, s1_dh};
    wire [RW-1:0] du_x = {{(RW-QW-2){s1_du[QW+1]}}, s1_du};
    wire signed [RW-1:0]  r_hold = ($signed(dh_x) <<< PF) - $signed({{(RW-NAW-1){1'b0}}, na, 1'b0});
    wire signed [RW-1:0]  r_up   = ($signed(du_x) <<< PF) - $signed({{(RW-NAW-2){1'b0}}, s1_naa, 1'b0});
    wire [NAW:0]          naa    = {1'b0, na} + {{(NAW+1-PF){1'b0}}, acc};
    wire signed [ZXW-1:0] zx     = budget_x - $signed({{(ZXW-PW-3){1'b0}}, p, 3'b000});
    wire [FEED_W+7:0] v100  = {2'd0, speed, 6'd0} + {3'd0, speed, 5'd0} + {6'd0, speed, 2'd0};
    wire [FEED_W+7:0] va100 = {1'd0, va, 6'd0} + {2'd0, va, 5'd0} + {5'd0, va, 2'd0};

    assign valid   = (fresh == 2'd3) & ~(s3_succ & ~succ);
    assign ok_hold = s3_le | s3_hold;
    assign ok_up   = s3_lt | s3_up;

    always @(posedge clk) begin
        if (rst) begin
            fresh <= 2'd0;
            s1_dh <= {(QW+2){1'b0}}; s1_du <= {(QW+2){1'b0}}; s1_naa <= {(NAW+1){1'b0}};
            s1_zx <= {ZXW{1'b0}}; s1_succ <= 1'b0; s1_le <= 1'b0; s1_lt <= 1'b0;
            s2_hold <= {RW{1'b0}}; s2_up <= {RW{1'b0}}; s2_zx <= {ZXW{1'b0}}; s2_succ <= 1'b0;
            s2_le <= 1'b0; s2_lt <= 1'b0; s2_v100 <= {(FEED_W+8){1'b0}}; s2_va100 <= {(FEED_W+8){1'b0}};
            s2_above <= 1'b0; s2_fit <= 1'b0;
            s3_hold <= 1'b0; s3_up <= 1'b0; s3_succ <= 1'b0; s3_le <= 1'b0; s3_lt <= 1'b0;
            over <= 1'b0; room <= 1'b0;
        end else begin
            fresh    <= event_now ? 2'd0 : fresh == 2'd3 ? 2'd3 : fresh + 2'd1;
            s1_dh    <= dh; s1_du <= du; s1_naa <= naa; s1_zx <= zx; s1_succ <= succ;
            s1_le    <= n <= floor_n; s1_lt <= n < floor_n;
            s2_hold  <= r_hold; s2_up <= r_up; s2_zx <= s1_zx >>> bs; s2_succ <= s1_succ;
            s2_le    <= s1_le; s2_lt <= s1_lt; s2_v100 <= v100; s2_va100 <= va100;
            s2_above <= speed > limit;
            s2_fit   <= (va <= {1'b0, limit}) & ~va[FEED_W] & (n != NMAX);
            s3_hold  <= s2_zx >= $signed({{(ZXW-RW){s2_hold[RW-1]}}, s2_hold});
            s3_up    <= s2_zx >= $signed({{(ZXW-RW){s2_up[RW-1]}}, s2_up});
            s3_le    <= s2_le; s3_lt <= s2_lt; s3_succ <= s2_succ;
            over     <= s2_above | (fo_valid & (s2_v100 > fo));
            room     <= fo_valid & s2_fit & (s2_va100 <= fo);
        end
    end
endmodule
`default_nettype wire
