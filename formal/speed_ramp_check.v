// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Formal harness of the path-speed profile generator (formal/speed_ramp.sby) at
// small widths: FEED_W 6, NW 4, PF 3, LEN_W 8, ZW 12.  The environment is a profile
// queue whose head holds still until it is popped (a move: rate 1 .. 2^PF, length
// > 0, limit >= feed, a budget no larger than floor(2 rate length / (2^bs A)); or a
// barrier, finished at will), a quantum A > 0 and block_shift 2 or 3 that stay
// (REST = 1: a move enters only while the generator is at rest, so every move ends
// at rest), with hold and override at will.  Properties, besides the generator's own
// (n by at most one quantum a block, only at DDA ticks; the adders' registers):
//  - distance: whenever the generator is at rest, the travel since reset is the sum
//    of the lengths taken plus the last overshoot, 0 <= overshoot < A;
//  - n falls to 0 inside a segment only under hold;
//  - REST = 1: never `late` (braking to rest is always in time; the last quantum
//    drops from n = 1 exactly at the clock the segment ends).
// INVARIANTS_ONLY: the generator's own properties alone (the k-induction task).
module speed_ramp_check #(
    parameter integer REST = 1      // 1: moves enter at rest only; 0: look-ahead too
) (
    input wire       clk,
    input wire       rst,
    input wire       next_valid,
    input wire       next_barrier,
    input wire [5:0] next_feed,
    input wire [5:0] next_limit,
    input wire [3:0] next_exit,
    input wire [3:0] next_rate,
    input wire [7:0] next_length,
    input wire [11:0] next_budget,
    input wire       barrier_done,
    input wire [5:0] speed_quantum,
    input wire [3:0] block_shift,
    input wire [7:0] override,
    input wire       hold
);
    wire next_pop, up, down, block, moving, segment, stopped, late;
    wire [5:0] speed;
    speed_ramp #(.FEED_W(6), .NW(4), .PF(3), .LEN_W(8), .ZW(12)) dut (
        .clk(clk), .rst(rst), .next_valid(next_valid), .next_barrier(next_barrier),
        .next_feed(next_feed), .next_limit(next_limit), .next_exit(next_exit),
        .next_rate(next_rate), .next_length(next_length), .next_budget(next_budget),
        .next_pop(next_pop), .barrier_done(barrier_done), .speed_quantum(speed_quantum),
        .block_shift(block_shift), .override(override), .hold(hold), .speed(speed),
        .up(up), .down(down), .block(block), .moving(moving), .segment(segment),
        .stopped(stopped), .late(late));

`ifdef FORMAL
    reg f_past_valid = 1'b0;
    always @(posedge clk) f_past_valid <= 1'b1;
    always @(*) if (!f_past_valid) assume (rst);

    // the queue's head holds until the clock after a pop
    always @(posedge clk) if (f_past_valid && !$past(rst) && $past(next_valid) && !$past(next_pop))
        assume (next_valid && $stable(next_barrier) && $stable(next_feed) && $stable(next_limit) &&
                $stable(next_exit) && $stable(next_rate) && $stable(next_length) && $stable(next_budget));
    wire [15:0] f_scale = {10'd0, speed_quantum} << block_shift;
    always @(*) if (next_valid && !next_barrier) begin
        assume (next_rate != 4'd0 && next_rate <= 4'd8 && next_length != 8'd0 && next_limit >= next_feed);
        assume ({4'd0, next_budget} * {16'd0, f_scale} <= 32'd2 * {28'd0, next_rate} * {24'd0, next_length});
    end
    always @(*) begin
        assume (speed_quantum != 6'd0 && block_shift >= 4'd2 && block_shift <= 4'd3);
        if (REST != 0 && next_valid && !next_barrier && !next_pop) assume (!moving);
    end
    always @(posedge clk) if (f_past_valid && !$past(rst))
        assume ($stable(speed_quantum) && $stable(block_shift));
`ifdef PIPELINE
    // (the pipeline task: a plain environment, so that the bounded check reaches the
    // decisions on the budget at n >= 2: quantum 1, blocks of 4, no hold, no barrier)
    always @(*) assume (speed_quantum == 6'd1 && block_shift == 4'd2 && !hold && !next_barrier &&
                        override == 8'd100);
`endif

    // distance: travel since reset against the lengths taken
    reg [15:0] f_travel, f_taken;
    reg        f_late;
    always @(posedge clk) begin
        if (rst) begin
            f_travel <= 16'd0; f_taken <= 16'd0; f_late <= 1'b0;
        end else begin
            f_travel <= f_travel + {10'd0, speed};
            if (next_pop && !next_barrier) f_taken <= f_taken + {8'd0, next_length};
            if (late) f_late <= 1'b1;
        end
    end
`ifndef INVARIANTS_ONLY
    always @(posedge clk) if (f_past_valid && !rst && !$past(rst)) begin
        if (!moving && !next_pop && !f_late && !late)     // (a late stop may overshoot)
            assert (f_travel >= f_taken && f_travel < f_taken + {10'd0, speed_quantum});
        if (segment && speed == 6'd0 && $past(speed) != 6'd0) assert ($past(hold) || next_pop);
        if (REST != 0) assert (!late);
    end
`endif
    wire unused = &{1'b0, up, down, block, stopped};
`endif
endmodule
`default_nettype wire
