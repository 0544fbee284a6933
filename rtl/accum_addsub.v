// SPDX-License-Identifier: Apache-2.0
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
`ifdef FORMAL
    // F follows clear/load/add; in ones' complement the sum is right modulo
    // 2^WIDTH - 1 (end-around carry), in two's modulo 2^WIDTH.
    reg f_past_valid = 1'b0;
    always @(posedge clk) f_past_valid <= 1'b1;
    localparam [WIDTH:0] F_MOD = ONES_COMPLEMENT != 0 ? (1 << WIDTH) - 1 : (1 << WIDTH);
    always @(posedge clk) if (f_past_valid) begin
        if ($past(rst) || $past(clear)) assert (f_q == {WIDTH{1'b0}});
        else if ($past(load)) assert (f_q == $past(load_value));
        // Ones' complement with cin = 1 is left out: -0 + -0 + 1 gives +0, not 1
        // (the second end-around carry is lost); reported, not yet decided.
        else if ($past(add) && (ONES_COMPLEMENT == 0 || !$past(cin)))
            assert ({2'b0, f_q} % {1'b0, F_MOD} == ({2'b0, $past(f_q)} + {2'b0, $past(operand)}
                    + {{(WIDTH+1){1'b0}}, $past(cin)}) % {1'b0, F_MOD});
        else if (!$past(add)) assert (f_q == $past(f_q));
    end
`endif
endmodule
`default_nettype wire
