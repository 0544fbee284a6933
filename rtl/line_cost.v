// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// A line's cost from its geometry, for the record unpacker's cost code: the true path
// length of one step event of the line (x, y, z) whose step events are the |axis| of
// one of its axes, in units of 2^-FRAC axial steps, rounded to nearest (halves up):
//     cost = round(2^FRAC sqrt(x^2 + y^2 + z^2) / |axis|)
//          = (floor(isqrt((x^2 + y^2 + z^2) 4^(FRAC + 1)) / |axis|) + 1) / 2,
// modulo 2^FEED_W (the G-code compiler's cmd_cost of a line, its true length over its
// step events).  Bit-serial, a fixed CLOCKS = 4 W + FRAC + 6 clocks from `start`:
//   1. the sum of squares by shift-and-add, one multiplier bit a clock: for each axis
//      a clock loads |axis| and W clocks add it, shifted, where its bit is one;
//   2. the integer square root of the sum with 2 FRAC + 2 zero bits below it, digit by
//      digit, one root bit a clock (the sum's two top bits shifted in, then zeros);
//   3. beside it, one clock behind, the restoring division of the root by |axis|, one
//      root bit in and one quotient bit out a clock; the quotient's FEED_W + 1 low bits
//      are kept, and the last clock rounds (the quotient + 1, halved).
// |axis| = 0 gives a quotient of W + FRAC + 1 ones (the division subtracts nothing):
// a cost of 2^(W + FRAC) mod 2^FEED_W (0 when FEED_W <= W + FRAC).  `done` strobes
// the clock `cost` is formed; x, y, z and `axis` must stay put from `start` to `done`.
// It is the path length per step event that the lecture's speed-setting block ("БЗС",
// step_cost) charges, here for a whole line: its true length shared evenly by its step
// events.
module line_cost #(
    parameter integer W      = 32,  // axis width, signed (>= 2)
    parameter integer FEED_W = 34,  // cost width (>= 2)
    parameter integer FRAC   = 32   // fraction bits: an axial step costs 2^FRAC (1 .. 64)
) (
    input  wire              clk,
    input  wire              rst,
    input  wire              start,     // strobe: x, y, z and axis are the line's
    input  wire [W-1:0]      x,
    input  wire [W-1:0]      y,
    input  wire [W-1:0]      z,
    input  wire [1:0]        axis,      // the step events' axis: 1, 2, 3 = x, y, z (0: z)
    output reg  [FEED_W-1:0] cost,
    output reg               done       // strobe: cost is formed
);
    initial begin
        if (W < 2) $error("%m: W must be at least 2");
        if (FEED_W < 2) $error("%m: FEED_W must be at least 2");
        if (FRAC < 1 || FRAC > 64) $error("%m: FRAC must be 1 .. 64");
        if (4 * W + FRAC + 6 > 511) $error("%m: 4 W + FRAC + 6 must be at most 511");
    end

    localparam integer PASS   = W + 1;             // clocks of one square: a load, W steps
    localparam integer RW     = W + FRAC + 1;      // root bits: one a clock
    localparam integer ROOT_AT = 3 * PASS;         // the root's first clock
    localparam integer CLOCKS = ROOT_AT + RW + 2;  // the division ends one clock after the root
    localparam [8:0]   LAST   = CLOCKS[8:0] - 9'd1;
    localparam integer ROOT_END = ROOT_AT + RW;
    localparam [8:0]   P1 = PASS[8:0], P2 = P1 + P1, R0 = ROOT_AT[8:0], R1 = ROOT_END[8:0];

    function [W-1:0] magnitude(input [W-1:0] value);
        magnitude = value[W-1] ? ~value + 1'b1 : value;   // |-2^(W-1)| = 2^(W-1) fits
    endfunction

    reg  [8:0]      clock_count;    // clocks since start
    reg             running;
    reg  [2*W-1:0]  shifted;        // |axis| x 2^k
    reg  [W-1:0]    multiplier;     // |axis| >> k
    reg  [2*W-1:0]  sum;            // x^2 + y^2 + z^2 (<= 3 x 4^(W-1)); then shifted out, two bits a clock
    reg  [RW-1:0]   root;
    reg  [RW:0]     remainder;      // the radicand's so far less root^2 (<= 2 root)
    reg  [W-1:0]    residue;        // the division's remainder (< |axis|)
    reg  [FEED_W:0] quotient;

    wire [8:0]      c        = start ? 9'd0 : clock_count;
    wire [1:0]      pass     = c < P1 ? 2'd0 : c < P2 ? 2'd1 : 2'd2;
    wire [W-1:0]    operand  = magnitude(pass == 2'd0 ? x : pass == 2'd1 ? y : z);
    wire            load     = c == 9'd0 || c == P1 || c == P2;
    wire            square   = (start | running) & ~load & (c < R0);
    wire            rooting  = running & (c >= R0) & (c < R1);
    wire            dividing = running & (c > R0) & (c <= R1);
    wire [RW+2:0]   widened  = {remainder, sum[2*W-1:2*W-2]};
    wire [RW+2:0]   trial    = {1'b0, root, 2'b01};
    wire [RW+2:0]   less     = widened - trial;
    wire            fits     = ~less[RW+2];                        // widened >= trial
    wire [W-1:0]    divisor  = magnitude(axis == 2'd1 ? x : axis == 2'd2 ? y : z);
    wire [W+1:0]    dividend = {1'b0, residue, root[0]};             // (< 2 |axis| unless |axis| = 0)
    wire [W+1:0]    left     = dividend - {2'b0, divisor};
    wire            goes     = ~left[W+1];                         // dividend >= divisor
    wire [FEED_W+1:0] rounded = {1'b0, quotient} + 1'b1;

    always @(posedge clk) begin
        done <= 1'b0;
        if (rst) begin
            clock_count <= 9'd0; running <= 1'b0; cost <= {FEED_W{1'b0}};
        end else begin
            if (start | running) begin
                clock_count <= c + 9'd1;
                running     <= c != LAST;
            end
            if (start) begin
                sum <= {(2*W){1'b0}}; root <= {RW{1'b0}}; remainder <= {(RW+1){1'b0}};
                residue <= {W{1'b0}}; quotient <= {(FEED_W+1){1'b0}};
            end
            if ((start | running) & load) begin
                shifted    <= {{W{1'b0}}, operand};
                multiplier <= operand;
            end
            if (square) begin
                if (multiplier[0]) sum <= sum + shifted;
                shifted    <= shifted << 1;
                multiplier <= multiplier >> 1;
            end
            if (rooting) begin
                sum       <= sum << 2;
                root      <= {root[RW-2:0], fits};
                remainder <= fits ? less[RW:0] : widened[RW:0];
            end
            if (dividing) begin
                residue  <= goes ? left[W-1:0] : dividend[W-1:0];
                quotient <= {quotient[FEED_W-1:0], goes};
            end
            if (running && c == LAST) begin
                cost <= rounded[FEED_W:1];
                done <= 1'b1;
            end
        end
    end

    wire unused = &{1'b0, rounded[FEED_W+1], less[RW+1], widened[RW+2:RW+1], left[W], dividend[W+1:W]};
endmodule
`default_nettype wire
