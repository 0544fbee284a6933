// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Operand multiplexer of the linear core's step loop, iCE40 form: mux 12 of
// SU 1571551's node 19, out = sel ? in1 : in0.  Same module name and ports as
// rtl/operand_mux.v, whose mux keeps its hierarchy for ECP5's sake; this one
// does not, so ABC merges it with the callers' idle select (about 100 LUTs
// fewer in lin_exact on iCE40 at the same Fmax, the adders being cut in two).
// The synthesis file list picks this one for iCE40; formal/operand_mux.sby
// proves the two forms equal.
module operand_mux #(
    parameter integer WIDTH = 34    // data width in bits (>= 1)
) (
    input  wire             sel,
    input  wire [WIDTH-1:0] in0,
    input  wire [WIDTH-1:0] in1,
    output wire [WIDTH-1:0] out
);
    initial if (WIDTH < 1) $error("%m: WIDTH must be at least 1");
    mux2 #(.WIDTH(WIDTH)) u_mux12 (
        .sel(sel), .in0(in0), .in1(in1), .out(out));
`ifdef FORMAL
    always @(*) assert (out == (sel ? in1 : in0));
`endif
endmodule
`default_nettype wire
