// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Adder of the linear core's step loop (rtl/lin_exact.v: adder 3's look-ahead
// copies and the steps-left counters): sum = a + b (mod 2^WIDTH).  This is the
// portable form, one carry chain, right where carry chains are fast (ECP5);
// b_high_plus1 is not read.  rtl/ice40/carry_select_add.v is the carry-select
// form with the same ports (iCE40's slow chains), picked by the synthesis file
// list; formal/carry_select_add.sby proves the two equal.
module carry_select_add #(
    parameter integer WIDTH = 34,               // operand width in bits (>= 2)
    parameter integer LOW   = 0                 // bits in the low part (1 .. WIDTH-1); 0: 2/5 of WIDTH
) (
    input  wire [WIDTH-1:0]     a,
    input  wire [WIDTH-1:0]     b,
    // b's high part (above the low part's LOW bits) + 1: read by the carry-select form only
    input  wire [WIDTH-(LOW != 0 ? LOW : WIDTH < 5 ? 1 : WIDTH * 2 / 5)-1:0] b_high_plus1,
    output wire [WIDTH-1:0]     sum
);
    initial begin
        if (WIDTH < 2) $error("%m: WIDTH must be at least 2");
        if (LOW < 0 || LOW > WIDTH - 1) $error("%m: LOW must be 0 (automatic) or 1 .. WIDTH-1");
    end

    assign sum = a + b;
    wire unused = &{1'b0, b_high_plus1};
`ifdef FORMAL
    localparam integer LO = LOW != 0 ? LOW : WIDTH < 5 ? 1 : WIDTH * 2 / 5;
    always @(*) if (b_high_plus1 == b[WIDTH-1:LO] + 1'b1) assert (sum == a + b);
`endif
endmodule
`default_nettype wire
