// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Budget refinement of the path-speed profile generator (speed_ramp), in the
// lecture's speed-setting block ("БЗС"): the clock that crosses a segment's end is
// charged to the next segment's budget whole (2 p' n), and the part of its travel
// that belonged to the segment before, r = the old S (or, at a load, K A + c), is
// given back as 2 p' floor(r / A), one quotient bit a clock, most significant first,
// over the NW clocks after the switch: restoring division by shifts.  The divisor
// starts at A 2^(NW-1) and halves every clock; when the remainder holds it, the
// remainder loses it and `gift` carries that bit's worth, p' 2^(k+1) for bit k (it
// starts at p' 2^NW and halves too).  The quotient bit is formed a clock ahead.
//
// Timing: `start` loads the division (and overrides `cancel`); `cancel` drops what
// is left of it (the segment ended first); `gift` is the bit of this clock, to be
// added to the budget at the next edge.  r < A 2^NW, so NW bits hold the quotient.
module speed_ramp_refine #(
    parameter integer FEED_W = 16,  // speed word: path units per clock (>= 2)
    parameter integer NW     = 16,  // speed in quanta n, the quotient's bits (2 .. 64)
    parameter integer PF     = 12   // fraction bits of the rate p (1 .. 64)
) (
    input  wire                 clk,
    input  wire                 rst,
    input  wire                 start,          // a switch above rest or a load: divide `remainder`
    input  wire                 cancel,         // the segment's end: drop the rest of the division
    input  wire [NW+FEED_W-1:0] remainder,      // r, below A 2^NW
    input  wire [FEED_W-1:0]    speed_quantum,  // A, the divisor
    input  wire [PF:0]          rate,           // p' of the segment that receives the gift
    output wire [PF+NW:0]       gift            // this clock's part of 2 p' floor(r / A)
);
    initial begin
        if (FEED_W < 2) $error("%m: FEED_W must be at least 2");
        if (NW < 2 || NW > 64) $error("%m: NW must be 2 .. 64");
        if (PF < 1 || PF > 64) $error("%m: PF must be 1 .. 64");
    end

    localparam integer MW = NW + FEED_W;            // the remainder
    localparam [31:0]  NW32 = NW;
    localparam [7:0]   NW8  = NW32[7:0];

    reg  [7:0]    count;        // quotient bits still to form
    reg  [MW-1:0] rest;         // the remainder
    reg  [MW-2:0] divisor;      // A 2^k
    reg  [PF+NW:0] worth;       // p' 2^(k+1)
    reg           hit;          // count != 0 and rest >= divisor, formed a clock ahead

    wire [MW-1:0] rest_less    = rest - {1'b0, divisor};
    wire [MW-2:0] divisor_half = divisor >> 1;
    // the first bit, r >= A 2^(NW-1), on the top bits (equal for integers)
    wire          start_hit    = remainder[MW-1:NW-1] >= {1'b0, speed_quantum};
    assign gift = hit ? worth : {(PF+NW+1){1'b0}};

    always @(posedge clk) begin
        if (rst) begin
            count <= 8'd0; rest <= {MW{1'b0}}; divisor <= {(MW-1){1'b0}};
            worth <= {(PF+NW+1){1'b0}}; hit <= 1'b0;
        end else begin
            if (start) begin
                rest <= remainder; divisor <= {speed_quantum, {(NW-1){1'b0}}};
                worth <= {rate, {NW{1'b0}}}; count <= NW8;
            end else if (cancel) begin
                count <= 8'd0;
            end else if (count != 8'd0) begin
                if (hit) rest <= rest_less;
                divisor <= divisor_half; worth <= worth >> 1; count <= count - 8'd1;
            end
            // the next clock's bit: the divisor halves, the remainder loses it or not
            if (start)
                hit <= start_hit;
            else if (cancel || count <= 8'd1)
                hit <= 1'b0;
            else
                hit <= (hit ? rest_less : rest) >= {1'b0, divisor_half};
        end
    end

`ifdef FORMAL
    // (formal/speed_ramp.sby) the bit formed a clock ahead is the bit of its clock
    always @(*) if (!rst) assert (hit == ((count != 8'd0) && (rest >= {1'b0, divisor})));
`endif
endmodule
`default_nettype wire
