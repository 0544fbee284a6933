// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ECP5 form of mux_add (rtl/mux_add.v: same ports and function, proved equivalent by
// `make formal`): sum = x + (sel ? c : d), x = a (LOAD = 0) or sel ? 0 : a (LOAD = 1).
//
// The chain is built from ECP5 carry cells (CCU2C) by hand: each bit's LUT4 computes
// x ^ y from a, sel, c, d, so the select costs no LUT and no route in front of the
// chain (Yosys maps a + (sel ? c : d) to a LUT and then a CCU2C in another slice).  The
// cell's carry generate is that LUT with c = d = 0, which is x: right whenever
// x ^ y = 0, because y = 0 for c = d = 0.
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

    // LUT4 inputs A = a, B = sel, C = c, D = d; INIT bit {D, C, B, A} = x ^ y.
    localparam [15:0] INIT = LOAD != 0 ? 16'hd1e2 : 16'h596a;
    localparam integer PAIRS = (WIDTH + 1) / 2;
    localparam integer PAD = 2 * PAIRS - WIDTH;
    wire [2*PAIRS-1:0] pa = {{PAD{1'b0}}, a}, ps = {2*PAIRS{sel}},
                       pc = {{PAD{1'b0}}, c}, pd = {{PAD{1'b0}}, d};
    wire [2*PAIRS-1:0] s;
    wire [PAIRS:0]     carry;
    assign carry[0] = 1'b0;
    genvar i;
    generate
        for (i = 0; i < PAIRS; i = i + 1) begin : g_pair
            CCU2C #(.INIT0(INIT), .INIT1(INIT), .INJECT1_0("NO"), .INJECT1_1("NO")) u_cell (
                .CIN(carry[i]),
                .A0(pa[2*i]), .B0(ps[2*i]), .C0(pc[2*i]), .D0(pd[2*i]),
                .A1(pa[2*i+1]), .B1(ps[2*i+1]), .C1(pc[2*i+1]), .D1(pd[2*i+1]),
                .S0(s[2*i]), .S1(s[2*i+1]), .COUT(carry[i+1]));
        end
    endgenerate
    assign sum = s[WIDTH-1:0];
    wire unused = &{1'b0, s, carry[PAIRS]};
endmodule
`default_nettype wire
