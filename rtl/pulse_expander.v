// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Pulse expander: `active` is high for LENGTH cycles after a `trigger` cycle
// (a new trigger restarts the count).  SU1665343: expander 25, the inhibit
// on AND 10, 11 while the sector-switch correction runs.
module pulse_expander #(
    parameter integer LENGTH = 4    // cycles the inhibit lasts (1 .. 255)
) (
    input  wire clk,
    input  wire rst,
    input  wire clear,      // drop the inhibit (end of work)
    input  wire trigger,
    output wire active
);
    initial if (LENGTH < 1 || LENGTH > 255) $error("%m: LENGTH must be 1 .. 255");

    localparam [7:0] START = LENGTH[7:0];
    reg [7:0] count_q;
    always @(posedge clk) begin
        if (rst || clear)
            count_q <= 8'd0;
        else if (trigger)
            count_q <= START;
        else if (count_q != 8'd0)
            count_q <= count_q - 8'd1;
    end
    assign active = count_q != 8'd0;
endmodule
`default_nettype wire
