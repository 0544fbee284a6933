// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Sequential signed multiplier (shift-add, radix 2): product = a * b, for set-up
// products that must not cost a combinational multiplier.
// The multiplicand, sign-extended, shifts left one place per cycle and is added
// to the accumulator when the multiplier's next bit (LSB first) is 1; the last
// (sign) bit subtracts it: -(A * 2^(WIDTH-1)) = ~A * 2^(WIDTH-1) + 2^(WIDTH-1), the
// inverted operand with zeros below bit WIDTH-1 and a + 1 at bit WIDTH-1.
// The 2*WIDTH-bit accumulator is four chunks, each with its own short carry chain;
// a chunk's carry out is registered and enters the next chunk one cycle later
// (carry-save at the chunk borders), so no carry chain is longer than
// ceil((WIDTH+1) / 2) bits.  A border lies at bit WIDTH-1: the + 1 is preset there
// (chunk 2's first bit) at the start, and no partial product reaches below it after
// the chunks there have settled, so one flush cycle settles the last carries.  The
// start clears the sums and carries with the flip-flops' synchronous reset, so the
// chains' sums and carries go straight into flip-flops (no LUT after a chain; a
// carry that also fed fabric logic would split an iCE40 chain).
// The partial product is registered, from the operand registers only, so the chains
// start at registers and no path runs from a, b to the accumulator: the first busy
// cycle clears the accumulator while the first partial product is registered.  While
// idle the operand registers follow a and b (no clock enable).
//
// Timing: `start` in a cycle with busy low captures a, b (cycle 0); busy is high
// in cycles 1 .. WIDTH+2 (a clearing cycle, WIDTH partial products, a carry flush);
// `done` is a one-cycle strobe in cycle WIDTH+3, when `product` becomes valid; product
// holds until the next product's first busy cycle (it shows partial sums while busy).
// `start` while busy is ignored; `rst` returns to idle and clears the product.
module seq_mult #(
    parameter integer WIDTH = 33    // operand width, signed (>= 3)
) (
    input  wire               clk,
    input  wire               rst,
    input  wire               start,    // capture a, b (ignored while busy)
    input  wire [WIDTH-1:0]   a,        // signed operands
    input  wire [WIDTH-1:0]   b,
    output wire               busy,     // high from the cycle after start until the product is ready
    output reg                done,     // one-cycle strobe: product valid from this cycle on
    output wire [2*WIDTH-1:0] product   // signed a * b, held until the cycle after the next start
);
    initial begin
        if (WIDTH < 3) $error("%m: WIDTH must be at least 3");
    end

    localparam integer PW = 2 * WIDTH;          // product width
    localparam integer NW = $clog2(WIDTH + 2);  // cycle counter 0 .. WIDTH+1

    reg  [PW-1:0]    acc_q;        // partial sum (plus the pending chunk carries)
    reg  [PW-1:0]    mcand_q;      // multiplicand, sign-extended, shifted left i places
    reg  [WIDTH-1:0] mplier_q;     // multiplier, shifted right: bit i in bit 0 (zeros follow)
    reg  [2:0]       carry_q;      // pending carries into chunks 1, 2 and 3
    reg  [PW-1:0]    addend_q;     // this cycle's partial product: 0, mcand or ~mcand's top (a cycle old)
    reg              sign_q;       // mplier_q[0] is b's sign bit (busy cycle WIDTH)
    reg              first_q;      // the first busy cycle
    reg  [NW-1:0]    count_q;      // busy cycle index
    reg              last_q;       // the last busy cycle (count_q = WIDTH + 1)
    reg              busy_q;

    assign busy = busy_q;
    assign product = acc_q;

    // The partial product, registered (the chunk chains start at registers): 0, the
    // multiplicand, or (b's sign bit) its inverse from bit WIDTH-1 up.
    localparam [PW-1:0] SIGN_MASK = {{(PW-WIDTH+1){1'b1}}, {(WIDTH-1){1'b0}}};
    wire [PW-1:0] partial = !mplier_q[0] ? {PW{1'b0}} : sign_q ? ~mcand_q & SIGN_MASK : mcand_q;
    wire [PW-1:0] a_ext = {{(PW-WIDTH){a[WIDTH-1]}}, a};
    // Chunk borders: the low WIDTH-1 bits in two chunks, the rest in two.
    function integer border(input integer k);
        border = k == 0 ? 0 : k == 1 ? (WIDTH - 1) / 2 : k == 2 ? WIDTH - 1 : k == 3 ? WIDTH - 1 + (WIDTH + 2) / 2 : PW;
    endfunction
    wire [PW-1:0] acc_next;         // the chunks' sums
    wire [3:0]    carry_out;        // and their carries out
    wire [3:0]    carry_in = {carry_q, 1'b0};
    genvar j;
    generate
        for (j = 0; j < 4; j = j + 1) begin : g_chunk
            localparam integer LO = border(j), N = border(j + 1) - border(j);
            assign {carry_out[j], acc_next[LO +: N]} = {1'b0, acc_q[LO +: N]} + {1'b0, addend_q[LO +: N]} +
                                                       {{N{1'b0}}, carry_in[j]};
        end
    endgenerate
    localparam [31:0] BEFORE_LAST32 = WIDTH;       // busy cycle index before the last one
    localparam [NW-1:0] BEFORE_LAST = BEFORE_LAST32[NW-1:0];

    always @(posedge clk) begin
        addend_q <= partial;        // every cycle: a register with no enable and no reset
        // The first busy cycle clears the sum and the carries (the partial product
        // registered while idle is not this product's) and presets the + 1 of
        // -A * 2^(WIDTH-1); the other bits' clear is the flip-flops' synchronous reset.
        if (rst || first_q) begin
            acc_q   <= {{(PW-WIDTH){1'b0}}, !rst && mplier_q[WIDTH-1], {(WIDTH-1){1'b0}}};
            carry_q <= 3'b000;
        end else if (busy_q) begin
            acc_q   <= acc_next;
            carry_q <= carry_out[2:0];
        end
        // The operands: data registers (no reset), following a and b while idle (no
        // clock enable: the enable nets of the parent's loops keep the global buffers).
        if (!busy_q) begin
            mcand_q  <= a_ext;
            mplier_q <= b;
        end else begin
            mcand_q  <= {mcand_q[PW-2:0], 1'b0};
            mplier_q <= {1'b0, mplier_q[WIDTH-1:1]};
        end
        if (rst) begin
            count_q    <= {NW{1'b0}};
            first_q    <= 1'b0;
            sign_q     <= 1'b0;
            last_q     <= 1'b0;
            busy_q     <= 1'b0;
            done       <= 1'b0;
        end else begin
            done <= 1'b0;
            if (!busy_q) begin
                if (start) begin
                    count_q    <= {NW{1'b0}};
                    sign_q     <= 1'b0;
                    first_q    <= 1'b1;
                    busy_q     <= 1'b1;
                end
            end else begin
                first_q    <= 1'b0;
                sign_q     <= {{(32-NW){1'b0}}, count_q} + 32'd2 == WIDTH;
                count_q    <= count_q + 1'b1;
                last_q     <= count_q == BEFORE_LAST;
                if (last_q) begin
                    busy_q <= 1'b0;
                    done   <= 1'b1;
                end
            end
        end
    end

    // Chunk 3's carry out falls off the top.
    wire unused = &{1'b0, carry_out[3]};
endmodule
`default_nettype wire
