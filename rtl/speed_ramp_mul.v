// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Set-up multiplier of the speed-setting block ("БЗС" of the lecture): unsigned
// product = a * b by shift and add, the multiplier's most significant bit first
// (product = 2 product + a when the bit is 1), one bit per cycle, so that the
// profile generator re-expresses its state for the next segment (p' n, f (f + 1),
// feed * override) without a combinational multiplier.
//
// Timing: `start` in a cycle with busy low captures a and b (cycle 0); busy is
// high in cycles 1 .. BW; `done` is a one-cycle strobe in cycle BW + 1, when
// `product` is valid; product holds until the next start.  `start` while busy
// is ignored; `rst` returns to idle and clears the product.
module speed_ramp_mul #(
    parameter integer AW = 8,   // width of the multiplicand a (>= 1)
    parameter integer BW = 8    // width of the multiplier b = busy cycles (1 .. 255)
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             start,    // capture a, b (ignored while busy)
    input  wire [AW-1:0]    a,        // unsigned operands
    input  wire [BW-1:0]    b,
    output reg              busy,     // high while the bits of b are taken
    output reg              done,     // one-cycle strobe: product valid from this cycle on
    output reg  [AW+BW-1:0] product   // a * b
);
    initial begin
        if (AW < 1) $error("%m: AW must be at least 1");
        if (BW < 1 || BW > 255) $error("%m: BW must be 1 .. 255");
    end

    localparam [31:0] BW32 = BW;
    localparam [7:0]  BW8 = BW32[7:0];
    reg [AW-1:0] a_q;
    reg [BW-1:0] b_q;
    reg [7:0]    count;

    always @(posedge clk) begin
        if (rst) begin
            busy    <= 1'b0;
            done    <= 1'b0;
            count   <= 8'd0;
            a_q     <= {AW{1'b0}};
            b_q     <= {BW{1'b0}};
            product <= {(AW+BW){1'b0}};
        end else if (!busy) begin
            done <= 1'b0;
            if (start) begin
                a_q     <= a;
                b_q     <= b;
                product <= {(AW+BW){1'b0}};
                count   <= BW8;
                busy    <= 1'b1;
            end
        end else begin
            product <= {product[AW+BW-2:0], 1'b0} + (b_q[BW-1] ? {{BW{1'b0}}, a_q} : {(AW+BW){1'b0}});
            b_q     <= b_q << 1;
            count   <= count - 8'd1;
            if (count == 8'd1) begin
                busy <= 1'b0;
                done <= 1'b1;
            end
        end
    end
`ifdef FORMAL
    // the count runs BW .. 1 while busy (formal/speed_ramp.sby, k-induction)
    always @(*) if (!rst) begin
        assert (count <= BW8);
        assert (busy == (count != 8'd0));
    end
`endif
endmodule
`default_nettype wire
