// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Reversible (up/down) counter with parallel load, direct and inverted outputs.
// SU1571551: counters 1 and 2.  SU1665343: counters CT7, CT8 (ones' complement;
// CT8's "subtract in bit 1" input is `dec2`).
// Priority: rst, load, then the count inputs.  Simultaneous count requests
// add up (inc + dec = no change), so no request is ever dropped.
module updown_counter #(
    parameter integer WIDTH = 8,            // counter width in bits (>= 3)
    parameter integer ONES_COMPLEMENT = 0   // 1: ones'-complement arithmetic with end-around carry
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             load,       // q <= load_value
    input  wire [WIDTH-1:0] load_value,
    input  wire             inc,        // +1
    input  wire             dec,        // -1
    input  wire             dec2,       // -2 (subtract in bit 1)
    output wire [WIDTH-1:0] q,          // direct outputs
    output wire [WIDTH-1:0] q_n         // inverted outputs
);
    initial begin
        if (WIDTH < 3) $error("%m: WIDTH must be at least 3");
        if (ONES_COMPLEMENT != 0 && ONES_COMPLEMENT != 1) $error("%m: ONES_COMPLEMENT must be 0 or 1");
    end

    reg [WIDTH-1:0] q_q;

    // Net change in {-3 .. +1}, as a WIDTH-bit two's complement addend.
    wire signed [2:0]      delta = $signed({2'b00, inc}) - $signed({2'b00, dec}) - $signed({1'b0, dec2, 1'b0});
    wire [WIDTH-1:0]       addend = {{(WIDTH-3){delta[2]}}, delta};
    // Two's complement: the count requests come late in the cycle (from the
    // sign decision), so every candidate is formed from the register alone
    // and the requests only select one (they stay off the carry chains).
    reg  [WIDTH-1:0]       twos_sum;
    always @(*) begin
        case ({inc, dec, dec2})     // constant-folds when a core ties a request low
            3'b100:         twos_sum = q_q + {{(WIDTH-1){1'b0}}, 1'b1};
            3'b010, 3'b101: twos_sum = q_q - {{(WIDTH-1){1'b0}}, 1'b1};
            3'b001, 3'b111: twos_sum = q_q - {{(WIDTH-2){1'b0}}, 2'd2};
            3'b011:         twos_sum = q_q - {{(WIDTH-2){1'b0}}, 2'd3};
            default:        twos_sum = q_q;                     // none, or +1 - 1
        endcase
    end
    // Ones' complement: counting up adds with the carry out of the top bit
    // wrapped into the LSB; counting down subtracts |delta| with the borrow
    // wrapped around, so that counting down to zero gives +0 (all outputs
    // low), as a reversible counter does, not the -0 that adding the
    // complement would give (SU1665343 Table 2: CT8 = 2 - 2 must read +0).
    wire [WIDTH-1:0]       magnitude = delta[2] ? -addend : addend;
    wire [WIDTH:0]         ones_raw = {1'b0, q_q} + {1'b0, magnitude};
    wire [WIDTH-1:0]       ones_up = ones_raw[WIDTH-1:0] + {{(WIDTH-1){1'b0}}, ones_raw[WIDTH]};
    wire [WIDTH:0]         ones_diff = {1'b0, q_q} - {1'b0, magnitude};
    wire [WIDTH-1:0]       ones_down = ones_diff[WIDTH-1:0] - {{(WIDTH-1){1'b0}}, ones_diff[WIDTH]};
    wire [WIDTH-1:0]       ones_sum = delta[2] ? ones_down : ones_up;
    wire [WIDTH-1:0]       next = ONES_COMPLEMENT != 0 ? ones_sum : twos_sum;

    always @(posedge clk) begin
        if (rst)
            q_q <= {WIDTH{1'b0}};
        else if (load)
            q_q <= load_value;
        else
            q_q <= next;
    end

    assign q   = q_q;
    assign q_n = ~q_q;
`ifdef FORMAL
    // Two's complement: q moves by inc - dec - 2 dec2 (modulo 2^WIDTH) and
    // no count request is dropped.
    reg f_past_valid = 1'b0;
    always @(posedge clk) f_past_valid <= 1'b1;
    always @(posedge clk) if (f_past_valid && ONES_COMPLEMENT == 0) begin
        if ($past(rst)) assert (q_q == {WIDTH{1'b0}});
        else if ($past(load)) assert (q_q == $past(load_value));
        else assert (q_q == $past(q_q) + {{(WIDTH-1){1'b0}}, $past(inc)} - {{(WIDTH-1){1'b0}}, $past(dec)}
                             - {{(WIDTH-2){1'b0}}, $past(dec2), 1'b0});
    end
    always @(*) assert (q_n == ~q);
`endif
endmodule
`default_nettype wire
