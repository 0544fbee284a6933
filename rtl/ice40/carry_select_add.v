// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Adder of the linear core's step loop, iCE40 form: sum = a + b (mod 2^WIDTH)
// with the carry chain cut in two (carry select), for iCE40's slow carry
// chains.  Same module name and ports as rtl/carry_select_add.v (one chain);
// the synthesis file list picks this one for iCE40, and
// formal/carry_select_add.sby proves the two equal.  The low part and both
// versions of the high part (carry in 0 and 1) are added at the same time;
// the low part's carry picks one.  The caller supplies b's high part plus one
// (a register loaded with b), so the two high adders are separate and Yosys
// does not merge them into one chain with a late carry-in.  The low part is
// the shorter one by default: its carry still has to fan out to every
// high-part mux.
module carry_select_add #(
    parameter integer WIDTH = 34,               // operand width in bits (>= 2)
    parameter integer LOW   = 0                 // bits in the low part (1 .. WIDTH-1); 0: 2/5 of WIDTH
) (
    input  wire [WIDTH-1:0]     a,
    input  wire [WIDTH-1:0]     b,
    // b's high part (above the low part's LOW bits) + 1
    input  wire [WIDTH-(LOW != 0 ? LOW : WIDTH < 5 ? 1 : WIDTH * 2 / 5)-1:0] b_high_plus1,
    output wire [WIDTH-1:0]     sum
);
    initial begin
        if (WIDTH < 2) $error("%m: WIDTH must be at least 2");
        if (LOW < 0 || LOW > WIDTH - 1) $error("%m: LOW must be 0 (automatic) or 1 .. WIDTH-1");
    end

    localparam integer LO = LOW != 0 ? LOW : WIDTH < 5 ? 1 : WIDTH * 2 / 5;
    localparam integer HI = WIDTH - LO;

    wire [LO:0]   low    = {1'b0, a[LO-1:0]} + {1'b0, b[LO-1:0]};
    wire [HI-1:0] high_0 = a[WIDTH-1:LO] + b[WIDTH-1:LO];
    wire [HI-1:0] high_1 = a[WIDTH-1:LO] + b_high_plus1;
    assign sum = {low[LO] ? high_1 : high_0, low[LO-1:0]};
`ifdef FORMAL
    always @(*) if (b_high_plus1 == b[WIDTH-1:LO] + 1'b1) assert (sum == a + b);
`endif
endmodule
`default_nettype wire
