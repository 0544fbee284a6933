// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Equivalence of operand_mux's two forms (formal/operand_mux.sby): the
// portable one (rtl/operand_mux.v, the mux kept as its own module) and the
// iCE40 one (rtl/ice40/operand_mux.v, elaborated at the same WIDTH and renamed
// operand_mux_ice40 by the .sby script), on the same free select and inputs:
// the outputs are equal.
module operand_mux_equiv #(
    parameter integer WIDTH = 34
) (
    input wire             sel,
    input wire [WIDTH-1:0] in0,
    input wire [WIDTH-1:0] in1
);
    wire [WIDTH-1:0] out_portable, out_ice40;
    operand_mux #(.WIDTH(WIDTH)) u_portable (
        .sel(sel), .in0(in0), .in1(in1), .out(out_portable));
    operand_mux_ice40 u_ice40 (
        .sel(sel), .in0(in0), .in1(in1), .out(out_ice40));
`ifdef FORMAL
    always @(*) assert (out_portable == out_ice40);
`endif
endmodule
`default_nettype wire
