// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Formal harness of the synchronization buffer (formal/step_sync.sby): a
// producer that honours STOP with the buffer's LATENCY (1: the linear and curve
// cores; 2: circ_arc, whose strobes come a cycle after the tick), a feed tick at
// will.  Properties: no step is refused (no overflow), steps in = steps out +
// stored (none lost, none duplicated), and the n-th step out is the n-th
// step in (checked for one arbitrary n with its direction bits).
module step_sync_check #(
    parameter integer LATENCY = 1   // 1 or 2
) (
    input wire       clk,
    input wire       rst,
    input wire [1:0] in_step,
    input wire [1:0] in_dir,
    input wire       tick
);
    wire       stop, out_valid, overflow;
    wire [1:0] out_step, out_dir, level;
    wire       out_data;
    step_sync #(.AXES(2), .DEPTH(2), .LATENCY(LATENCY), .DATA_W(1), .LW(2)) dut (
        .clk(clk), .rst(rst), .in_step(in_step), .in_dir(in_dir), .in_data(1'b0),
        .stop(stop), .tick(tick), .out_valid(out_valid), .out_step(out_step),
        .out_dir(out_dir), .out_data(out_data), .level(level), .overflow(overflow)
    );

`ifdef FORMAL
    reg f_past_valid = 1'b0;
    always @(posedge clk) f_past_valid <= 1'b1;
    always @(*) if (!f_past_valid) assume (rst);
    // The producer: a step only LATENCY cycles after a tick it was given (STOP low),
    // with no reset since.
    reg [1:0] f_given = 2'b00;           // a tick was given 1, 2 cycles ago
    always @(posedge clk) f_given <= rst ? 2'b00 : {f_given[0], !stop};
    always @(*) if (in_step != 2'b00) assume (!rst && f_given[LATENCY-1]);

    reg [5:0] n_in, n_out;
    (* anyconst *) reg [5:0] f_pick;
    reg [3:0] f_picked;                  // {dir, step} of step number f_pick
    reg       f_seen;
    wire push = in_step != 2'b00;
    wire pop  = out_valid && tick;
    always @(posedge clk) begin
        if (rst) begin
            n_in <= 6'd0; n_out <= 6'd0; f_seen <= 1'b0; f_picked <= 4'd0;
        end else begin
            n_in  <= n_in + {5'd0, push};
            n_out <= n_out + {5'd0, pop};
            if (push && n_in == f_pick) begin
                f_seen <= 1'b1; f_picked <= {in_dir, in_step};
            end
        end
    end
    always @(posedge clk) if (f_past_valid && !rst) begin
        assert (!overflow);
        assert (n_in - n_out == {4'd0, level});
        assert (level <= 2'd2);
        if (pop && n_out == f_pick) assert (f_seen && {out_dir, out_step} == f_picked);
    end
    wire unused = &{1'b0, out_data};
`endif
endmodule
`default_nettype wire
