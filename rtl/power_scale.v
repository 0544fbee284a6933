// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Laser power that follows the speed (no patent element: Grbl's dynamic laser power, M4
// in laser mode): so that a corner or a start, where the machine moves slower, gets the
// same energy per length as the cruise,
//
//     scaled = duty * ratio / 65536,   ratio = floor(speed * 65536 / D),   D = feed << shift
//
// where speed is the S-curve filter's sum, 2^shift times the speed of the steps (so the
// power follows the steps, not the speed generator ahead of them), and feed the running
// move's cruise: duty itself at or above the cruise, 0 while feed is 0.  Bit-serial, to
// stay small at the controller's wide speed words: one full adder walks the
// RW = SPEED_W + 2 bits of a partial remainder held in a shift register, lowest bit first.
//   load pass ........ the remainder R = speed; speed >= D and feed != 0 found on the way
//   16 divide passes . non-restoring division: R = 2R - D if R >= 0, else 2R + D; the
//                      quotient bit is 1 when the new R is >= 0
//   16 multiply rounds acc = (acc + duty bit * ratio) / 2, lowest duty bit first
//   done ............. scaled = acc (duty if speed >= D); the inputs taken for the next
// A sequence is ROUNDS = 17 x RW + 17 clocks (833 at FEED_W 34, SPEED_W 46): `scaled` is
// new every ROUNDS clocks, from the inputs of the clock that ended the sequence before.
module power_scale #(
    parameter integer FEED_W  = 16, // width of feed (1 .. 200)
    parameter integer SPEED_W = 22  // width of speed: FEED_W + the largest shift (FEED_W .. 200)
) (
    input  wire               clk,
    input  wire               rst,
    input  wire [15:0]        duty,     // the programmed power, 0 .. 65535
    input  wire [SPEED_W-1:0] speed,    // 2^shift times the speed of the steps
    input  wire [3:0]         shift,    // (at most SPEED_W - FEED_W)
    input  wire [FEED_W-1:0]  feed,     // the cruise speed of the move (its units)
    output reg  [15:0]        scaled
);
    initial begin
        if (FEED_W < 1 || FEED_W > 200) $error("%m: FEED_W must be 1 .. 200");
        if (SPEED_W < FEED_W || SPEED_W > 200) $error("%m: SPEED_W must be FEED_W .. 200");
    end

    localparam integer RW = SPEED_W + 2;          // the partial remainder, signed: |2R| < 2^RW / 2
    localparam [31:0] TOP_WIDE   = RW - 1;
    localparam [31:0] FEED_WIDE  = FEED_W;
    localparam [31:0] SPEED_WIDE = SPEED_W;
    localparam [7:0]  TOP    = TOP_WIDE[7:0];     // the last bit of a pass
    localparam [7:0]  FEED_BITS  = FEED_WIDE[7:0];
    localparam [7:0]  SPEED_BITS = SPEED_WIDE[7:0];
    localparam [4:0]  PASSES = 5'd17;             // the load pass and 16 divide passes

    reg  [SPEED_W-1:0] speed_q;
    reg  [FEED_W-1:0]  feed_q;
    reg  [3:0]         shift_q;
    reg  [15:0]       duty_q;
    reg  [RW-1:0]     remainder;    // R, lowest bit at [0]; a pass shifts it through once
    reg  [7:0]        bit_index;    // 0 .. TOP within a pass
    reg  [4:0]        pass;         // 0 load, 1 .. 16 divide, 17 multiply
    reg  [4:0]        multiply;     // the multiply round, 0 .. 16 (16: done)
    reg               previous;     // R's bit below the one leaving now: 2R's bit
    reg               carry;
    reg               negative;     // R < 0 (from the pass before)
    reg               at_least;     // speed >= D, found lowest bits first
    reg               nonzero;      // feed != 0
    reg  [15:0]       ratio;        // quotient bits, highest first
    reg  [15:0]       acc;

    // the bits of this clock: speed's bit_index, D's (feed's bit_index - shift)
    wire [SPEED_W-1:0] speed_at = speed_q >> bit_index;
    wire [7:0]         feed_index = bit_index - {4'd0, shift_q};
    wire [FEED_W-1:0]  feed_at  = feed_q >> feed_index;
    wire speed_bit   = (bit_index < SPEED_BITS) & speed_at[0];
    wire feed_bit    = (bit_index >= {4'd0, shift_q}) & (feed_index < FEED_BITS) & feed_at[0];
    wire first       = bit_index == 8'd0;
    wire last        = bit_index == TOP;
    wire subtract    = ~negative;
    wire a           = first ? 1'b0 : previous;          // 2R
    wire b           = feed_bit ^ subtract;               // -D: its complement, carry in 1
    wire c           = first ? subtract : carry;
    wire sum         = a ^ b ^ c;
    wire [15:0] factor = nonzero ? ratio : 16'd0;     // (speed >= D: duty, below)
    wire [16:0] added  = {1'b0, acc} + (duty_q[multiply[3:0]] ? {1'b0, factor} : 17'd0);

    always @(posedge clk) begin
        if (rst) begin
            speed_q   <= {SPEED_W{1'b0}};
            feed_q    <= {FEED_W{1'b0}};
            shift_q   <= 4'd0;
            duty_q    <= 16'd0;
            remainder <= {RW{1'b0}};
            bit_index <= 8'd0;
            pass      <= 5'd0;
            multiply  <= 5'd0;
            previous  <= 1'b0;
            carry     <= 1'b0;
            negative  <= 1'b0;
            at_least  <= 1'b1;
            nonzero   <= 1'b0;
            ratio     <= 16'd0;
            acc       <= 16'd0;
            scaled    <= 16'd0;
        end else if (pass != PASSES) begin
            bit_index <= last ? 8'd0 : bit_index + 8'd1;
            previous  <= remainder[0];
            if (last)
                pass <= pass + 5'd1;
            if (pass == 5'd0) begin
                remainder <= {speed_bit, remainder[RW-1:1]};
                at_least  <= (speed_bit & ~feed_bit) | (~(speed_bit ^ feed_bit) & at_least);
                nonzero   <= nonzero | feed_bit;
            end else begin
                remainder <= {sum, remainder[RW-1:1]};
                carry     <= (a & b) | (a & c) | (b & c);
                if (last) begin
                    negative <= sum;
                    ratio    <= {ratio[14:0], ~sum};
                end
            end
        end else if (multiply != 5'd16) begin
            acc      <= added[16:1];
            multiply <= multiply + 5'd1;
        end else begin
            scaled    <= nonzero & at_least ? duty_q : acc;
            speed_q   <= speed;
            feed_q    <= feed;
            shift_q   <= shift;
            duty_q    <= duty;
            pass      <= 5'd0;
            multiply  <= 5'd0;
            negative  <= 1'b0;
            at_least  <= 1'b1;
            nonzero   <= 1'b0;
            acc       <= 16'd0;
        end
    end

    wire unused = &{1'b0, speed_at, feed_at, added[0]};    // (bit 0 of the first two is used)
endmodule
`default_nettype wire
