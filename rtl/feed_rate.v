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
// 3 * 2^(2 FRAC), formed at elaboration by step_cost (shared with step_pacer),
// so any FRAC up to 64 is exact.
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
    reg  [AW-1:0]     acc;
    reg  [FEED_W-1:0] feed_q;
    wire [AW-1:0]     cost;
    step_cost #(.FRAC(FRAC), .COST_W(AW)) u_cost (.axes(axes), .cost(cost));

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
