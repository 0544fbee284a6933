// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Path-speed profile of motion_top: the lecture's speed-setting block ("БЗС")
// grown into a profile generator with acceleration.
//   profile queue ....... sync_fifo u_queue: one entry per accepted command, pushed with
//                         the geometry queue of motion_top; a move's profile (feed, limit,
//                         exit, rate, length, budget) or a BARRIER (dwell / event)
//   virtual domain ...... speed_ramp u_ramp: the trapezoid, n quanta of speed_quantum,
//                         braking to the next segment's exit speed (0 before a barrier,
//                         at the end of the queue, or while `hold` is on)
//   S-curve ............. jerk_filter u_jerk: the moving sum of the last 2^jerk_shift
//                         block speeds (jerk_shift 0: the trapezoid itself)
//   step domain ......... step_pacer u_pacer: phase += that sum every clock; the waiting
//                         step of the synchronization buffer leaves when the phase covers
//                         its cost (the segment's cost, or the lecture's 1, sqrt 2, sqrt 3)
// A barrier entry is popped by the ramp once the dispatcher has finished that dwell or
// event (`barrier_done`) and the speed is 0, so a dwell or event never overlaps motion.
// The ramp's outputs are registers: `speed` is v of this clock, decided at the edge
// that ended the block-end clock before (`block` then).  The filter takes a change of
// the speed in the clock it ends, once per block, as a code of +-1 quantum: here its
// own copy of the speed, speed_f, follows the ramp's one quantum per block tick
// (block_q, the ramp's block a clock late) towards the ramp's speed.  A change made
// at a block end (every one but the last drop of a stop) is thus passed on in the
// next clock: the step domain runs one clock behind the virtual domain.  The last drop
// of a stop comes at the clock the segment ends, inside a block when block_shift > 0:
// speed_f follows it in the next clock too, and the filter books the rest of that
// block's travel as a debt it pays back before it empties, so the step domain's
// distance equals the ramp's at every stop (nothing accumulates over many stops).
module path_profile #(
    parameter integer FEED_W = 16,  // speed word width: path units per clock (>= 2)
    parameter integer FRAC   = 16,  // fraction bits: an axial step is 2^FRAC path units (1 .. 64)
    parameter integer NW     = 16,  // speed in quanta, width (1 .. FEED_W)
    parameter integer PF     = 12,  // rate fraction bits: rate 2^PF = one quantum per block (>= 1)
    parameter integer LEN_W  = 34,  // segment length width, path units (>= FEED_W)
    parameter integer ZW     = 48,  // braking budget width (>= LEN_W)
    parameter integer MW     = 6,   // jerk filter depth 2^MW blocks (2 .. 15)
    parameter integer QDEPTH = 4,   // entries the profile queue holds (>= 1)
    parameter integer QLW    = 3    // width of `level` (2^QLW > QDEPTH)
) (
    input  wire              clk,
    input  wire              rst,           // synchronous; motion_top also flushes with it
    // profile queue input (pushed with motion_top's geometry queue)
    input  wire              push,
    input  wire              push_barrier,  // a dwell or event: stop before it
    input  wire [FEED_W-1:0] push_feed,
    input  wire [FEED_W-1:0] push_limit,
    input  wire [NW-1:0]     push_exit,
    input  wire [PF:0]       push_rate,
    input  wire [LEN_W-1:0]  push_length,
    input  wire [ZW-1:0]     push_budget,
    output wire              full,
    output wire [QLW-1:0]    level,
    input  wire              barrier_done,  // strobe: the dispatcher finished a dwell / event
    // settings
    input  wire [FEED_W-1:0] speed_quantum, // A, path units per clock (constant while busy)
    input  wire [3:0]        block_shift,
    input  wire [3:0]        jerk_shift,    // 0 .. MW (changed only while idle)
    /* verilator lint_off SYMRSVDWORD */   // `override` is a C++ word, not a Verilog one
    input  wire [7:0]        override,      // percent of the feed, 1 .. 200
    /* verilator lint_on SYMRSVDWORD */
    input  wire              hold,          // decelerate to 0 and stay
    // step domain
    input  wire              step_valid,    // a step waits in the synchronization buffer
    input  wire [1:0]        step_axes,
    input  wire [FEED_W-1:0] step_cost,     // path units of that step; 0: the lecture's costs
    input  wire              drive_ready,
    output wire              fire,          // the waiting step leaves now
    // status
    output wire [FEED_W-1:0] speed,         // virtual speed v, path units per clock
    output wire [FEED_W-1:0] cruise,        // the feed of the segment the ramp runs (the laser's power_scale)
    output wire [FEED_W+MW-1:0] step_speed, // the S-curve filter's sum: 2^speed_shift x the speed of the steps
    output wire [3:0]        speed_shift,   // the filter's shift in use
    output wire              moving,        // the ramp runs or the filter still sums speed
    output wire              stopped,       // hold has brought the speed to 0, and the filter's to 0
    output wire              still,         // no speed in the ramp or the filter: no step comes
    output wire              late,          // strobe: the ramp reached a stop or exit above its speed
    output wire              overrun        // the pacer's phase saturated: distance lost (sticky until rst)
);
    initial begin
        if (FEED_W < 2) $error("%m: FEED_W must be at least 2");
        if (FRAC < 1 || FRAC > 64) $error("%m: FRAC must be 1 .. 64");
        if (NW < 1 || NW > FEED_W) $error("%m: NW must be 1 .. FEED_W");
        if (PF < 1) $error("%m: PF must be at least 1");
        if (LEN_W < FEED_W) $error("%m: LEN_W must be at least FEED_W");
        if (ZW < LEN_W) $error("%m: ZW must be at least LEN_W");
        if (MW < 2 || MW > 15) $error("%m: MW must be 2 .. 15");
        if (QDEPTH < 1 || (1 << QLW) <= QDEPTH) $error("%m: need QDEPTH >= 1 and 2^QLW > QDEPTH");
    end

    localparam integer PW    = 1 + 2 * FEED_W + NW + PF + 1 + LEN_W + ZW;
    localparam integer SUM_W = FEED_W + MW;
    localparam integer GUARD = 8;                                   // the pacer's phase headroom
    localparam integer PHASE_W = (FEED_W > FRAC + 1 ? FEED_W : FRAC + 1) + MW + GUARD;

    wire [PW-1:0]     head;
    wire              head_valid, next_pop, unused_overflow;
    wire              h_barrier;
    wire [FEED_W-1:0] h_feed, h_limit;
    wire [NW-1:0]     h_exit;
    wire [PF:0]       h_rate;
    wire [LEN_W-1:0]  h_length;
    wire [ZW-1:0]     h_budget;
    sync_fifo #(.WIDTH(PW), .DEPTH(QDEPTH), .LW(QLW)) u_queue (
        .clk(clk), .rst(rst), .push(push),
        .din({push_barrier, push_feed, push_limit, push_exit, push_rate, push_length, push_budget}),
        .pop(next_pop), .dout(head), .valid(head_valid), .full(full), .level(level),
        .overflow(unused_overflow)
    );
    assign {h_barrier, h_feed, h_limit, h_exit, h_rate, h_length, h_budget} = head;

    wire up, down, block, ramp_moving, ramp_stopped, segment;
    speed_ramp #(.FEED_W(FEED_W), .NW(NW), .PF(PF), .LEN_W(LEN_W), .ZW(ZW)) u_ramp (
        .clk(clk), .rst(rst),
        .next_valid(head_valid), .next_barrier(h_barrier), .next_feed(h_feed), .next_limit(h_limit),
        .next_exit(h_exit), .next_rate(h_rate), .next_length(h_length), .next_budget(h_budget),
        .next_pop(next_pop), .barrier_done(barrier_done),
        .speed_quantum(speed_quantum), .block_shift(block_shift), .override(override), .hold(hold),
        .speed(speed), .cruise(cruise), .up(up), .down(down), .block(block), .moving(ramp_moving), .stopped(ramp_stopped),
        .late(late), .segment(segment)
    );

    reg  [FEED_W-1:0] speed_f;      // the filter's speed: follows `speed`, a quantum per block
    reg               block_q;      // the ramp's block a clock late
    wire              rise = block_q && speed > speed_f;
    wire              fall = speed < speed_f;   // a stop's last drop: at once, inside a block
    always @(posedge clk) begin
        if (rst) begin
            speed_f <= {FEED_W{1'b0}};
            block_q <= 1'b0;
        end else begin
            block_q <= block;
            if (rise)
                speed_f <= speed_f + speed_quantum;
            else if (fall)
                speed_f <= speed_f - speed_quantum;
        end
    end

    wire [SUM_W-1:0] sum;
    wire [3:0]       shift;
    assign step_speed  = sum;
    assign speed_shift = shift;
    wire             empty;
    jerk_filter #(.FEED_W(FEED_W), .MW(MW), .SUM_W(SUM_W)) u_jerk (
        .clk(clk), .rst(rst), .speed(speed_f), .up(rise), .down(fall), .block(block_q),
        .speed_quantum(speed_quantum), .jerk_shift(jerk_shift), .sum(sum), .shift(shift), .empty(empty)
    );

    wire                             due;
    wire [PHASE_W-1:0]               phase;
    step_pacer #(.FEED_W(FEED_W), .FRAC(FRAC), .MW(MW), .SUM_W(SUM_W), .GUARD(GUARD), .PHASE_W(PHASE_W)) u_pacer (
        .clk(clk), .rst(rst), .sum(sum), .jerk_shift(shift), .step_valid(step_valid),
        .step_axes(step_axes), .step_cost(step_cost), .drive_ready(drive_ready), .fire(fire),
        .due(due), .overrun(overrun), .phase(phase)
    );

    assign moving = ramp_moving | ~empty;
    // The S-curve filter lags the ramp by up to 2^jerk_shift blocks: a hold is at rest, and
    // the machine still, only once the filter has no speed either
    assign still   = speed == {FEED_W{1'b0}} && empty;
    assign stopped = ramp_stopped & empty;
    wire unused = &{1'b0, unused_overflow, due, phase, up, down, segment};   // motion_top refuses a push when either queue is full
endmodule
`default_nettype wire
