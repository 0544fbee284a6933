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
    output wire             overflow
);
    initial begin
        if (WIDTH < 3) $error("%m: WIDTH must be at least 3");
    end

    reg [WIDTH-1:0] value_q, coef_a_q, coef_b_q;

    // Two adders in WIDTH + 2 bits: v ± a ± b cannot wrap there.
    localparam integer XW = WIDTH + 2;
    wire [XW-1:0] v_ext = {{2{value_q[WIDTH-1]}}, value_q};
    wire [XW-1:0] a_ext = {{2{coef_a_q[WIDTH-1]}}, coef_a_q};
    wire [XW-1:0] b_ext = {{2{coef_b_q[WIDTH-1]}}, coef_b_q};
    wire [XW-1:0] a_term = step_a ? (neg_a ? -a_ext : a_ext) : {XW{1'b0}};
    wire [XW-1:0] b_term = step_b ? (neg_b ? -b_ext : b_ext) : {XW{1'b0}};
    wire [XW-1:0] sum = v_ext + a_term + b_term;

    assign next_value = sum[WIDTH-1:0];
    // Fits iff the bits above the sign bit all copy it.
    assign overflow = (sum[XW-1:WIDTH-1] != {3{sum[WIDTH-1]}});
    assign value = value_q;

    always @(posedge clk) begin
        if (rst) begin
            value_q  <= {WIDTH{1'b0}};
            coef_a_q <= {WIDTH{1'b0}};
            coef_b_q <= {WIDTH{1'b0}};
        end else if (load) begin
            value_q  <= load_value;
            coef_a_q <= coef_a_in;
            coef_b_q <= coef_b_in;
        end else if (advance) begin
            value_q  <= next_value;
        end
    end
endmodule
`default_nettype wire
