// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Path-speed profile generator: the virtual domain of the lecture's speed-setting
// block ("БЗС"), a trapezoid generator with a look-ahead of one segment.
//
// The speed is n quanta, v = n * A (A = speed_quantum, path units per clock).
// Time runs in blocks of 2^block_shift clocks; at the end of every block a DDA adds
// the segment's rate (p * 2^PF) and, when it overflows, n may rise or fall by one:
// path acceleration p * A / 2^block_shift per clock^2.  The remaining distance S of
// the segment falls by v every clock; the clock that crosses 0 carries its overshoot
// into the next segment, so the distance is exact.
// Braking: the budget Zx = 2^block_shift * 2 p S / (2^block_shift A) * 2^PF falls by
// 2 p n * 2^PF every clock.  At a DDA tick, with u the DDA phase of the next block,
// n is raised only if Zx >= R(n + 1, u) << block_shift, kept only if
// Zx >= R(n, u) << block_shift, else lowered, where R(n, u) = n^2 + n - f^2 - f +
// 2 n (p - u) (quanta^2, n > f; 0 for n <= f) bounds the budget that braking at
// every following tick may use (f = max(exit, 1)).  n (n + 1), p n and n u are kept
// by adders.  The target is the exit speed if the next segment is known (at the
// head of the queue, not a barrier, its p' n and f (f + 1) set up by the sequential
// multipliers, p' n followed as n moves), else 0: at the clock S crosses 0 with
// target 0 the last quantum drops (n 1 -> 0; `late` if n was higher).  The crossing
// clock's travel is charged to the next segment's budget whole (2 p' n) and the part
// that belonged to the old one, 2 p' floor(S / A), is given back over the next NW
// clocks (restoring division by shifts: speed_ramp_refine).  Cap: v <= min(feed *
// override / 100, limit), compared as 100 v <= feed * override (the product
// recomputed every 9 clocks), lowered at the DDA ticks when exceeded.  hold lowers n
// at every tick to 0.
// Timing: the thresholds and the cap are compared over the three clocks before a tick
// (the decision pipeline below; blocks of at least 4 clocks, block_shift >= 2), so a
// tick decides on registered bits; floor(Zx / 2^bs) >= R is Zx >= R << bs for an
// integer R, so one shifter serves both thresholds.  The block end, the refinement's
// quotient bit, the set-up's `known`, the DDA's carry and the crossing (from S - v,
// kept beside S) are formed a clock ahead.
module speed_ramp #(
    parameter integer FEED_W = 16,  // speed word: path units per clock (>= 2)
    parameter integer NW     = 16,  // speed in quanta n (2 .. 64)
    parameter integer PF     = 12,  // fraction bits of the rate p (1 .. 64)
    parameter integer LEN_W  = 34,  // segment length in path units (>= FEED_W)
    parameter integer ZW     = 48   // budget Z0 in quanta^2 * 2^PF (>= 2)
) (
    input  wire              clk,
    input  wire              rst,
    input  wire              next_valid,     // a segment is at the head of the profile queue
    input  wire              next_barrier,   // ... and it is a barrier (dwell / event)
    input  wire [FEED_W-1:0] next_feed,      // its cruise speed v_c
    input  wire [FEED_W-1:0] next_limit,     // its speed ceiling (override > 100 %)
    input  wire [NW-1:0]     next_exit,      // its exit speed in quanta
    input  wire [PF:0]       next_rate,      // its rate p * 2^PF, 1 .. 2^PF
    input  wire [LEN_W-1:0]  next_length,    // its length in path units
    input  wire [ZW-1:0]     next_budget,    // its budget Z0
    output reg               next_pop,       // registered strobe: drop the head at the next edge
    input  wire              barrier_done,   // strobe: a dwell / event has finished
    input  wire [FEED_W-1:0] speed_quantum,  // A (constant while moving)
    input  wire [3:0]        block_shift,    // block = 2^block_shift clocks, >= 2 (constant while moving)
    /* verilator lint_off SYMRSVDWORD */
    input  wire [7:0]        override,       // percent, 1 .. 200 (clamped)
    /* verilator lint_on SYMRSVDWORD */
    input  wire              hold,           // decelerate to 0 and stay
    output reg  [FEED_W-1:0] speed,          // v = n * A, the travel of this clock
    output wire [FEED_W-1:0] cruise,         // the feed of the segment in progress (or the last one)
    output reg               up,             // n rose at the last edge
    output reg               down,           // n fell at the last edge
    output wire              block,          // this clock ends a block
    output wire              moving,         // n != 0 or a segment in progress
    output wire              segment,        // a segment in progress
    output wire              stopped,        // hold and n = 0
    output reg               late            // strobe: a stop or exit reached above its speed
);
    initial begin
        if (FEED_W < 2) $error("%m: FEED_W must be at least 2");
        if (NW < 2 || NW > 64) $error("%m: NW must be 2 .. 64");
        if (PF < 1 || PF > 64) $error("%m: PF must be 1 .. 64");
        if (LEN_W < FEED_W) $error("%m: LEN_W must be at least FEED_W");
        if (ZW < 2) $error("%m: ZW must be at least 2");
    end

    localparam integer QW  = 2 * NW;                      // n (n + 1)
    localparam integer PW  = PF + NW;                     // p n (p <= 1)
    localparam integer NAW = NW + PF;                     // n * acc
    localparam integer RW  = 2 * NW + PF + 3;             // R, signed
    localparam integer ZXW = (ZW > RW ? ZW : RW) + 17;    // Zx, signed (<< block_shift <= 15)
    localparam integer SW  = LEN_W + 2;                   // S, signed
    localparam integer MW  = NW + FEED_W;                 // the refinement's remainder
    localparam [NW-1:0] ONE_N = {{(NW-1){1'b0}}, 1'b1};

    reg  [14:0]     bc;          // clock in the block
    reg  [3:0]      bs_q;        // block_shift
    reg             bend;        // this clock ends a block (bc >= 2^bs_q - 1, formed a clock ahead)
    reg  [PF-1:0]   acc;         // DDA phase
    reg  [NW-1:0]   n;
    reg             zero_speed;  // n == 0 (kept beside n: no reduction of n in the decisions' paths)
    reg  [QW-1:0]   q;           // n (n + 1)
    reg  [PW-1:0]   p;           // rate * n
    reg  [NAW-1:0]  na;          // n * acc
    reg  signed [SW-1:0]  remaining;   // S
    reg  signed [SW-1:0]  gap;         // S - v: S after this clock's travel
    reg             cross_q;     // seg and gap <= 0: this clock crosses the segment's end
    reg  signed [ZXW-1:0] budget_x;    // Zx
    reg             seg;         // a segment in progress
    reg  [PF:0]     rate;
    reg  [FEED_W-1:0] feed, limit;
    reg  [NW-1:0]   exit_cur;    // the segment's exit speed (quanta) and f (f + 1)
    reg  [QW-1:0]   f_sq_cur;
    reg  [FEED_W+7:0] fo;        // feed * override
    reg             fo_valid, fo_ok;
    reg  [7:0]      bar_count;   // finished barriers not yet passed
    reg             hold_q;

    wire        head      = next_valid & ~next_pop;
    wire        move_head = head & ~next_barrier;
    wire        bar_head  = head & next_barrier;
    wire        known;       // the successor's set-up (speed_ramp_setup)
    wire [PW-1:0] p_sh;
    wire [QW-1:0] f_pre;
    wire [FEED_W+7:0] fo_next;
    wire        fn_valid;
    wire        succ      = known;   // (the set-up runs only while a move is at the head)
    wire [NW-1:0] fx_cur  = exit_cur == {NW{1'b0}} ? ONE_N : exit_cur;
    wire [NW-1:0] floor_n = succ ? fx_cur : ONE_N;
    wire [QW-1:0] f_sq    = succ ? f_sq_cur : {{(QW-2){1'b0}}, 2'd2};
    wire        exit_zero = ~succ | (exit_cur == {NW{1'b0}});
    assign moving  = ~zero_speed | seg;
    assign cruise  = feed;
    assign segment = seg;
    assign stopped = hold_q & zero_speed;

    wire [7:0]  ovr = override == 8'd0 ? 8'd1 : override > 8'd200 ? 8'd200 : override;

    // block, DDA, and n * acc after this block
    wire [14:0]   bc_n    = bend ? 15'd0 : bc + 15'd1;
    wire [14:0]   mask_n  = (15'd1 << block_shift) - 15'd1;
    assign block = bend;
    wire [PF:0]   acc_sum = {1'b0, acc} + rate;
    reg           carry_q;    // acc + rate overflows (formed a clock ahead)
    wire          dtick   = bend & carry_q;
    wire [PF-1:0] acc_n   = bend ? acc_sum[PF-1:0] : acc;
    wire [NAW-1:0] na_p   = na + {{(NAW-PW){1'b0}}, p};          // n * acc + n * rate
    wire [NAW-1:0] na_t   = na_p - {n, {PF{1'b0}}};              // ... less n 2^PF at a tick
    wire [NAW-1:0] na1    = bend ? (dtick ? na_t : na_p) : na;

    // the budget after this clock, with the refinement's quotient bit (added last)
    wire [PW:0] gift;            // speed_ramp_refine
    wire signed [ZXW-1:0] zx_base = budget_x - $signed({{(ZXW-PW-1){1'b0}}, p, 1'b0});
    wire signed [ZXW-1:0] zx1 = zx_base + $signed({{(ZXW-PW-1){1'b0}}, gift});

    // q_up, p_up, na_t_up: the companions of n + 1 after a tick (na_t = n acc', acc' the
    // DDA phase after the tick)
    wire [QW-1:0]  q_up  = q + {{(QW-NW-1){1'b0}}, n, 1'b0} + {{(QW-2){1'b0}}, 2'd2};
    wire [PW-1:0]  p_up  = p + {{(PW-PF-1){1'b0}}, rate};
    wire [NAW-1:0] na_t_up = na_t + {{NW{1'b0}}, acc_sum[PF-1:0]};

    // the decision pipeline (speed_ramp_decide): the thresholds and the cap compared over
    // the three clocks before a tick; a tick it has not seen (within 3 clocks of a switch,
    // load or end) keeps n, which costs the new segment at most 2 n of its budget until
    // the next tick (the host keeps EXIT_MARGIN = 4 quanta of margin at every entry)
    wire seen, ok_hold, ok_up, over, room;
    wire [FEED_W:0]   va    = {1'b0, speed} + {1'b0, speed_quantum};

    wire n_many = |n[NW-1:1];   // n >= 2 (a reduction, not a carry chain shared with n - 1)
    reg signed [1:0] step;
    always @* begin
        step = 2'sd0;
        if (dtick) begin
            if (hold) step = zero_speed ? 2'sd0 : -2'sd1;
            else if (!seg) step = 2'sd0;
            else if (zero_speed) step = 2'sd1;
            else if (!seen) step = 2'sd0;
            else if (over && n_many) step = -2'sd1;
            else if (room && ok_up) step = 2'sd1;
            else if (ok_hold) step = 2'sd0;
            else if (n_many) step = -2'sd1;
        end
    end
    wire st_up = step == 2'sd1, st_dn = step == -2'sd1;

    // crossing the end of the segment, switch, load, barrier: S - v is kept in `gap`
    // (formed with S and v at the edge before), so the crossing is a register
    wire crossing = cross_q;
    wire final_q  = crossing & exit_zero;
    wire switch_s = crossing & succ;
    wire end_s    = crossing & ~succ;
    wire load     = ~seg & succ;
    wire bar_pop  = bar_head & ~seg & zero_speed & ((bar_count != 8'd0) | barrier_done);
    wire pop      = switch_s | load | bar_pop;
    wire [NW-1:0] n_d = st_up ? n + ONE_N : st_dn ? n - ONE_N : n;
    wire [NW-1:0] n_less  = n - ONE_N;                         // st_dn only with n >= 1
    // n_d = 0: n = 0 kept, 1 lowered, or all ones raised (wraps)
    wire zero_next = (zero_speed & ~st_up) | (st_dn & ~n_many) | (st_up & (&n));
    wire late_n   = crossing & (exit_zero ? n_many :
                                st_up ? n >= floor_n : st_dn ? n_less > floor_n : n > floor_n);
    wire [MW+SW-1:0] rem_ext = {{MW{1'b0}}, remaining};    // S > 0 at a switch
    // a load carries S = c <= 0: charged as K quanta-clocks, K = 1 if c > -A, else
    // 2^NW - 1, and 2 p' floor((K A + c) / A) given back by the refinement
    wire signed [SW+NW:0] rem_wide = {{(NW+1){remaining[SW-1]}}, remaining};
    wire signed [SW+NW:0] a_wide   = {{(SW+NW+1-FEED_W){1'b0}}, speed_quantum};
    wire signed [SW+NW:0] a_k      = $signed({{(SW+1-FEED_W){1'b0}}, speed_quantum, {NW{1'b0}}}) - a_wide;
    wire signed [SW+NW:0] load_small = rem_wide + a_wide;   // both sums at once, then the choice
    wire signed [SW+NW:0] load_large = rem_wide + a_k;
    wire        carry_small = load_small > 0;
    wire signed [SW+NW:0] load_r = carry_small ? load_small : load_large;
    wire [MW+SW+NW:0] load_r_ext = {{MW{1'b0}}, load_r};
    wire [MW-1:0] ref_load_r  = switch_s ? rem_ext[MW-1:0] : load_r[SW+NW] ? {MW{1'b0}} : load_r_ext[MW-1:0];
    wire signed [ZXW-1:0] budget_next = $signed({{(ZXW-ZW){1'b0}}, next_budget}) <<< bs_q;

    // S and v after this clock, and the next clock's gap and crossing (v = 0 while no
    // segment is in progress, so S + length is gap + length at a load as at a switch)
    wire [FEED_W-1:0] speed_next = final_q ? {FEED_W{1'b0}} : st_up ? va[FEED_W-1:0] :
                                   st_dn ? speed - speed_quantum : speed;
    wire signed [SW-1:0] rem_start = gap + $signed({2'b00, next_length});
    wire signed [SW-1:0] rem_next  = (switch_s | load) ? rem_start : seg ? gap : remaining;
    wire signed [SW-1:0] gap_next  = rem_next - $signed({{(SW-FEED_W){1'b0}}, speed_next});
    wire        seg_next  = (switch_s | load) | (seg & ~end_s);
    wire [PF:0] rate_next = (switch_s | load) ? next_rate : rate;
    wire [PF:0] acc_sum_next = {1'b0, acc_n} + rate_next;

    // the cap's feed * override, recomputed all the time
    wire          mo_busy, mo_done;
    wire [FEED_W+7:0] mo_product;
    speed_ramp_mul #(.AW(FEED_W), .BW(8)) u_mul_fo (
        .clk(clk), .rst(rst), .start(~mo_busy), .a(feed), .b(ovr),
        .busy(mo_busy), .done(mo_done), .product(mo_product));
    speed_ramp_decide #(.FEED_W(FEED_W), .NW(NW), .PF(PF), .ZW(ZW)) u_decide (
        .clk(clk), .rst(rst), .event_now(bend | switch_s | load | end_s), .succ(succ),
        .n(n), .q(q), .f_sq(f_sq), .floor_n(floor_n), .na(na), .acc(acc), .p(p),
        .budget_x(budget_x), .bs(bs_q), .speed(speed), .va(va), .limit(limit), .fo(fo),
        .fo_valid(fo_valid), .valid(seen), .ok_hold(ok_hold), .ok_up(ok_up), .over(over),
        .room(room));
    speed_ramp_setup #(.FEED_W(FEED_W), .NW(NW), .PF(PF)) u_setup (
        .clk(clk), .rst(rst), .pop(pop), .move_head(move_head), .n(n),
        .n_up(st_up & ~final_q), .n_down(st_dn & ~final_q), .n_zero(final_q),
        .next_rate(next_rate), .next_exit(next_exit), .next_feed(next_feed), .ovr(ovr),
        .known(known), .p_sh(p_sh), .f_pre(f_pre), .fo_next(fo_next), .fn_valid(fn_valid));
    // + 2 p' floor(S / A) over the NW clocks after a switch above rest or a load
    speed_ramp_refine #(.FEED_W(FEED_W), .NW(NW), .PF(PF)) u_refine (
        .clk(clk), .rst(rst), .start((switch_s & ~zero_speed) | load), .cancel(crossing),
        .remainder(ref_load_r), .speed_quantum(speed_quantum), .rate(next_rate), .gift(gift));

    always @(posedge clk) begin
        if (rst) begin
            bc <= 15'd0; bs_q <= 4'd0; bend <= 1'b1; acc <= {PF{1'b0}};
            n <= {NW{1'b0}}; zero_speed <= 1'b1; speed <= {FEED_W{1'b0}}; q <= {QW{1'b0}}; p <= {PW{1'b0}}; na <= {NAW{1'b0}};
            remaining <= {SW{1'b0}}; gap <= {SW{1'b0}}; cross_q <= 1'b0; carry_q <= 1'b0; budget_x <= {ZXW{1'b0}};
            seg <= 1'b0; rate <= {(PF+1){1'b0}}; feed <= {FEED_W{1'b0}}; limit <= {FEED_W{1'b0}};
            exit_cur <= {NW{1'b0}}; f_sq_cur <= {QW{1'b0}};
            fo <= {(FEED_W+8){1'b0}}; fo_valid <= 1'b0; fo_ok <= 1'b0; bar_count <= 8'd0;
            up <= 1'b0; down <= 1'b0; next_pop <= 1'b0; late <= 1'b0; hold_q <= 1'b0;
        end else begin
            // speed and its companions
            zero_speed <= final_q | zero_next;
            if (final_q) begin
                n <= {NW{1'b0}}; q <= {QW{1'b0}}; p <= {PW{1'b0}}; na <= {NAW{1'b0}};
            end else begin
                n     <= n_d;
                q     <= st_up ? q_up : st_dn ? q - {{(QW-NW-1){1'b0}}, n, 1'b0} : q;
                na    <= st_up ? na_t_up : st_dn ? na_t - {{NW{1'b0}}, acc_sum[PF-1:0]} : na1;
                if (switch_s)
                    p <= st_up ? p_sh + {{(PW-PF-1){1'b0}}, next_rate} :
                         st_dn ? p_sh - {{(PW-PF-1){1'b0}}, next_rate} : p_sh;
                else if (load)
                    p <= {PW{1'b0}};
                else
                    p <= st_up ? p_up : st_dn ? p - {{(PW-PF-1){1'b0}}, rate} : p;
            end
            speed     <= speed_next;
            remaining <= rem_next;
            gap       <= gap_next;
            cross_q   <= seg_next & (gap_next[SW-1] | (gap_next == {SW{1'b0}}));
            carry_q   <= acc_sum_next[PF];
            up       <= final_q ? 1'b0 : st_up;
            down     <= final_q ? ~zero_speed : st_dn;
            late     <= late_n;
            next_pop <= pop;
            acc      <= acc_n;
            bc       <= bc_n;
            bs_q     <= block_shift;
            bend     <= bc_n >= mask_n;
            hold_q   <= hold;
            bar_count <= bar_count + {7'd0, barrier_done} - {7'd0, bar_pop};
            // the segment
            if (switch_s | load) begin
                rate <= rate_next; feed <= next_feed; limit <= next_limit;
                exit_cur <= next_exit; f_sq_cur <= f_pre;
                budget_x  <= budget_next - (switch_s ? $signed({{(ZXW-PW-1){1'b0}}, p_sh, 1'b0}) :
                                            carry_small ? $signed({{(ZXW-PF-2){1'b0}}, next_rate, 1'b0}) :
                                            $signed({{(ZXW-PW-2){1'b0}}, next_rate, {NW{1'b0}}, 1'b0}) -
                                            $signed({{(ZXW-PF-2){1'b0}}, next_rate, 1'b0}));
                seg <= 1'b1;
            end else if (end_s) begin
                budget_x <= {ZXW{1'b0}}; seg <= 1'b0;
            end else begin
                budget_x <= zx1;
            end
            // feed * override
            if (switch_s | load) begin
                fo <= fo_next; fo_valid <= fn_valid; fo_ok <= 1'b0;
            end else begin
                if (mo_done & fo_ok) begin
                    fo <= mo_product; fo_valid <= 1'b1;
                end
                if (~mo_busy) fo_ok <= 1'b1;
            end
        end
    end

`ifdef FORMAL
    `include "speed_ramp_properties.vh"
`endif

    wire unused = &{1'b0, rem_ext[MW+SW-1:MW], load_r_ext[MW+SW+NW:MW], acc_sum[PF]};   // (carry_q)
endmodule
`default_nettype wire
