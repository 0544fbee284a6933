`default_nettype none
// Half-step test of an end point against a circle: on_band = |sqrt(b) - sqrt(a)| <= 1/2,
// a = squared radius of the circle (start point), b = squared radius of the end point.
// Exact integer form, no square root:  with d = |b - a|, s = min(a, b),
//   sqrt(max) <= sqrt(s) + 1/2  <=>  d == 0  or  (4d - 1)^2 <= 16 s.
// The command check of the circular cores (lecture seed 004, "start or end point not
// on the circle") as one combinational block.  circ_quadrant and circ_arc evaluate
// the same test without a combinational multiplier, with m = |d|:
// d == 0 or m^2 <= s + (m - 1) div 2 (seq_mult).  Combinational.
module circle_band #(
    parameter integer AW = 16   // width of the unsigned squared radii a, b (>= 4)
) (
    input  wire [AW-1:0] a,
    input  wire [AW-1:0] b,
    output wire          on_band
);
    initial begin
        if (AW < 4) $error("%m: AW must be at least 4");
    end

    // If d >= 2^HW then (4d - 1)^2 > 16 * 2^AW > 16 s: outside, no product needed.
    localparam integer HW = (AW + 1) / 2 + 1;
    localparam integer PW = 2 * HW + 4;          // (4d - 1)^2 and 16 s both fit

    wire [AW-1:0] d = a >= b ? a - b : b - a;
    wire [AW-1:0] s = a >= b ? b : a;
    wire          d_small = d[AW-1:HW] == {(AW-HW){1'b0}};
    wire [HW+1:0] lhs = {d[HW-1:0], 2'b00} - {{(HW+1){1'b0}}, 1'b1};   // 4d - 1
    wire [PW-1:0] lhs_sq = {{(PW-HW-2){1'b0}}, lhs} * {{(PW-HW-2){1'b0}}, lhs};
    wire [PW-1:0] s16 = {{(PW-AW-4){1'b0}}, s, 4'b0000};
    assign on_band = d == {AW{1'b0}} || (d_small && lhs_sq <= s16);
endmodule
`default_nettype wire
