// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Speed-setting block of the lecture ("БЗС"): turns the programmed
// feed into the feed tick that releases steps from the synchronization
// buffer, with a constant path speed.
//
// A phase accumulator: `acc` grows by the feed every clock; `tick` is high
// while acc >= 0 (the interval after the last step has run out).  A step
// leaving (`take`) costs its path length: 1, sqrt(2) or sqrt(3) times 2^FRAC
// for a step on one, two or three axes, so the interval after a diagonal step
// is 1.41 times longer and after a 3-axis step 1.73 times (the lecture's rule).
// The path speed is feed / 2^FRAC steps per clock.  The costs are rounded to
// the nearest integer: relative speed error <= 2^-(FRAC+1) / sqrt(2).  They are
// exact integer square roots, rounded to nearest, of 2 * 2^(2 FRAC) and
// 3 * 2^(2 FRAC), formed by the constant function `root` on 2 FRAC + 4 bit words
// (digit by digit, shifts and subtractions only), so any FRAC up to 64 is exact.
//
// While `tick` is high and no step leaves, acc holds (no burst of stored
// ticks after a pause).  The feed of the step that leaves is latched with it
// and paces the interval after that step, so a new feed takes effect exactly
// at the first step of its segment: no glitch, no lost or extra tick.  The
// phase left over (less than one clock) carries only while the feed stays.
module feed_rate #(
    parameter integer FEED_W = 16,  // width of the feed word (>= 1)
    parameter integer FRAC   = 16   // fraction bits: an axial step costs 2^FRAC (1 .. 64)
) (
    input  wire              clk,
    input  wire              rst,
    input  wire [FEED_W-1:0] feed,  // feed of the step that leaves, steps/clock * 2^FRAC
    input  wire [1:0]        axes,  // number of axes of that step (0 counts as 1)
    input  wire              take,  // the step leaves now (taken only with `tick`)
    output wire              tick   // level: a step may leave
);
    initial begin
        if (FEED_W < 1) $error("%m: FEED_W must be at least 1");
        if (FRAC < 1 || FRAC > 64) $error("%m: FRAC must be 1 .. 64");
    end

    localparam integer AW = (FEED_W > FRAC + 2 ? FEED_W : FRAC + 2) + 2;  // signed accumulator
    // radicand words: 3 * 2^(2 FRAC) < 2^(2 FRAC + 2), and at least AW bits
    localparam integer RW = 2 * FRAC + 4 > AW ? 2 * FRAC + 4 : AW + AW % 2;

    // round(sqrt(n)): the integer square root digit by digit (two radicand bits a
    // digit), then up by one if n - r^2 > r (n is an integer, so never a tie).
    function [RW-1:0] root(input [RW-1:0] n);
        reg [RW-1:0] rest, r, trial;
        integer i;
        begin
            rest = n;
            r    = {RW{1'b0}};
            for (i = RW / 2 - 1; i >= 0; i = i - 1) begin
                trial = (r << (i + 1)) | ({{(RW-1){1'b0}}, 1'b1} << (2 * i));  // (2r + 2^i) 2^i
                if (rest >= trial) begin
                    rest = rest - trial;
                    r    = r | ({{(RW-1){1'b0}}, 1'b1} << i);
                end
            end
            root = rest > r ? r + 1'b1 : r;
        end
    endfunction

    localparam [RW-1:0] ONE_SQUARED = {{(RW-1){1'b0}}, 1'b1} << (2 * FRAC);
    localparam [RW-1:0] COST1 = {{(RW-1){1'b0}}, 1'b1} << FRAC;
    localparam [RW-1:0] COST2 = root(ONE_SQUARED << 1);             // round(sqrt(2) * 2^FRAC)
    localparam [RW-1:0] COST3 = root((ONE_SQUARED << 1) + ONE_SQUARED);  // round(sqrt(3) * 2^FRAC)

    reg  [AW-1:0]     acc;
    reg  [FEED_W-1:0] feed_q;
    reg  [AW-1:0]     cost;
    always @* begin
        case (axes)
            2'd2:    cost = COST2[AW-1:0];
            2'd3:    cost = COST3[AW-1:0];
            default: cost = COST1[AW-1:0];
        endcase
    end

    assign tick = ~acc[AW-1];
    wire [AW-1:0] feed_ext   = {{(AW-FEED_W){1'b0}}, feed};
    wire [AW-1:0] feed_q_ext = {{(AW-FEED_W){1'b0}}, feed_q};

    always @(posedge clk) begin
        if (rst) begin
            acc    <= {AW{1'b0}};
            feed_q <= {FEED_W{1'b0}};
        end else if (take & tick) begin
            // The phase left over (< one clock of the old feed) only carries
            // at the same feed; a new feed starts from phase 0.
            acc    <= (feed == feed_q ? acc : {AW{1'b0}}) + feed_ext - cost;
            feed_q <= feed;
        end else if (~tick) begin
            acc    <= acc + feed_q_ext;
        end
    end
endmodule
`default_nettype wire
