// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Two-input multiplexer: out = sel ? in1 : in0.
// SU1571551: multiplexer 12 of node 19 (counter 1 direct / counter 2 inverted).
module mux2 #(
    parameter integer WIDTH = 8     // data width in bits (>= 1)
) (
    input  wire             sel,
    input  wire [WIDTH-1:0] in0,
    input  wire [WIDTH-1:0] in1,
    output wire [WIDTH-1:0] out
);
    initial if (WIDTH < 1) $error("%m: WIDTH must be at least 1");
    assign out = sel ? in1 : in0;
`ifdef FORMAL
    always @(*) assert (out == (sel ? in1 : in0));
`endif
endmodule
`default_nettype wire
