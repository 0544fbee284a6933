// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// iCE40 form of chain_add (rtl/chain_add.v: same ports and function, proved equivalent
// by `make formal`): {cout, sum} = a + b + cin, or a + ~b + cin (SUBTRACT = 1).
//
// iCE40's carry chain is slow, so the chain is cut in two (carry select): the low 2/5
// and both versions of the high part (carry in 0 and 1) are summed at once, and the
// low part's carry picks one.  The high part's x + y + 1 is written as x - ~y, so
// Yosys keeps the two high adders apart.
module chain_add #(
    parameter integer WIDTH    = 32,    // operand width in bits (>= 1)
    parameter integer SUBTRACT = 0      // 1: a + ~b + cin (a - b with cin = 1)
) (
    input  wire [WIDTH-1:0] a,
    input  wire [WIDTH-1:0] b,
    input  wire             cin,
    output wire [WIDTH-1:0] sum,
    output wire             cout
);
    initial begin
        if (WIDTH < 1) $error("%m: WIDTH must be at least 1");
        if (SUBTRACT != 0 && SUBTRACT != 1) $error("%m: SUBTRACT must be 0 or 1");
    end

    wire [WIDTH-1:0] y = SUBTRACT != 0 ? ~b : b;
    generate
        if (WIDTH < 2) begin : g_narrow
            assign {cout, sum} = {1'b0, a} + {1'b0, y} + {{WIDTH{1'b0}}, cin};
        end else begin : g_split
            localparam integer LOW = WIDTH < 5 ? 1 : WIDTH * 2 / 5, HIGH = WIDTH - LOW;
            wire [LOW:0]  low    = {1'b0, a[LOW-1:0]} + {1'b0, y[LOW-1:0]} + {{LOW{1'b0}}, cin};
            wire [HIGH:0] high_0 = {1'b0, a[WIDTH-1:LOW]} + {1'b0, y[WIDTH-1:LOW]};
            wire [HIGH:0] high_1 = {1'b0, a[WIDTH-1:LOW]} - {1'b1, ~y[WIDTH-1:LOW]};
            assign {cout, sum} = {low[LOW] ? high_1 : high_0, low[LOW-1:0]};
        end
    endgenerate
endmodule
`default_nettype wire
