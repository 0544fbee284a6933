// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Step pacer of the speed-setting block of the lecture ("БЗС"): releases the
// steps waiting in the synchronization buffer (step_sync) at the path speed of
// the profile.  A phase accumulator:
//
//     phase += sum every clock            (sum = F of jerk_filter, M x the speed)
//     a waiting step leaves (`fire`) when phase >= cost << shift and the output
//     stage is ready; then phase -= cost << shift            (M = 2^shift)
//
// cost is the step's `step_cost` (path units per step event, the same for every
// step of a segment: its true length / N) or, when step_cost = 0, the lecture's
// 1, sqrt(2), sqrt(3) x 2^FRAC for a step on 1, 2, 3 axes (step_cost.v).  No
// distance is ever lost: when a step is due but none is waiting (or the output
// stage is busy) the phase keeps growing, and the steps then leave one per
// clock until it has caught up.  Hold is a deceleration of the ramp upstream,
// not a gate here.  The phase has GUARD bits above the largest cost << MW: it
// absorbs a stall of 2^GUARD clocks at F = the largest cost << MW per clock
// (at a realistic speed, far longer); beyond that it saturates and `overrun`
// stays high until rst (distance lost: an error).
module step_pacer #(
    parameter integer FEED_W = 16,          // width of step_cost and of the speed (>= 2)
    parameter integer FRAC   = 16,          // fraction bits: an axial step costs 2^FRAC (1 .. 64)
    parameter integer MW     = 6,           // largest jerk_shift (2 .. 15), as jerk_filter's
    parameter integer SUM_W  = FEED_W + MW, // width of sum: must be FEED_W + MW
    parameter integer GUARD  = 8,           // phase bits above the largest cost << MW (1 .. 32)
    parameter integer PHASE_W = FEED_W > FRAC + 1 ? FEED_W + MW + GUARD : FRAC + 1 + MW + GUARD  // width of phase: must be max(FEED_W, FRAC + 1) + MW + GUARD
) (
    input  wire              clk,
    input  wire              rst,
    input  wire [SUM_W-1:0]  sum,          // F: phase advance of this clock
    input  wire [3:0]        jerk_shift,   // jerk_filter's `shift` (above MW counts as MW)
    input  wire              step_valid,   // a step waits in step_sync
    input  wire [1:0]        step_axes,    // its number of axes (0 counts as 1)
    input  wire [FEED_W-1:0] step_cost,    // its cost, 0 = the lecture's costs
    input  wire              drive_ready,  // the output stage takes a step now
    output wire              fire,         // the step leaves this clock
    output wire              due,          // phase >= cost << shift
    output reg               overrun,      // the phase saturated (sticky until rst)
    output reg [PHASE_W-1:0] phase         // the phase accumulator (monitor)
);
    initial begin
        if (FEED_W < 2) $error("%m: FEED_W must be at least 2");
        if (FRAC < 1 || FRAC > 64) $error("%m: FRAC must be 1 .. 64");
        if (MW < 2 || MW > 15) $error("%m: MW must be 2 .. 15");
        if (SUM_W != FEED_W + MW) $error("%m: SUM_W must be FEED_W + MW");
        if (GUARD < 1 || GUARD > 32) $error("%m: GUARD must be 1 .. 32");
        if (PHASE_W != (FEED_W > FRAC + 1 ? FEED_W : FRAC + 1) + MW + GUARD)
            $error("%m: PHASE_W must be max(FEED_W, FRAC + 1) + MW + GUARD");
    end

    localparam integer CW = FEED_W > FRAC + 1 ? FEED_W : FRAC + 1;  // cost width
    localparam integer PW = PHASE_W;
    localparam [3:0]   DEEPEST = MW[3:0];

    wire [CW-1:0] lecture;
    step_cost #(.FRAC(FRAC), .COST_W(CW)) u_cost (.axes(step_axes), .cost(lecture));

    wire [3:0]    used = jerk_shift > DEEPEST ? DEEPEST : jerk_shift;
    wire [CW-1:0] cost = step_cost != {FEED_W{1'b0}} ? {{(CW-FEED_W){1'b0}}, step_cost} : lecture;
    wire [PW-1:0] need = {{(PW-CW){1'b0}}, cost} << used;
    assign due  = phase >= need;
    assign fire = step_valid & drive_ready & due;
    // The next phase for both outcomes, formed beside the test rather than after it:
    // phase + sum, and phase - need + sum (>= 0 when the step fires) as one carry-save
    // layer (phase, sum, ~need) and one adder; bit PW of either is the overflow.
    wire [PW:0]   sum_w = {{(PW+1-SUM_W){1'b0}}, sum};
    wire [PW:0]   keep  = {1'b0, phase} + sum_w;
    wire [PW:0]   neg   = ~{1'b0, need};
    wire [PW:0]   bits  = {1'b0, phase} ^ sum_w ^ neg;
    wire [PW-1:0] carry = (phase & sum_w[PW-1:0]) | (phase & neg[PW-1:0]) | (sum_w[PW-1:0] & neg[PW-1:0]);
    wire [PW:0]   taken = bits + {carry, 1'b1};             // phase + sum - need mod 2^(PW+1)
    wire [PW:0]   next  = fire ? taken : keep;

    always @(posedge clk) begin
        if (rst) begin
            phase   <= {PW{1'b0}};
            overrun <= 1'b0;
        end else if (next[PW]) begin
            phase   <= {PW{1'b1}};
            overrun <= 1'b1;
        end else begin
            phase   <= next[PW-1:0];
        end
    end
endmodule
`default_nettype wire
