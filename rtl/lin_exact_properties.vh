// SPDX-License-Identifier: Apache-2.0
// Properties of lin_exact for SymbiYosys (formal/lin_exact.sby), included into the module
// under `ifdef FORMAL: they read its registers by name.
    // Properties for SymbiYosys (formal/lin_exact.sby).  After a start the
    // core emits exactly |X| steps on X and |Y| on Y, then `done`; no step
    // while idle; every step is caused by a tick.  The invariants tie the
    // counters, F and the look-ahead registers to the steps already emitted,
    // so k-induction closes.
    reg f_past_valid = 1'b0;
    always @(posedge clk) f_past_valid <= 1'b1;
    always @(*) if (!f_past_valid) assume (rst);

    reg  [CW-1:0] f_len_x, f_len_y, f_cnt_x, f_cnt_y;  // |X|, |Y| of the move; steps seen
    wire [WIDTH-1:0] abs_x = x[WIDTH-1] ? -x : x;
    wire [WIDTH-1:0] abs_y = y[WIDTH-1] ? -y : y;
    always @(posedge clk) begin
        if (rst) begin
            f_len_x <= {CW{1'b0}}; f_len_y <= {CW{1'b0}};
            f_cnt_x <= {CW{1'b0}}; f_cnt_y <= {CW{1'b0}};
        end else if (load) begin
            f_len_x <= {1'b0, abs_x}; f_len_y <= {1'b0, abs_y};
            f_cnt_x <= {CW{1'b0}};    f_cnt_y <= {CW{1'b0}};
        end else begin
            f_cnt_x <= f_cnt_x + {{(CW-1){1'b0}}, step_x};
            f_cnt_y <= f_cnt_y + {{(CW-1){1'b0}}, step_y};
        end
    end
    // Steps taken so far, counting the strobes on the outputs right now.
    wire [CW-1:0] f_done_x = f_cnt_x + {{(CW-1){1'b0}}, step_x};
    wire [CW-1:0] f_done_y = f_cnt_y + {{(CW-1){1'b0}}, step_y};
    wire [CW-1:0] f_l = x_is_long_q ? f_len_x : f_len_y;
    wire [CW-1:0] f_s = x_is_long_q ? f_len_y : f_len_x;
    wire [CW-1:0] f_diag = x_is_long_q ? f_done_y : f_done_x;    // diagonal steps
    wire [CW-1:0] f_axial = (x_is_long_q ? f_done_x : f_done_y) - f_diag;
    // Expression (1) in closed form, wide enough not to wrap:
    // 2F = L - 2S - 2aS + 2d(L - S) for a axial and d diagonal steps.
    localparam integer PW = 2 * CW + 4;
    wire [PW-1:0] f_l_w = {{(PW-CW){1'b0}}, f_l};
    wire [PW-1:0] f_s_w = {{(PW-CW){1'b0}}, f_s};
    wire [PW-1:0] f_expect = f_l_w - 2 * f_s_w - 2 * {{(PW-CW){1'b0}}, f_axial} * f_s_w
                           + 2 * {{(PW-CW){1'b0}}, f_diag} * (f_l_w - f_s_w);
    wire [FW-1:0] f_op = negative_q ? d2 : a2;
    always @(posedge clk) if (f_past_valid && !rst && !$past(rst)) begin
        // the step count: never beyond |X|, |Y|; exactly |X|, |Y| at done
        assert (f_cnt_x <= f_len_x && f_cnt_y <= f_len_y);
        assert (f_len_x <= {2'b01, {(CW-2){1'b0}}} && f_len_y <= {2'b01, {(CW-2){1'b0}}});
        if (done) assert (f_cnt_x == f_len_x && f_cnt_y == f_len_y);
        // no step while idle, so none after done; a step needs a tick
        if (step_x || step_y) assert (busy && $past(tick));
        if (!busy) assert (ctr1 == {CW{1'b0}} && ctr2 == {CW{1'b0}} && f == {FW{1'b0}}
                           && !x_is_long_q && !step_x && !step_y);
        // invariants of a move
        assert (!(frame_q && run));
        if (busy) assert (x_is_long_q == (f_len_x >= f_len_y) && f_s <= f_l);
        if (frame_q) assert (ctr1 == f_l - f_s && ctr2 == f_s && !step_x && !step_y
                             && f == {1'b0, f_l} - {f_s, 1'b0});
        if (run) assert (ctr1 == f_l - f_s - f_axial && ctr2 == f_s - f_diag - 1'b1
                         && f_diag <= f_s && f_axial <= f_l - f_s);
        // AND 9 and the run enable, formed a cycle ahead from the steps left
        if (busy) assert (left2 == left1 - 1'b1 && left_op_hi1 == left_op[CW-1:CLO] + 1'b1);
        if (frame_q) assert (left1 == {CW{1'b0}} && left_op == ctr1 + ctr2 - 1'b1);
        if (run) assert (left1 == ctr1 + ctr2 && &left_op);
        assert (busy_q == (frame_q | run) && finish == at_end_q
                && at_end_q == (run && ctr1 == {CW{1'b0}} && &ctr2)
                && active_q == (run && !(ctr1 == {CW{1'b0}} && &ctr2)));
        // F by expression (1); the midpoint bounds -2S <= 2F < 2(L - S) (or L = 0)
        if (run)
            assert ({{(PW-FW){f[FW-1]}}, f} == f_expect && diagonal_q == f_l - f_s && axial_q == -f_s
                    && $signed(f) >= -$signed({1'b0, f_s, 1'b0})
                    && ($signed(f) < $signed({1'b0, f_l - f_s, 1'b0}) || f_l == {CW{1'b0}}));
        // the retimed decision: look-ahead sums, operands and sign
        if (busy) begin
            assert (axial_hi1_q == a2[FW-1:LO] + 1'b1 && diagonal_hi1_q == d2[FW-1:LO] + 1'b1
                    && negative_q == f[FW-1]);
            if (frame_q)
                assert (f_axial_q == {FW{1'b0}} && f_diagonal_q == {FW{1'b0}}
                        && op_axial_q == f + a2 && op_diagonal_q == f + d2);
            else
                assert (f_axial_q == f + a2 && f_diagonal_q == f + d2
                        && op_axial_q == f_op && op_diagonal_q == f_op);
            assert (op_axial_hi1_q == op_axial_q[FW-1:LO] + 1'b1
                    && op_diagonal_hi1_q == op_diagonal_q[FW-1:LO] + 1'b1);
        end
    end
