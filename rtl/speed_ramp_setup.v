// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Look-ahead set-up of the speed-setting block ("БЗС" of the lecture): re-expresses
// the profile generator's state for the segment at the head of the queue while the
// current one runs, with shift-and-add multipliers only (speed_ramp_mul):
//   p_sh  = next_rate * n_sh, started with n_sh = n (NW clocks), then following n after
//           every edge by up to two steps of +- next_rate a clock (n moves by one at
//           most, or to 0), so it is next_rate * n once `known`; the distance n - n_sh is
//           formed from registers, n's move of this edge (n_up, n_down, n_zero) only
//           selects among the candidates;
//   f_pre = f (f + 1), f = max(next_exit, 1) (NW clocks);
//   fo_next = next_feed * override (8 clocks, recomputed all the time), `fn_valid`
//           once a product of this head is in.
// `pop` (the head is taken at this edge) restarts everything for the next head.
module speed_ramp_setup #(
    parameter integer FEED_W = 16,  // speed word (>= 1)
    parameter integer NW     = 16,  // speed in quanta n (2 .. 64)
    parameter integer PF     = 12   // fraction bits of the rate (1 .. 64)
) (
    input  wire                  clk,
    input  wire                  rst,
    input  wire                  pop,        // the head is taken at this edge
    input  wire                  move_head,  // a move (not a barrier) is at the head
    input  wire [NW-1:0]         n,          // the generator's speed now
    input  wire                  n_up,       // ... and at this edge: n + 1
    input  wire                  n_down,     //                       n - 1
    input  wire                  n_zero,     //                       0
    input  wire [PF:0]           next_rate,
    input  wire [NW-1:0]         next_exit,
    input  wire [FEED_W-1:0]     next_feed,
    input  wire [7:0]            ovr,        // override, clamped
    output wire                  known,      // p_sh = next_rate * n, f_pre valid
    output reg  [PF+NW-1:0]      p_sh,
    output reg  [2*NW-1:0]       f_pre,
    output reg  [FEED_W+7:0]     fo_next,
    output reg                   fn_valid
);
    initial begin
        if (FEED_W < 1) $error("%m: FEED_W must be at least 1");
        if (NW < 2 || NW > 64) $error("%m: NW must be 2 .. 64");
        if (PF < 1 || PF > 64) $error("%m: PF must be 1 .. 64");
    end

    localparam integer PW = PF + NW;
    localparam integer QW = 2 * NW;
    localparam [1:0] IDLE = 2'd0, BUSY = 2'd1, DONE = 2'd2;
    localparam [NW-1:0] ONE_N = {{(NW-1){1'b0}}, 1'b1};

    reg  [1:0]    pre;
    reg  [NW-1:0] n_sh;          // the n that p_sh belongs to
    reg           fn_ok;         // the running feed * override is this head's
    reg           same;          // n_sh == n (formed a clock ahead)
    assign known = (pre == DONE) & same;

    wire [NW-1:0] fx = next_exit == {NW{1'b0}} ? ONE_N : next_exit;
    wire          mp_busy, mp_done, mf_busy, mf_done, mn_busy, mn_done;
    wire [PW:0]   mp_product;
    wire [QW:0]   mf_product;
    wire [FEED_W+7:0] mn_product;
    wire pre_start = (pre == IDLE) & move_head & ~pop & ~mp_busy;
    speed_ramp_mul #(.AW(PF + 1), .BW(NW)) u_mul_p (
        .clk(clk), .rst(rst), .start(pre_start), .a(next_rate), .b(n),
        .busy(mp_busy), .done(mp_done), .product(mp_product));
    speed_ramp_mul #(.AW(NW + 1), .BW(NW)) u_mul_f (
        .clk(clk), .rst(rst), .start(pre_start), .a({1'b0, fx} + 1'b1), .b(fx),
        .busy(mf_busy), .done(mf_done), .product(mf_product));
    speed_ramp_mul #(.AW(FEED_W), .BW(8)) u_mul_fn (
        .clk(clk), .rst(rst), .start(~mn_busy), .a(next_feed), .b(ovr),
        .busy(mn_busy), .done(mn_done), .product(mn_product));

    // gap = n after this edge - n_sh, clamped to -2 .. 2: n - n_sh clamped to -4 .. 4
    // first (n moves by one at most, or to 0), so that |moved| > 2 whenever the true
    // distance after the edge is
    wire [NW:0] apart_full = {1'b0, n} - {1'b0, n_sh};
    wire signed [3:0] apart = $signed(apart_full) > 4 ? 4'sd4 : $signed(apart_full) < -4 ? -4'sd4 : apart_full[3:0];
    wire signed [3:0] moved = apart + (n_up ? 4'sd1 : 4'sd0) - (n_down ? 4'sd1 : 4'sd0);
    wire signed [2:0] to_zero = n_sh > ONE_N ? -3'sd2 : n_sh == ONE_N ? -3'sd1 : 3'sd0;
    wire          far = n_zero ? n_sh > ONE_N + ONE_N : (moved > 4'sd2) | (moved < -4'sd2);
    wire signed [2:0] gap = n_zero ? to_zero : moved > 4'sd2 ? 3'sd2 : moved < -4'sd2 ? -3'sd2 : moved[2:0];
    // n_sh == n after this edge, for each way n_sh moves
    wire          stays  = n_zero ? n_sh == {NW{1'b0}} : moved == 4'sd0;  // n_sh kept
    wire          still  = n_zero ? n == {NW{1'b0}} : ~n_up & ~n_down;    // n_sh <= n
    wire [PW-1:0] rate1 = {{(PW-PF-1){1'b0}}, next_rate};
    wire [PW-1:0] rate2 = {{(PW-PF-2){1'b0}}, next_rate, 1'b0};

    always @(posedge clk) begin
        if (rst) begin
            pre <= IDLE; n_sh <= {NW{1'b0}}; same <= 1'b1; p_sh <= {PW{1'b0}}; f_pre <= {QW{1'b0}};
            fo_next <= {(FEED_W+8){1'b0}}; fn_valid <= 1'b0; fn_ok <= 1'b0;
        end else begin
            same <= pop ? stays : pre_start ? still : pre == DONE ? ~far : stays;
            if (pop) pre <= IDLE;
            else if (pre_start) begin
                pre <= BUSY; n_sh <= n;
            end else if (pre == BUSY && mp_done) begin
                pre <= DONE; p_sh <= mp_product[PW-1:0]; f_pre <= mf_product[QW-1:0];
            end else if (pre == DONE) begin
                n_sh <= n_sh + {{(NW-2){gap[2]}}, gap[1:0]};
                p_sh <= gap == 3'sd2 ? p_sh + rate2 : gap == 3'sd1 ? p_sh + rate1 :
                        gap == -3'sd1 ? p_sh - rate1 : gap == -3'sd2 ? p_sh - rate2 : p_sh;
            end
            if (pop) begin
                fn_valid <= 1'b0; fn_ok <= 1'b0;
            end else begin
                if (mn_done & fn_ok) begin
                    fo_next <= mn_product; fn_valid <= 1'b1;
                end
                if (~mn_busy) fn_ok <= move_head;
            end
        end
    end

`ifdef FORMAL
    // (formal/speed_ramp.sby, the harness holds the head until it is popped)
    wire [PW-1:0] f_ps = rate1 * {{PF{1'b0}}, n_sh};
    always @(*) if (!rst) begin
        if (pre != IDLE) assert (move_head);
        if (pre == DONE) assert (p_sh == f_ps);
        assert (same == (n_sh == n));
    end
`endif

    wire unused = &{1'b0, mf_busy, mf_done, mp_product[PW], mf_product[QW], apart_full[NW:4]};
endmodule
`default_nettype wire
