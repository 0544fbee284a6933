// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Adder with an operand select (the arc core's loop adders and its point counters):
//   sum = x + (sel ? c : d),  x = a (LOAD = 0) or sel ? 0 : a (LOAD = 1).
// LOAD = 0 lets a decision bit pick one of two increments (the midpoint loop); LOAD = 1
// is a loadable counter (sel: sum = c, otherwise a + d).
//
// This is the portable form, used by every simulation and by families without a form
// of their own.  Family forms (same name, ports and function, proved equivalent by
// `make formal`) are picked by the synthesis file list:
//   rtl/ecp5/mux_add.v   the select inside the carry cells' own LUTs;
//   rtl/ice40/mux_add.v  both sums in carry-select adders, the select after them.
module mux_add #(
    parameter integer WIDTH = 34,       // operand width in bits (>= 1)
    parameter integer LOAD  = 0         // 1: sel also clears x (sum = c)
) (
    input  wire [WIDTH-1:0] a,
    input  wire             sel,
    input  wire [WIDTH-1:0] c,
    input  wire [WIDTH-1:0] d,
    output wire [WIDTH-1:0] sum
);
    initial begin
        if (WIDTH < 1) $error("%m: WIDTH must be at least 1");
        if (LOAD != 0 && LOAD != 1) $error("%m: LOAD must be 0 or 1");
    end

    wire [WIDTH-1:0] x = (LOAD != 0 && sel) ? {WIDTH{1'b0}} : a;
    assign sum = x + (sel ? c : d);
endmodule
`default_nettype wire
