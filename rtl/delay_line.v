// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Delay element with taps: taps[i] is `d` delayed by i+1 clock cycles.
// SU1665343: delay elements 12, 13, 14 (let the counters settle before the
// adder reads them), 19 and 26 (order the sector-switch corrections).  In RTL
// a delay fixes the order of micro-operations, not an analog time.
module delay_line #(
    parameter integer LENGTH = 2    // number of taps = longest delay in cycles (>= 1)
) (
    input  wire              clk,
    input  wire              rst,
    input  wire              clear,     // empty the line (end of work, input 32)
    input  wire              d,
    output wire [LENGTH-1:0] taps
);
    initial if (LENGTH < 1) $error("%m: LENGTH must be at least 1");

    reg [LENGTH-1:0] q;
    generate
        if (LENGTH == 1) begin : g_one
            always @(posedge clk) q <= (rst || clear) ? 1'b0 : d;
        end else begin : g_many
            always @(posedge clk) q <= (rst || clear) ? {LENGTH{1'b0}} : {q[LENGTH-2:0], d};
        end
    endgenerate
    assign taps = q;
endmodule
`default_nettype wire
