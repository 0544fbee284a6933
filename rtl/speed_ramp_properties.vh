// SPDX-License-Identifier: Apache-2.0
// Properties of speed_ramp for SymbiYosys (formal/speed_ramp.sby), included into the
// module under `ifdef FORMAL: they read its registers by name.
    // (formal/speed_ramp.sby) n moves only at a DDA tick and by one quantum, except
    // the last quantum at the clock a segment ends at rest (from n = 1, else `late`);
    // the registers kept by adders equal their products, those formed a clock ahead
    // their definitions; the successor's set-up too (the harness holds the head until
    // it is popped).
    wire [NW-1:0] n_next = final_q ? {NW{1'b0}} : n_d;
    reg f_past_valid = 1'b0;
    always @(posedge clk) f_past_valid <= 1'b1;
    wire [QW-1:0]  f_q  = {{NW{1'b0}}, n} * ({{NW{1'b0}}, n} + {{(QW-1){1'b0}}, 1'b1});
    wire [PW-1:0]  f_p  = {{(PW-PF-1){1'b0}}, rate} * {{PF{1'b0}}, n};
    wire [NAW-1:0] f_na = {{PF{1'b0}}, n} * {{NW{1'b0}}, acc};
    always @(*) if (f_past_valid && !rst) begin
        if (n_next != n) assert (dtick || final_q);
        if (!late_n) assert (n_next == n || n_next == n + ONE_N || n_next + ONE_N == n);
        if (final_q && !late_n) assert (n <= ONE_N);
        assert (rate <= {1'b1, {PF{1'b0}}});
        if (!seg) assert (n == {NW{1'b0}});
        assert (q == f_q);
        assert (zero_speed == (n == {NW{1'b0}}));
        assert (gap == remaining - $signed({{(SW-FEED_W){1'b0}}, speed}));
        assert (cross_q == (seg && gap <= 0));
        assert (carry_q == acc_sum[PF]);
        if (known) assert (move_head);
        if (!seg) assert (speed == {FEED_W{1'b0}});
        assert (bend == (bc >= (15'd1 << bs_q) - 15'd1));
        assert (p == f_p);
        assert (na == f_na);
    end
`ifndef INVARIANTS_ONLY
    // the pipeline is sound: at a tick it decides on, each comparison it passes holds for
    // the budget and the thresholds of the tick itself (braking_need at the phase the
    // tick leaves), and its floor is no higher than the tick's
    wire signed [RW-1:0] f_r_hold = ($signed({{(RW-QW){1'b0}}, q} - {{(RW-QW){1'b0}}, f_sq}) <<< PF)
        + $signed({{(RW-PW-1){1'b0}}, p, 1'b0}) - $signed({{(RW-NAW-1){1'b0}}, na_t, 1'b0});
    wire signed [RW-1:0] f_r_up = ($signed({{(RW-QW){1'b0}}, q_up} - {{(RW-QW){1'b0}}, f_sq}) <<< PF)
        + $signed({{(RW-PW-1){1'b0}}, p_up, 1'b0}) - $signed({{(RW-NAW-1){1'b0}}, na_t_up, 1'b0});
    wire signed [ZXW-1:0] f_zx = zx1 >>> bs_q;
    always @(*) if (f_past_valid && !rst && dtick && seen && seg && n != {NW{1'b0}}) begin
        if (ok_hold && n > floor_n) assert (f_zx >= $signed({{(ZXW-RW){f_r_hold[RW-1]}}, f_r_hold}));
        if (ok_up && ~&n && n + ONE_N > floor_n)
            assert (f_zx >= $signed({{(ZXW-RW){f_r_up[RW-1]}}, f_r_up}));
    end
    // (formal/speed_ramp.sby's cover task: the pipeline decides every way on its budget)
    always @(*) if (f_past_valid && !rst && dtick && seen && seg && !hold) begin
        cover (n > floor_n && !over && st_up);                 // raised on the budget
        cover (n > floor_n && !over && step == 2'sd0);         // kept on the budget
        cover (n > floor_n && !over && st_dn);                 // lowered: the budget fell short
    end
`endif
