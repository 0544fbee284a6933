// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Formal harness of the step pacer (formal/step_pacer.sby) behind the
// synchronization buffer, as motion_top wires them: step_sync's oldest step
// (its cost as the step's data) is offered to step_pacer, whose `fire` is the
// buffer's tick.  The producer honours STOP (LATENCY 1); F (`sum`), the output
// stage's ready and every step's cost are free inputs, so the speed may go to
// 0 and back at any time (a feed hold) and the output stage may stall.
// Properties:
//   distance: phase = F given - (cost << shift of the steps gone), modulo
//             2^16 ghost counters, unless `overrun` (phase saturated);
//             (k-induction: holds in every reachable state);
//   steps:    a step leaves only when it waits, the output stage is ready and
//             the phase covers it; none is refused, lost or duplicated (steps
//             in = steps out + stored); the n-th step out is the n-th step in,
//             with its direction and cost (one arbitrary n; bounded, from reset;
//             left out with DISTANCE_ONLY, as the order is not 1-inductive).
module step_pacer_check #(
    parameter integer FEED_W = 4,
    parameter integer FRAC   = 2,
    parameter integer MW     = 2,
    parameter integer GUARD  = 2
) (
    input wire              clk,
    input wire              rst,
    input wire [1:0]        in_step,
    input wire [1:0]        in_dir,
    input wire [FEED_W-1:0] in_cost,
    input wire [FEED_W+MW-1:0] sum,
    input wire              drive_ready
);
    localparam integer SUM_W = FEED_W + MW;
    localparam integer CW    = FEED_W > FRAC + 1 ? FEED_W : FRAC + 1;
    localparam integer PW    = CW + MW + GUARD;
    initial if (FRAC != 2) $error("%m: the lecture costs below are for FRAC 2");

    (* anyconst *) reg [3:0] jerk_shift;

    wire              stop, out_valid, overflow, fire, due, overrun;
    wire [PW-1:0]     phase;
    wire [1:0]        out_step, out_dir, level;
    wire [FEED_W-1:0] out_cost;
    step_sync #(.AXES(2), .DEPTH(2), .LATENCY(1), .DATA_W(FEED_W), .LW(2)) u_sync (
        .clk(clk), .rst(rst), .in_step(in_step), .in_dir(in_dir), .in_data(in_cost),
        .stop(stop), .tick(fire), .out_valid(out_valid), .out_step(out_step),
        .out_dir(out_dir), .out_data(out_cost), .level(level), .overflow(overflow)
    );
    wire [1:0] axes = {1'b0, out_step[0]} + {1'b0, out_step[1]};
    step_pacer #(.FEED_W(FEED_W), .FRAC(FRAC), .MW(MW), .SUM_W(SUM_W), .GUARD(GUARD)) dut (
        .clk(clk), .rst(rst), .sum(sum), .jerk_shift(jerk_shift), .step_valid(out_valid),
        .step_axes(axes), .step_cost(out_cost), .drive_ready(drive_ready),
        .fire(fire), .due(due), .overrun(overrun), .phase(phase)
    );

`ifdef FORMAL
    reg f_past_valid = 1'b0;
    always @(posedge clk) f_past_valid <= 1'b1;
    always @(*) if (!f_past_valid) assume (rst);
    // the producer: a step only in the cycle after a tick it was given (STOP low)
    reg f_given = 1'b0;
    always @(posedge clk) f_given <= rst ? 1'b0 : !stop;
    always @(*) if (in_step != 2'b00) assume (!rst && f_given);

    // the cost the pacer must charge: at FRAC 2 the lecture's are 4 and
    // round(sqrt(2) * 4) = 6 (two axes)
    wire [CW-1:0] lecture = axes == 2'd2 ? 6 : 4;
    wire [3:0]  used    = jerk_shift > MW ? MW[3:0] : jerk_shift;
    wire [CW-1:0] cost  = out_cost != {FEED_W{1'b0}} ? {{(CW-FEED_W){1'b0}}, out_cost} : lecture;
    wire [15:0] charge  = {{(16-CW){1'b0}}, cost} << used;

    reg [15:0] f_given_f, f_charged;
    reg [5:0]  n_in, n_out;
    (* anyconst *) reg [5:0] f_pick;
    reg [FEED_W+3:0] f_picked;             // {cost, dir, step} of step number f_pick
    reg        f_seen;
    wire push = in_step != 2'b00;
    always @(posedge clk) begin
        if (rst) begin
            f_given_f <= 16'd0; f_charged <= 16'd0;
            n_in <= 6'd0; n_out <= 6'd0; f_seen <= 1'b0; f_picked <= {(4 + FEED_W){1'b0}};
        end else begin
            f_given_f <= f_given_f + {{(16-SUM_W){1'b0}}, sum};
            f_charged <= f_charged + (fire ? charge : 16'd0);
            n_in  <= n_in + {5'd0, push};
            n_out <= n_out + {5'd0, fire};
            if (push && n_in == f_pick) begin
                f_seen <= 1'b1; f_picked <= {in_cost, in_dir, in_step};
            end
        end
    end
    always @(*) if (f_past_valid && !rst) begin
        // distance: nothing lost or created while the phase has room
        if (!overrun) assert ({{(16-PW){1'b0}}, phase} == f_given_f - f_charged);
        // a step leaves only when offered, ready and covered
        if (fire) assert (out_valid && drive_ready && {{(16-PW){1'b0}}, phase} >= charge);
        if (out_valid && drive_ready && {{(16-PW){1'b0}}, phase} >= charge) assert (fire);
    end
`ifndef DISTANCE_ONLY
    always @(posedge clk) if (f_past_valid && !rst && !$past(rst)) begin
        assert (!overflow);
        assert (n_in - n_out == {4'd0, level});
        if ($past(fire && n_out == f_pick)) assert ($past(f_seen && {out_cost, out_dir, out_step} == f_picked));
    end
`endif
    wire unused = &{1'b0, due};
`endif
endmodule
`default_nettype wire
