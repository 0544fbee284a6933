// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Orders a move's projections: |X|, |Y| into the long one L and the short one
// S, and L - S.  SU1571551's inputs 22-26 with trigger 15's input (X is the
// long axis when |X| >= |Y|); the lecture's accelerated line uses the same.
// Combinational; every WIDTH-bit value is legal (|-2^(WIDTH-1)| = 2^(WIDTH-1)
// fits the WIDTH+1-bit outputs).  Kept as its own module in synthesis, so
// the optimiser does not merge this input logic into the cores' register
// feedback paths.
module axis_order #(
    parameter integer WIDTH = 32    // width of the signed X, Y inputs (>= 2)
) (
    input  wire [WIDTH-1:0] x,              // signed X increment
    input  wire [WIDTH-1:0] y,              // signed Y increment
    output wire             x_is_long,      // |X| >= |Y|
    output wire [WIDTH:0]   long_len,       // L
    output wire [WIDTH:0]   short_len,      // S
    output wire [WIDTH:0]   difference      // L - S
);
    initial if (WIDTH < 2) $error("%m: WIDTH must be at least 2");

    wire [WIDTH-1:0] abs_x = x[WIDTH-1] ? -x : x;
    wire [WIDTH-1:0] abs_y = y[WIDTH-1] ? -y : y;
    assign x_is_long  = abs_x >= abs_y;
    assign long_len   = {1'b0, x_is_long ? abs_x : abs_y};
    assign short_len  = {1'b0, x_is_long ? abs_y : abs_x};
    assign difference = long_len - short_len;
`ifdef FORMAL
    always @(*) assert (long_len >= short_len && difference == long_len - short_len
                        && long_len <= {2'b01, {(WIDTH-1){1'b0}}});
`endif
endmodule
`default_nettype wire
