// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Operand multiplexer of the linear core's step loop (rtl/lin_exact.v): mux 12
// of SU 1571551's node 19, out = sel ? in1 : in0, in front of an operand
// register.  This is the portable form (the ECP5 build): the mux2 inside keeps
// its hierarchy, so that ABC does not merge the callers' idle select (folded
// into in0 and in1) into the sign decision on `sel`; merged, that decision
// takes three LUTs before the register, on ECP5's critical path.
// rtl/ice40/operand_mux.v is the iCE40 form with the same ports: a plain mux
// that synthesis merges (where the adders are cut in two the merged form is as
// fast and smaller); the synthesis file list picks the family's form, and
// formal/operand_mux.sby proves the two equal.
module operand_mux #(
    parameter integer WIDTH = 34    // data width in bits (>= 1)
) (
    input  wire             sel,
    input  wire [WIDTH-1:0] in0,
    input  wire [WIDTH-1:0] in1,
    output wire [WIDTH-1:0] out
);
    initial if (WIDTH < 1) $error("%m: WIDTH must be at least 1");
    (* keep_hierarchy *) mux2 #(.WIDTH(WIDTH)) u_mux12 (
        .sel(sel), .in0(in0), .in1(in1), .out(out));
`ifdef FORMAL
    always @(*) assert (out == (sel ? in1 : in0));
`endif
endmodule
`default_nettype wire
