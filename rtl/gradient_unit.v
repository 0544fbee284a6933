// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Gradient unit: keeps one affine function v = c + a·x + b·y up to date with
// adders only while the node (x, y) moves by unit steps (no multiplier, no
// divider).  Bulatnikov & Bulatnikova (2011), point 4: the tangent projection
// ΔX = φ(x, y) or ΔY = ψ(x, y) at the new node.
//
// `load` takes the value at the start node and the two coefficients.
// `next_value` is combinational: v after the step (step_a, neg_a) on x and
// (step_b, neg_b) on y, so the core can use the new projection in the same
// cycle; `advance` stores it.  `overflow` says next_value does not fit WIDTH.
// `magnitude` is |value| and `next_magnitude` |next_value| (unsigned WIDTH
// bits; |-2^(WIDTH-1)| fits).  For speed -v, -a and -b are kept in registers
// too: v ± a ± b and -v ∓ a ∓ b are formed side by side straight from
// registers, and the magnitude is a select by the sign, not a negation.
module gradient_unit #(
    parameter integer WIDTH = 24    // signed width of the value and the coefficients (>= 3)
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             load,       // value <= load_value, coefficients <= coef_*_in
    input  wire [WIDTH-1:0] load_value,
    input  wire [WIDTH-1:0] coef_a_in,  // change of v per +1 step on x
    input  wire [WIDTH-1:0] coef_b_in,  // change of v per +1 step on y
    input  wire             step_a,     // the step moves x ...
    input  wire             neg_a,      // ... by -1 (else +1)
    input  wire             step_b,     // the step moves y ...
    input  wire             neg_b,      // ... by -1 (else +1)
    input  wire             advance,    // value <= next_value
    output wire [WIDTH-1:0] value,
    output wire [WIDTH-1:0] next_value,
    output wire             overflow,
    output wire [WIDTH-1:0] magnitude,      // |value|
    output wire [WIDTH-1:0] next_magnitude  // |next_value| (when it fits)
);
    initial begin
        if (WIDTH < 3) $error("%m: WIDTH must be at least 3");
    end

    // Two adders in WIDTH + 2 bits: v ± a ± b cannot wrap there.
    localparam integer XW = WIDTH + 2;
    reg  [XW-1:0] v_q, nv_q;            // v and -v
    reg  [XW-1:0] a_q, na_q, b_q, nb_q; // a, -a, b, -b
    wire [XW-1:0] load_ext = {{2{load_value[WIDTH-1]}}, load_value};
    wire [XW-1:0] a_in_ext = {{2{coef_a_in[WIDTH-1]}}, coef_a_in};
    wire [XW-1:0] b_in_ext = {{2{coef_b_in[WIDTH-1]}}, coef_b_in};
    wire [XW-1:0] a_term  = step_a ? (neg_a ? na_q : a_q) : {XW{1'b0}};
    wire [XW-1:0] b_term  = step_b ? (neg_b ? nb_q : b_q) : {XW{1'b0}};
    wire [XW-1:0] na_term = step_a ? (neg_a ? a_q : na_q) : {XW{1'b0}};
    wire [XW-1:0] nb_term = step_b ? (neg_b ? b_q : nb_q) : {XW{1'b0}};
    wire [XW-1:0] sum  = v_q + a_term + b_term;
    wire [XW-1:0] nsum = nv_q + na_term + nb_term;      // -sum
    wire [XW-1:0] sum_wrapped = {{2{sum[WIDTH-1]}}, sum[WIDTH-1:0]};   // what `advance` stores

    assign next_value = sum[WIDTH-1:0];
    // Fits iff the bits above the sign bit all copy it.
    assign overflow = (sum[XW-1:WIDTH-1] != {3{sum[WIDTH-1]}});
    assign value = v_q[WIDTH-1:0];
    assign magnitude = v_q[WIDTH-1] ? nv_q[WIDTH-1:0] : v_q[WIDTH-1:0];
    assign next_magnitude = sum[WIDTH-1] ? nsum[WIDTH-1:0] : sum[WIDTH-1:0];

    always @(posedge clk) begin
        if (rst) begin
            v_q  <= {XW{1'b0}};
            nv_q <= {XW{1'b0}};
            a_q  <= {XW{1'b0}};
            na_q <= {XW{1'b0}};
            b_q  <= {XW{1'b0}};
            nb_q <= {XW{1'b0}};
        end else if (load) begin
            v_q  <= load_ext;
            nv_q <= -load_ext;
            a_q  <= a_in_ext;
            na_q <= -a_in_ext;
            b_q  <= b_in_ext;
            nb_q <= -b_in_ext;
        end else if (advance) begin
            v_q  <= sum_wrapped;
            nv_q <= overflow ? -sum_wrapped : nsum;     // = -sum_wrapped
        end
    end
endmodule
`default_nettype wire
