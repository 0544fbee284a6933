// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// iCE40 form of mux_add (rtl/mux_add.v: same ports and function, proved equivalent by
// `make formal`): sum = x + (sel ? c : d), x = a (LOAD = 0) or sel ? 0 : a (LOAD = 1).
//
// iCE40's carry chain is slow, so each candidate sum has a carry-select adder of its
// own (the low 2/5 and both versions of the high part summed at once, the low part's
// carry picking one), and the select comes after the chains:
//   LOAD = 0:  sel ? a + c : a + d;     LOAD = 1:  sel ? c : a + d.
// So the select's source (a decision bit) drives only the output multiplexers, not
// the chains.
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

    // a + b with the chain cut after the low LOW bits; a + b + 1 of the high part is
    // written as a - ~b, so Yosys keeps the two high adders apart.
    localparam integer LOW = WIDTH < 5 ? 1 : WIDTH * 2 / 5;
    wire [WIDTH-1:0] sum_c, sum_d;
    generate
        if (WIDTH < 2) begin : g_narrow
            assign sum_c = a + c;
            assign sum_d = a + d;
        end else begin : g_split
            wire [LOW:0] low_c = {1'b0, a[LOW-1:0]} + {1'b0, c[LOW-1:0]};
            wire [LOW:0] low_d = {1'b0, a[LOW-1:0]} + {1'b0, d[LOW-1:0]};
            assign sum_c = {low_c[LOW] ? a[WIDTH-1:LOW] - ~c[WIDTH-1:LOW] : a[WIDTH-1:LOW] + c[WIDTH-1:LOW],
                            low_c[LOW-1:0]};
            assign sum_d = {low_d[LOW] ? a[WIDTH-1:LOW] - ~d[WIDTH-1:LOW] : a[WIDTH-1:LOW] + d[WIDTH-1:LOW],
                            low_d[LOW-1:0]};
        end
        if (LOAD != 0) begin : g_load
            assign sum = sel ? c : sum_d;
            wire unused = &{1'b0, sum_c};
        end else begin : g_select
            assign sum = sel ? sum_c : sum_d;
        end
    endgenerate
endmodule
`default_nettype wire
