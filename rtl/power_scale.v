// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Laser power that follows the speed (no patent element: Grbl's dynamic laser power, M4
// in laser mode): so that a corner or a start, where the machine moves slower, gets the
// same energy per length as the cruise,
//
//     scaled = duty * ratio / 65536,   ratio = floor(min(speed, feed) * 65536 / feed)
//
// (ratio 65535 at or above the feed, 0 while feed is 0).  A free-running sequence of 34
// clocks takes duty, speed and feed (round 0), divides (restoring, a quotient bit a clock,
// rounds 1 .. 16), multiplies (shift and add, rounds 17 .. 32) and sets `scaled` (round
// 33): it follows the inputs within 68 clocks.
module power_scale #(
    parameter integer FEED_W = 16   // width of speed and feed (>= 1)
) (
    input  wire              clk,
    input  wire              rst,
    input  wire [15:0]       duty,     // the programmed power, 0 .. 65535
    input  wire [FEED_W-1:0] speed,    // the path speed now
    input  wire [FEED_W-1:0] feed,     // the cruise speed of the move (same units)
    output reg  [15:0]       scaled
);
    initial begin
        if (FEED_W < 1) $error("%m: FEED_W must be at least 1");
    end

    localparam [5:0] MULTIPLY = 6'd17, LAST = 6'd33;   // 1 .. 16 divide, 17 .. 32 multiply

    reg  [5:0]        round;        // 0: take the inputs; 33: the result
    reg  [FEED_W-1:0] remainder;    // < divisor
    reg  [FEED_W-1:0] divisor;
    reg               zero, whole;  // feed 0: ratio 0; speed >= feed: ratio 65535
    reg  [15:0]       ratio;        // quotient bits, shifted in highest first
    reg  [15:0]       power;        // duty's bits still to add, lowest first
    reg  [31:0]       addend;       // the ratio, shifted
    reg  [31:0]       product;
    wire [FEED_W:0]   doubled = {remainder, 1'b0};
    wire [FEED_W+1:0] less    = {1'b0, doubled} - {2'b00, divisor};
    wire              fits    = ~less[FEED_W+1];                       // doubled >= divisor
    wire [15:0]       factor  = zero ? 16'd0 : whole ? 16'hFFFF : ratio;
    wire              first   = round == MULTIPLY;
    wire [31:0]       base    = first ? 32'd0 : product;               // the product so far
    wire [31:0]       term    = first ? {16'd0, factor} : addend;      // factor << (round - 17)

    always @(posedge clk) begin
        if (rst) begin
            round     <= 6'd0;
            remainder <= {FEED_W{1'b0}};
            divisor   <= {FEED_W{1'b0}};
            zero      <= 1'b1;
            whole     <= 1'b0;
            ratio     <= 16'd0;
            power     <= 16'd0;
            addend    <= 32'd0;
            product   <= 32'd0;
            scaled    <= 16'd0;
        end else begin
            round <= round == LAST ? 6'd0 : round + 6'd1;
            if (round == 6'd0) begin
                zero      <= feed == {FEED_W{1'b0}};
                whole     <= speed >= feed;
                remainder <= speed >= feed ? {FEED_W{1'b0}} : speed;
                divisor   <= feed;
                power     <= duty;
            end else if (round < MULTIPLY) begin
                ratio     <= {ratio[14:0], fits};
                remainder <= fits ? less[FEED_W-1:0] : doubled[FEED_W-1:0];
            end else if (round < LAST) begin
                product <= power[0] ? base + term : base;
                addend  <= term << 1;
                power  <= power >> 1;
            end else begin
                scaled <= product[31:16];
            end
        end
    end
endmodule
`default_nettype wire
