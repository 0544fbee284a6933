`default_nettype none
// Sequential signed multiplier (shift-add, radix 2): product = a * b, for set-up
// products that must not cost a combinational multiplier.
// The multiplicand, sign-extended, shifts left one place per cycle and is added
// to the accumulator when the multiplier's next bit (LSB first) is 1; the last
// (sign) bit subtracts it (two's complement: inverted operand plus a carry-in).
// The 2*WIDTH-bit accumulator is three chunks of CW bits, each with its own short
// carry chain; a chunk's carry out is registered and enters the next chunk one
// cycle later (carry-save at the chunk borders), so no carry chain is longer
// than CW = ceil(2*WIDTH / 3) bits.  Two flush cycles settle those carries.
// The partial product is registered a cycle ahead, so the chains start at
// registers; while idle the operand registers follow a and b (no clock enable).
//
// Timing: `start` in a cycle with busy low captures a, b (cycle 0); busy is high
// in cycles 1 .. WIDTH+2 (WIDTH partial products, two carry flushes); `done` is
// a one-cycle strobe in cycle WIDTH+3, when `product` becomes valid; product
// holds until the next start (it shows partial sums while busy).  `start` while
// busy is ignored; `rst` clears everything.
module seq_mult #(
    parameter integer WIDTH = 33    // operand width, signed (>= 2)
) (
    input  wire               clk,
    input  wire               rst,
    input  wire               start,    // capture a, b (ignored while busy)
    input  wire [WIDTH-1:0]   a,        // signed operands
    input  wire [WIDTH-1:0]   b,
    output wire               busy,     // high from the cycle after start until the product is ready
    output reg                done,     // one-cycle strobe: product valid from this cycle on
    output wire [2*WIDTH-1:0] product   // signed a * b, held until the next start
);
    initial begin
        if (WIDTH < 2) $error("%m: WIDTH must be at least 2");
    end

    localparam integer PW = 2 * WIDTH;          // product width
    localparam integer CW = (PW + 2) / 3;       // chunk width
    localparam integer AW = 3 * CW;             // accumulator (PW rounded up to three chunks)
    localparam integer NW = $clog2(WIDTH + 2);  // cycle counter 0 .. WIDTH+1

    reg  [AW-1:0]    acc_q;        // partial sum (plus the pending chunk carries)
    reg  [AW-1:0]    mcand_q;      // multiplicand, sign-extended, shifted left i places
    reg  [WIDTH-1:0] mplier_q;     // multiplier, shifted right: bit i in bit 0 (zeros follow)
    reg  [1:0]       carry_q;      // pending carries into chunks 1 and 2
    reg  [AW-1:0]    addend_q;     // this cycle's partial product: 0, mcand_q or ~mcand_q
    reg              cin0_q;       // + 1 with ~mcand_q (b's sign bit subtracts)
    reg              sign_next_q;  // mplier_q[1] is b's sign bit (busy cycle WIDTH - 2)
    reg  [NW-1:0]    count_q;      // busy cycle index
    reg              last_q;       // the last busy cycle (count_q = WIDTH + 1)
    reg              busy_q;

    assign busy = busy_q;
    assign product = acc_q[PW-1:0];

    // The partial product is registered a cycle ahead (the chunk chains start at
    // registers): 0, the multiplicand, or (b's sign bit) its inverse + 1.
    function automatic [AW:0] partial(input bit_i, sign_i, input [AW-1:0] m);   // {+1, addend}
        partial = !bit_i ? {(AW+1){1'b0}} : sign_i ? {1'b1, ~m} : {1'b0, m};
    endfunction
    wire [AW-1:0] a_ext = {{(AW-WIDTH){a[WIDTH-1]}}, a};
    wire [AW:0]   first = partial(b[0], 1'b0, a_ext);                               // for cycle 1
    wire [AW:0]   next = partial(mplier_q[1], sign_next_q, {mcand_q[AW-2:0], 1'b0});
    wire [CW:0]   sum0 = {1'b0, acc_q[CW-1:0]}        + {1'b0, addend_q[CW-1:0]}        + {{CW{1'b0}}, cin0_q};
    wire [CW:0]   sum1 = {1'b0, acc_q[2*CW-1:CW]}     + {1'b0, addend_q[2*CW-1:CW]}     + {{CW{1'b0}}, carry_q[0]};
    wire [CW:0]   sum2 = {1'b0, acc_q[3*CW-1:2*CW]}   + {1'b0, addend_q[3*CW-1:2*CW]}   + {{CW{1'b0}}, carry_q[1]};
    localparam [31:0] BEFORE_LAST32 = WIDTH;       // busy cycle index before the last one
    localparam [NW-1:0] BEFORE_LAST = BEFORE_LAST32[NW-1:0];

    always @(posedge clk) begin
        if (rst) begin
            acc_q      <= {AW{1'b0}};
            mcand_q    <= {AW{1'b0}};
            mplier_q   <= {WIDTH{1'b0}};
            carry_q    <= 2'b00;
            addend_q   <= {AW{1'b0}};
            cin0_q     <= 1'b0;
            count_q    <= {NW{1'b0}};
            sign_next_q <= 1'b0;
            last_q     <= 1'b0;
            busy_q     <= 1'b0;
            done       <= 1'b0;
        end else begin
            done <= 1'b0;
            if (!busy_q) begin
                // The operand registers follow a and b while idle (no clock enable:
                // the enable nets of the parent's loops keep the global buffers).
                mcand_q  <= a_ext;
                mplier_q <= b;
                {cin0_q, addend_q} <= first;
                if (start) begin
                    acc_q      <= {AW{1'b0}};
                    carry_q    <= 2'b00;
                    count_q    <= {NW{1'b0}};
                    sign_next_q <= WIDTH == 2;
                    busy_q     <= 1'b1;
                end
            end else begin
                acc_q      <= {sum2[CW-1:0], sum1[CW-1:0], sum0[CW-1:0]};
                carry_q    <= {sum1[CW], sum0[CW]};
                mcand_q    <= {mcand_q[AW-2:0], 1'b0};
                mplier_q   <= {1'b0, mplier_q[WIDTH-1:1]};
                {cin0_q, addend_q} <= next;
                sign_next_q <= {{(32-NW){1'b0}}, count_q} + 32'd3 == WIDTH;
                count_q    <= count_q + 1'b1;
                last_q     <= count_q == BEFORE_LAST;
                if (last_q) begin
                    busy_q <= 1'b0;
                    done   <= 1'b1;
                end
            end
        end
    end

    // Chunk 2's carry out falls off the top; bits above PW are padding; the operand
    // registers are read a cycle ahead (the partial product is registered).
    wire unused = &{1'b0, sum2[CW], acc_q[AW-1:PW-1], mcand_q[AW-1], mplier_q[0]};
endmodule
`default_nettype wire
