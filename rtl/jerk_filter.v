// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// S-curve filter of the speed-setting block of the lecture ("БЗС"): the path
// speed profile's jerk limit.  The virtual trapezoid (speed_ramp) changes its
// speed v by one quantum A at most once per block; this filter outputs
//
//     sum = F = v(t) + v(t - B) + ... + v(t - (M - 1) B),  M = 2^shift blocks,
//
// the moving sum of the block speeds (B = 2^block_shift clocks).  Each block's
// change of v is kept as a 2-bit code (two's complement -2 .. +1 quanta) in a
// delay line of 2^MW codes (code_delay, block RAM); per block tick, adders only:
//     D <= D + A (c_now - c_delayed)     (D = v_now - v_delayed)
//     F <= F + D_new.
// The sum of F over time is exactly M times the sum of v, so a pacer that
// charges each step M times its cost travels exactly the virtual distance;
// the acceleration of F rises over M blocks: jerk = a / (M blocks).
// shift = 0 is the trapezoid (infinite jerk): sum = speed.
//
// Contract with the ramp: up / down mean v changes by +-A at the end of this
// clock (speed shows the new value from the next clock on).  They come with
// `block`, except the last drop of a stop, which may come inside a block (at
// most one such `down` per block; an `up` without `block` is ignored): the
// filter then keeps the old speed to the block's end, books the extra travel,
// A << shift per clock, as a debt and pays it back from F (sum = F - pay,
// pay = min(debt, F)) before it empties, so the distance stays exact.
// With shift > 0, block ticks come at least 2 clocks apart (the delay line's word,
// read at a tick, is taken from a flip-flop a clock later; speed_ramp's blocks are of
// 4 clocks or more).  speed_quantum is constant while the filter is not empty.
// jerk_shift is latched into `shift` only while the filter is empty (a new value then
// restarts the delay line; values above MW count as MW); the pacer must use
// `shift`.
module jerk_filter #(
    parameter integer FEED_W = 16,          // width of the speed and the quantum (>= 2)
    parameter integer MW     = 6,           // log2 of the delay line depth: jerk_shift 0 .. MW (2 .. 15)
    parameter integer SUM_W  = FEED_W + MW  // width of sum: must be FEED_W + MW
) (
    input  wire              clk,
    input  wire              rst,
    input  wire [FEED_W-1:0] speed,          // virtual speed v of this clock
    input  wire              up,             // v rises by one quantum at the end of this clock
    input  wire              down,           // v falls by one quantum at the end of this clock (or a stop's last drop)
    input  wire              block,          // block tick (the clock where v may change)
    input  wire [FEED_W-1:0] speed_quantum,  // A
    input  wire [3:0]        jerk_shift,     // log2 M, taken while empty
    output wire [SUM_W-1:0]  sum,            // F: sum of the last M block speeds
    output wire [3:0]        shift,          // the jerk_shift in use (for step_pacer)
    output wire              empty           // F = 0, v = 0, nothing in flight
);
    initial begin
        if (FEED_W < 2) $error("%m: FEED_W must be at least 2");
        if (MW < 2 || MW > 15) $error("%m: MW must be 2 .. 15");
        if (SUM_W != FEED_W + MW) $error("%m: SUM_W must be FEED_W + MW");
    end

    localparam integer DW = FEED_W + 3;                // D and A (c_now - c_delayed), signed
    localparam integer OW = FEED_W + 2 * MW + 16;      // the debt of drops inside blocks
    localparam [3:0]  DEEPEST = MW[3:0];                  // the largest shift
    localparam [MW:0] DEPTH = {1'b1, {MW{1'b0}}};      // 2^MW

    reg  [SUM_W-1:0]  total;        // F
    reg  [DW-1:0]     delta;        // D = v_now - v_delayed, two's complement
    reg  [3:0]        shift_q;
    reg  [MW:0]       count;        // codes written since the restart, saturating at 2^MW
    reg  [MW-1:0]     write_address;
    reg  [1:0]        code_last;
    wire [1:0]        code_read;
    reg  [1:0]        code_held;    // code_read a clock after the read: the RAM's output alone in its path
    reg               pending;      // a drop inside this block, booked at its end
    reg  [OW-1:0]     owed;         // travel F owes back (F units)

    // this block's code: up - down, plus a drop made inside the block
    wire [1:0]  code_now = {1'b0, up} - {1'b0, down} - {1'b0, pending};   // modulo 4: -2 .. +1
    wire [MW:0] span     = {{MW{1'b0}}, 1'b1} << shift_q;                // M
    wire        single   = shift_q == 4'd0;
    wire        aged     = count >= span;                                 // the code M ticks ago exists
    wire [1:0]  code_old = ~aged ? 2'b00 : single ? code_last : code_held;
    wire [MW-1:0] read_address = write_address + 1'b1 - span[MW-1:0];     // the code M - 1 ticks ago

    // A * (c_now - c_old), c in {-2 .. +1}: 0, +-A, +-2A or +-3A
    wire [DW-1:0] quantum = {3'b000, speed_quantum};
    wire [DW-1:0] triple  = quantum + (quantum << 1);
    wire signed [2:0] step_old = {code_old[1], code_old};
    wire signed [3:0] change   = {code_now[1], code_now[1], code_now} - {step_old[2], step_old};
    reg  [DW-1:0] adjust;
    always @* begin
        case (change)
            4'sd1:   adjust = quantum;
            4'sd2:   adjust = quantum << 1;
            4'sd3:   adjust = triple;
            -4'sd1:  adjust = -quantum;
            -4'sd2:  adjust = -(quantum << 1);
            -4'sd3:  adjust = -triple;
            default: adjust = {DW{1'b0}};
        endcase
    end
    wire [DW-1:0]    delta_next = delta + adjust;
    wire [SUM_W-1:0] delta_wide;                       // D, sign-extended (F is modulo 2^SUM_W)
    generate
        if (SUM_W > DW) begin : g_extend
            assign delta_wide = {{(SUM_W-DW){delta_next[DW-1]}}, delta_next};
        end else if (SUM_W == DW) begin : g_same
            assign delta_wide = delta_next;
        end else begin : g_cut
            assign delta_wide = delta_next[SUM_W-1:0];
            wire unused_top = &{1'b0, delta_next[DW-1:SUM_W]};
        end
    endgenerate

    // the debt: A << shift for every clock the filter keeps a speed the ramp dropped
    wire [OW-1:0]    accrue = pending && !single ? {{(OW-FEED_W){1'b0}}, speed_quantum} << shift_q
                                                 : {OW{1'b0}};
    wire [OW-1:0]    total_wide = {{(OW-SUM_W){1'b0}}, total};
    // pay = min(debt, F): one subtraction gives both the rest of the debt and the
    // comparison; F - debt is formed beside it
    wire [OW:0]      rest     = {1'b0, owed} - {1'b0, total_wide};   // debt - F
    wire             covered  = rest[OW];                             // debt < F
    wire [SUM_W-1:0] left     = total - owed[SUM_W-1:0];              // F - debt, if covered
    wire [OW-1:0]    owed_now = single ? owed : covered ? {OW{1'b0}} : rest[OW-1:0];
    wire [3:0] wanted = jerk_shift > DEEPEST ? DEEPEST : jerk_shift;
    assign empty = total == {SUM_W{1'b0}} && delta == {DW{1'b0}} && speed == {FEED_W{1'b0}} &&
                   owed == {OW{1'b0}} && !pending;
    assign sum   = single ? {{MW{1'b0}}, speed} : covered ? left : {SUM_W{1'b0}};
    assign shift = shift_q;

    code_delay #(.AW(MW), .WIDTH(2)) u_line (
        .clk(clk), .write(block), .write_address(write_address), .data(code_now),
        .read(block), .read_address(read_address), .q(code_read)
    );

    always @(posedge clk) begin
        if (rst) begin
            total         <= {SUM_W{1'b0}};
            delta         <= {DW{1'b0}};
            count         <= {(MW+1){1'b0}};
            write_address <= {MW{1'b0}};
            code_last     <= 2'b00;
            code_held     <= 2'b00;
            shift_q       <= wanted;
            pending       <= 1'b0;
            owed          <= {OW{1'b0}};
        end else begin
            pending <= ~block & (pending | down);
            code_held <= code_read;
            owed    <= owed_now + accrue;
            if (block) begin
                delta         <= delta_next;
                total         <= total + delta_wide;
                code_last     <= code_now;
                write_address <= write_address + 1'b1;
            end
            if (empty && wanted != shift_q) begin
                shift_q <= wanted;
                count   <= {{MW{1'b0}}, block};
            end else if (block && count != DEPTH) begin
                count   <= count + 1'b1;
            end
        end
    end
endmodule
`default_nettype wire
