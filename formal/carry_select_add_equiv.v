// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Equivalence of carry_select_add's two forms (formal/carry_select_add.sby):
// the portable one (rtl/carry_select_add.v, one carry chain) and the iCE40 one
// (rtl/ice40/carry_select_add.v, elaborated at the same WIDTH and LOW and
// renamed carry_select_add_ice40 by the .sby script),
// on the same free operands with b_high_plus1 as every caller drives it
// (b's high part plus one): the sums are equal.
module carry_select_add_equiv #(
    parameter integer WIDTH = 34,
    parameter integer LOW   = 0
) (
    input wire [WIDTH-1:0] a,
    input wire [WIDTH-1:0] b
);
    localparam integer LO = LOW != 0 ? LOW : WIDTH < 5 ? 1 : WIDTH * 2 / 5;
    wire [WIDTH-LO-1:0] b_high_plus1 = b[WIDTH-1:LO] + 1'b1;
    wire [WIDTH-1:0]    sum_chain, sum_select;
    carry_select_add #(.WIDTH(WIDTH), .LOW(LOW)) u_portable (
        .a(a), .b(b), .b_high_plus1(b_high_plus1), .sum(sum_chain));
    carry_select_add_ice40 u_ice40 (
        .a(a), .b(b), .b_high_plus1(b_high_plus1), .sum(sum_select));
`ifdef FORMAL
    always @(*) assert (sum_chain == sum_select);
`endif
endmodule
`default_nettype wire
