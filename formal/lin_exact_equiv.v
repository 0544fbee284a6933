// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Equivalence of lin_exact (the production core, retimed) and su1571551 with
// EXACT = 1 (the patent's circuit, expression (1)): formal/lin_exact_equiv.sby.
// The .sby script builds `miter` with Yosys's `miter -equiv`: both cores on the
// same inputs (in_clk, in_rst, in_start, in_tick, in_x, in_y), `trigger` high
// when any output differs.  Besides their ports, the script exposes the state
// the two share under the same names (2F, counters 1 and 2, the start-of-frame
// pulse, triggers 14 and 15, the held -S and L - S) as outputs, so the miter
// compares them too and k-induction closes.  This wrapper starts from a reset
// and asserts from the second cycle after it (the held operands are taken in
// every idle cycle, so they agree from then on) that nothing differs.
module lin_exact_equiv #(
    parameter integer WIDTH = 4     // width of X, Y: the .sby sets the cores' to the same
) (
    input wire             clk,
    input wire             rst,
    input wire             start,
    input wire             tick,
    input wire [WIDTH-1:0] x,
    input wire [WIDTH-1:0] y
);
    wire trigger;
    miter u_miter (
        .in_clk(clk), .in_rst(rst), .in_start(start), .in_tick(tick), .in_x(x), .in_y(y),
        .trigger(trigger)
    );
`ifdef FORMAL
    reg [1:0] f_cycle = 2'd0;       // 0: reset, 1: the held operands settle, 2: compared
    always @(posedge clk) if (f_cycle != 2'd2) f_cycle <= f_cycle + 2'd1;
    always @(*) if (f_cycle == 2'd0) assume (rst);
    always @(*) if (f_cycle == 2'd2) assert (!trigger);
`endif
endmodule
`default_nettype wire
