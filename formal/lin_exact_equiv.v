// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Equivalence miter (formal/lin_exact_equiv.sby): the production core
// lin_exact and the patent's circuit su1571551 in its exact mode (EXACT = 1,
// expression (1)) on the same free inputs, rst, start and tick included; every
// output must be equal in every cycle.
module lin_exact_equiv #(
    parameter integer WIDTH = 3     // width of X, Y (the .sby's bound is for 3)
) (
    input wire             clk,
    input wire             rst,
    input wire             start,
    input wire             tick,
    input wire [WIDTH-1:0] x,
    input wire [WIDTH-1:0] y
);
    wire [5:0] patent, retimed;     // {step_x, step_y, dir_x, dir_y, busy, done}
    su1571551 #(.WIDTH(WIDTH), .EXACT(1)) u_patent (
        .clk(clk), .rst(rst), .start(start), .tick(tick), .x(x), .y(y),
        .step_x(patent[5]), .step_y(patent[4]), .dir_x(patent[3]), .dir_y(patent[2]),
        .busy(patent[1]), .done(patent[0])
    );
    lin_exact #(.WIDTH(WIDTH)) u_retimed (
        .clk(clk), .rst(rst), .start(start), .tick(tick), .x(x), .y(y),
        .step_x(retimed[5]), .step_y(retimed[4]), .dir_x(retimed[3]), .dir_y(retimed[2]),
        .busy(retimed[1]), .done(retimed[0])
    );
`ifdef FORMAL
    // Both start from a reset (their own properties assume it too); from
    // then on the outputs agree in every cycle.
    reg f_past_valid = 1'b0;
    always @(posedge clk) f_past_valid <= 1'b1;
    always @(*) if (!f_past_valid) assume (rst);
    always @(posedge clk) if (f_past_valid) assert (patent == retimed);
`endif
endmodule
`default_nettype wire
