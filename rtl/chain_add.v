// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Adder with carry in and carry out, one carry chain:
//   {cout, sum} = a + b + cin (SUBTRACT = 0),  a + ~b + cin = a - b - !cin (SUBTRACT = 1).
// The arc core's wide sums off its loop (the set-up's two-cycle chunk sums with a
// registered carry, the stepper's load values).  A difference is written as a
// subtraction, so that carry cells that can subtract invert b inside the chain; the
// carry in enters as the low bit of a chain one bit longer, so the chain stays one.
//
// This is the portable form, used by every simulation and by ECP5 (whose carry chain
// is fast).  rtl/ice40/chain_add.v (same name, ports and function, proved equivalent
// by `make formal`) cuts the chain in two for iCE40's slow carry chain.
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

    wire [WIDTH+1:0] total;
    generate
        if (SUBTRACT != 0) begin : g_subtract
            // 2 (a - b) + cin - 1: its top bit is the borrow, the carry's complement.
            assign total = {1'b0, a, cin} - {1'b0, b, 1'b1};
            assign cout = !total[WIDTH+1];
        end else begin : g_add
            assign total = {1'b0, a, 1'b1} + {1'b0, b, cin};
            assign cout = total[WIDTH+1];
        end
    endgenerate
    assign sum = total[WIDTH:1];
    wire unused = &{1'b0, total[0]};
endmodule
`default_nettype wire
