`default_nettype none
// Accumulating adder-subtractor: F <= F + operand + cin on `add`.
// SU1571551: adder 3 of node 19 (the operand comes from mux 12; subtraction is
// adding a counter's inverted outputs).  SU1665343: adder 1 (ones' complement,
// end-around carry).  Lecture: the evaluation-function adder (carry-in adds 1).
module accum_addsub #(
    parameter integer WIDTH = 16,           // accumulator width in bits (>= 2)
    parameter integer ONES_COMPLEMENT = 0   // 1: ones' complement, carry out wraps into the LSB
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             clear,      // F <= 0 (end of move)
    input  wire             load,       // F <= load_value (initial evaluation function)
    input  wire [WIDTH-1:0] load_value,
    input  wire             add,        // F <= F + operand + cin
    input  wire [WIDTH-1:0] operand,
    input  wire             cin,
    output wire [WIDTH-1:0] f,          // accumulator contents
    output wire             negative,   // sign bit, direct output
    output wire             non_negative // sign bit, inverted output
);
    initial begin
        if (WIDTH < 2) $error("%m: WIDTH must be at least 2");
        if (ONES_COMPLEMENT != 0 && ONES_COMPLEMENT != 1) $error("%m: ONES_COMPLEMENT must be 0 or 1");
    end

    reg  [WIDTH-1:0] f_q;
    wire [WIDTH:0]   raw = {1'b0, f_q} + {1'b0, operand} + {{WIDTH{1'b0}}, cin};
    // End-around carry: in ones' complement the carry out is added back in.
    wire [WIDTH-1:0] sum = raw[WIDTH-1:0] + {{(WIDTH-1){1'b0}}, ONES_COMPLEMENT != 0 && raw[WIDTH]};

    always @(posedge clk) begin
        if (rst || clear)
            f_q <= {WIDTH{1'b0}};
        else if (load)
            f_q <= load_value;
        else if (add)
            f_q <= sum;
    end

    assign f            = f_q;
    assign negative     = f_q[WIDTH-1];
    assign non_negative = ~f_q[WIDTH-1];
endmodule
`default_nettype wire
