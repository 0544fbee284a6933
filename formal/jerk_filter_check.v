// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Formal harness of the S-curve filter (formal/jerk_filter.sby): a ramp that
// follows the filter's contract (a strobe only with a block tick, blocks of
// 2^block_shift clocks, the speed n * A changing at the end of the strobe's
// clock), any quantum A, any jerk_shift 0 .. MW and block_shift 0 .. 1 (0 with
// jerk_shift 0 only), the delay line's memory with any contents at power-up.  Property: in every
// clock the filter's F equals the golden moving sum
//     F(t) = v(t) + v(t - B) + ... + v(t - (M - 1) B)
// over a shadow history of the speed (so the distance is exactly M times the
// virtual one), and `sum` = F (shift > 0) or v (shift 0).
// With LATE defined, the last drop of a stop (1 -> 0 quantum) may also come
// inside a block, once per block: then `sum` is no longer the moving sum
// clock by clock (the filter keeps the speed to the block's end and pays the
// extra back later), and the property is the distance: whenever the filter is
// empty, the sum of `sum` so far is exactly 2^shift times the sum of v.
module jerk_filter_check #(
    parameter integer FEED_W = 4,
    parameter integer MW     = 2
) (
    input wire clk,
    input wire rst,
    input wire up,
    input wire down
);
    localparam integer SUM_W = FEED_W + MW;
    localparam integer HIST  = (1 << MW) * 2;          // M * B clocks at most

    (* anyconst *) reg [FEED_W-3:0] quantum;           // A < 2^(FEED_W-2): 3 quanta fit
    (* anyconst *) reg [3:0]        jerk_shift;
    (* anyconst *) reg              block_shift;

    reg  [1:0]        n;                                // speed in quanta, 0 .. 3
    reg               phase;                            // clock within the block (block_shift 1)
    wire              block = !block_shift || phase;
    wire [FEED_W-1:0] a     = {2'b00, quantum};
    wire [FEED_W-1:0] speed = n == 2'd0 ? 0 : n == 2'd1 ? a : n == 2'd2 ? a << 1 : (a << 1) + a;

    wire [SUM_W-1:0] sum;
    wire [3:0]       shift;
    wire             empty;
    jerk_filter #(.FEED_W(FEED_W), .MW(MW), .SUM_W(SUM_W)) dut (
        .clk(clk), .rst(rst), .speed(speed), .up(up), .down(down), .block(block),
        .speed_quantum(a), .jerk_shift(jerk_shift), .sum(sum), .shift(shift), .empty(empty)
    );

`ifdef FORMAL
    reg f_past_valid = 1'b0;
    always @(posedge clk) f_past_valid <= 1'b1;
    always @(*) if (!f_past_valid) assume (rst);
    always @(*) begin
        assume (jerk_shift <= MW);
        if (!block_shift) assume (jerk_shift == 0);     // shift > 0: blocks of 2 clocks or more
`ifdef LATE
        if (up) assume (block && !rst);
        if (down && !block) assume (!rst && n == 2'd1 && !f_late);
`else
        if (up || down) assume (block && !rst);
`endif
        if (up) assume (!down && n != 2'd3);
        if (down) assume (n != 2'd0);
    end

    // the ramp and the shadow history of the speed (hist[k] = v(t - 1 - k))
    reg [FEED_W-1:0] hist [0:HIST-1];
    integer k;
    always @(posedge clk) begin
        if (rst) begin
            n <= 2'd0;
            phase <= 1'b0;
            for (k = 0; k < HIST; k = k + 1) hist[k] <= {FEED_W{1'b0}};
        end else begin
            n <= n + {1'b0, up} - {1'b0, down};
            phase <= !phase;
            hist[0] <= speed;
            for (k = 1; k < HIST; k = k + 1) hist[k] <= hist[k - 1];
        end
    end

    // golden F: v(t) + v(t - B) + ... (M terms)
    reg [SUM_W-1:0] golden;
    integer j;
    always @(*) begin
        golden = {{MW{1'b0}}, speed};
        for (j = 1; j < (1 << MW); j = j + 1)
            if (j < (1 << jerk_shift))
                golden = golden + {{MW{1'b0}}, hist[(j << block_shift) - 1]};
    end

    // ghost totals: the virtual distance and the filter's, and a late drop in this block
    reg [15:0] f_virtual, f_filtered;
    reg        f_late;
    always @(posedge clk) begin
        if (rst) begin
            f_virtual <= 16'd0; f_filtered <= 16'd0; f_late <= 1'b0;
        end else begin
            f_virtual  <= f_virtual + {{(16-FEED_W){1'b0}}, speed};
            f_filtered <= f_filtered + {{(16-SUM_W){1'b0}}, sum};
            f_late     <= !block && (f_late || down);
        end
    end

`ifdef LATE
    always @(*) if (f_past_valid && !rst) begin
        assert (shift == jerk_shift);
        if (jerk_shift == 4'd0) assert (sum == {{MW{1'b0}}, speed});
        if (empty) assert (f_filtered == f_virtual << jerk_shift);
    end
`else
    always @(*) if (f_past_valid && !rst) begin
        assert (shift == jerk_shift);
        assert (sum == (jerk_shift == 4'd0 ? {{MW{1'b0}}, speed} : golden));
        if (empty) assert (golden == 0 && speed == 0);
        if (empty) assert (f_filtered == f_virtual << jerk_shift);
    end
`endif
`endif
endmodule
`default_nettype wire
