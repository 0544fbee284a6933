// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// The lecture's step costs of the speed-setting block ("БЗС"): the interval
// after a step on 1, 2 or 3 axes is 1, sqrt(2) or sqrt(3) times the axial one.
// cost = 2^FRAC, round(sqrt(2) 2^FRAC) or round(sqrt(3) 2^FRAC): exact integer
// square roots, rounded to nearest, of 2 * 2^(2 FRAC) and 3 * 2^(2 FRAC),
// formed at elaboration by the constant function `root` on 2 FRAC + 4 bit words
// (digit by digit, shifts and subtractions only), so any FRAC up to 64 is
// exact.  Only constants and a 4-way multiplexer remain in the hardware.
module step_cost #(
    parameter integer FRAC   = 16,  // fraction bits: an axial step costs 2^FRAC (1 .. 64)
    parameter integer COST_W = 18   // width of cost (>= FRAC + 1)
) (
    input  wire [1:0]        axes,  // number of axes of the step (0 counts as 1)
    output reg  [COST_W-1:0] cost   // its path length in units of 2^-FRAC axial steps
);
    initial begin
        if (FRAC < 1 || FRAC > 64) $error("%m: FRAC must be 1 .. 64");
        if (COST_W < FRAC + 1) $error("%m: COST_W must be at least FRAC + 1");
    end

    // radicand words: 3 * 2^(2 FRAC) < 2^(2 FRAC + 2), and at least COST_W bits
    localparam integer RW = 2 * FRAC + 4 > COST_W ? 2 * FRAC + 4 : COST_W + COST_W % 2;

    // round(sqrt(n)): the integer square root digit by digit (two radicand bits a
    // digit), then up by one if n - r^2 > r (n is an integer, so never a tie).
    function [RW-1:0] root(input [RW-1:0] n);
        reg [RW-1:0] rest, r, trial;
        integer i;
        begin
            rest = n;
            r    = {RW{1'b0}};
            for (i = RW / 2 - 1; i >= 0; i = i - 1) begin
                trial = (r << (i + 1)) | ({{(RW-1){1'b0}}, 1'b1} << (2 * i));  // (2r + 2^i) 2^i
                if (rest >= trial) begin
                    rest = rest - trial;
                    r    = r | ({{(RW-1){1'b0}}, 1'b1} << i);
                end
            end
            root = rest > r ? r + 1'b1 : r;
        end
    endfunction

    localparam [RW-1:0] ONE_SQUARED = {{(RW-1){1'b0}}, 1'b1} << (2 * FRAC);
    localparam [RW-1:0] COST1 = {{(RW-1){1'b0}}, 1'b1} << FRAC;
    localparam [RW-1:0] COST2 = root(ONE_SQUARED << 1);                  // round(sqrt(2) * 2^FRAC)
    localparam [RW-1:0] COST3 = root((ONE_SQUARED << 1) + ONE_SQUARED);  // round(sqrt(3) * 2^FRAC)

    always @* begin
        case (axes)
            2'd2:    cost = COST2[COST_W-1:0];
            2'd3:    cost = COST3[COST_W-1:0];
            default: cost = COST1[COST_W-1:0];
        endcase
    end
endmodule
`default_nettype wire
