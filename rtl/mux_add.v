`default_nettype none
// Adder with its operand select inside the carry chain's own LUTs (ECP5's CCU2C).
//   sum = x + y,  y = sel ? c : d,  x = a (LOAD = 0) or sel ? 0 : a (LOAD = 1),
// per bit (sel is a vector, so bits can take different selects).  LOAD = 1 is a
// loadable counter (sel: sum = c); LOAD = 0 lets a decision bit pick one of two
// increments (the arc core's midpoint loop).
//
// ECP5 = 1 builds the chain from ECP5 carry cells (CCU2C) by hand: each bit's LUT4
// computes x ^ y from a, sel, c, d, so the select costs no LUT and no route in front
// of the chain (Yosys maps a + (sel ? c : d) to a LUT and then a CCU2C in another
// slice).  The cell's carry generate is that LUT with c = d = 0, which is x: right
// whenever x ^ y = 0, because y = 0 for c = d = 0.  ECP5 = 0 is the same sum in plain
// Verilog, for simulation and other families.
module mux_add #(
    parameter integer WIDTH = 34,       // operand width in bits (>= 1)
    parameter integer LOAD  = 0,        // 1: sel also clears x (sum = c)
    parameter integer ECP5  = 0         // 1: ECP5 CCU2C cells; 0: behavioural
) (
    input  wire [WIDTH-1:0] a,
    input  wire [WIDTH-1:0] sel,
    input  wire [WIDTH-1:0] c,
    input  wire [WIDTH-1:0] d,
    output wire [WIDTH-1:0] sum
);
    initial begin
        if (WIDTH < 1) $error("%m: WIDTH must be at least 1");
        if (LOAD != 0 && LOAD != 1) $error("%m: LOAD must be 0 or 1");
        if (ECP5 != 0 && ECP5 != 1) $error("%m: ECP5 must be 0 or 1");
    end

    wire [WIDTH-1:0] x = LOAD != 0 ? a & ~sel : a;
    wire [WIDTH-1:0] y = (sel & c) | (~sel & d);

    generate
        if (ECP5 == 0) begin : g_plain
            assign sum = x + y;
        end else begin : g_ccu2c
            // LUT4 inputs A = a, B = sel, C = c, D = d; INIT bit {D, C, B, A} = x ^ y.
            localparam [15:0] INIT = LOAD != 0 ? 16'hd1e2 : 16'h596a;
            localparam integer PAIRS = (WIDTH + 1) / 2;
            wire [2*PAIRS-1:0] pa = {{(2*PAIRS-WIDTH){1'b0}}, a}, ps = {{(2*PAIRS-WIDTH){1'b0}}, sel},
                               pc = {{(2*PAIRS-WIDTH){1'b0}}, c}, pd = {{(2*PAIRS-WIDTH){1'b0}}, d};
            wire [2*PAIRS-1:0] s;
            wire [PAIRS:0]     carry;
            assign carry[0] = 1'b0;
            genvar i;
            for (i = 0; i < PAIRS; i = i + 1) begin : g_pair
                CCU2C #(.INIT0(INIT), .INIT1(INIT), .INJECT1_0("NO"), .INJECT1_1("NO")) u_cell (
                    .CIN(carry[i]),
                    .A0(pa[2*i]), .B0(ps[2*i]), .C0(pc[2*i]), .D0(pd[2*i]),
                    .A1(pa[2*i+1]), .B1(ps[2*i+1]), .C1(pc[2*i+1]), .D1(pd[2*i+1]),
                    .S0(s[2*i]), .S1(s[2*i+1]), .COUT(carry[i+1]));
            end
            assign sum = s[WIDTH-1:0];
            wire unused = &{1'b0, x, y, s, carry[PAIRS]};
        end
    endgenerate
endmodule
`default_nettype wire
