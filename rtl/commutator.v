// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Three-channel commutator of 2x3 AND/OR elements.  SU1665343: commutator 6
// (elements 37, fig. 3).  Channel k presents {v_k, lsb_k}: a counter's direct
// or inverted outputs shifted one bit left, the LSB from a trigger output, so
// that in ones' complement the adder receives 2v + 1 or 2v - 1 without any
// arithmetic.  Selects are one-hot (or all low: output 0).
module commutator #(
    parameter integer WIDTH = 8     // counter width in bits (>= 1); the output has WIDTH + 1
) (
    input  wire             sel1,   // A1
    input  wire             sel2,   // A2
    input  wire             sel3,   // A3
    input  wire [WIDTH-1:0] v1,     // B1 (shifted left)
    input  wire             lsb1,
    input  wire [WIDTH-1:0] v2,     // B2
    input  wire             lsb2,
    input  wire [WIDTH-1:0] v3,     // B3
    input  wire             lsb3,
    output wire [WIDTH:0]   out
);
    initial if (WIDTH < 1) $error("%m: WIDTH must be at least 1");

    wire [WIDTH:0] b1 = {v1, lsb1};
    wire [WIDTH:0] b2 = {v2, lsb2};
    wire [WIDTH:0] b3 = {v3, lsb3};
    genvar i;
    generate
        for (i = 0; i <= WIDTH; i = i + 1) begin : g_element37
            assign out[i] = (sel1 & b1[i]) | (sel2 & b2[i]) | (sel3 & b3[i]);
        end
    endgenerate
endmodule
`default_nettype wire
