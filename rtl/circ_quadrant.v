// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// First-quadrant circular interpolator of the lecture, standard (ACCEL = 0, the
// CLI's circ-std) and accelerated (ACCEL = 1, circ-accel).  F = x^2 + y^2 - R^2, F = 0 at
// the start point (R^2 = X_H^2 + Y_H^2), clockwise or counter-clockwise.
//   registers 1, 2 (-2X_H and 2Y_H for CCW, moving by 2) .. counters u_reg1, u_reg2
//       holding -X, Y (CCW) or X, -Y (CW); the adder sees them shifted one bit left
//   accumulating adder, carry-in adds the 1 ............ accum_addsub u_adder (cin = 1)
//   step counters KOX, KOY and their SR triggers ....... u_kox, u_koy, trig_x_q, trig_y_q
// The axis that moves the point inwards ("in": X for CCW, Y for CW) and the one
// that moves it outwards ("out": Y for CCW, X for CW):
//   standard:    F >= 0: in step,  F += 2*in_half + 1;   F < 0: out step, F += 2*out_half + 1
//   accelerated: octant in > out (out leads): F >= 0 diagonal, F < 0 out step;
//                octant in <= out (in leads): F >= 0 in step,  F < 0 diagonal;
//                diagonal: F += 2*in_half + 2*out_half + 2
// (the halves are the registers' contents before the step).  An axis whose counter
// reached 0 gives its tick to the other axis, so the move always ends at the end
// point; END when both triggers are reset.
//
// Set-up without combinational multipliers (circle_setup, as in circ_arc): four
// seq_mult instances square x0, y0, x1, y1 (a = R^2, b = |End|^2, d = b - a), then
// one forms m^2 with m = |d|; the end point is within half a step of the circle
// (the half-step test) <=> d = 0 or m^2 <= min(a, b) + (m - 1) div 2.  Sums
// (2*WIDTH + 2 bits) take two cycles, as two chunks with a registered carry.
//
// Timing: `start` in an idle cycle captures the command (cycle 0); the set-up
// checks it in cycle 2*WIDTH + 17; from the next cycle one step per `tick` as
// lin_std.  A bad
// command (a coordinate negative, start at the origin, end not reachable in the
// chosen direction inside the quadrant, end more than half a step off the circle)
// gives a one-cycle `error` strobe instead of `done`, with no step.
module circ_quadrant #(
    parameter integer WIDTH = 32,   // width of the signed coordinate inputs (>= 3)
    parameter integer ACCEL = 0     // 0: standard (one axis per tick), 1: accelerated (octants)
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             start,
    input  wire             tick,
    input  wire [WIDTH-1:0] x0,     // start point (signed, must be >= 0)
    input  wire [WIDTH-1:0] y0,
    input  wire [WIDTH-1:0] x1,     // end point
    input  wire [WIDTH-1:0] y1,
    input  wire             ccw,    // 1 = counter-clockwise
    output reg              step_x,
    output reg              step_y,
    output reg              dir_x,  // 1 = negative direction
    output reg              dir_y,
    output wire             busy,
    output reg              done,
    output reg              error   // one-cycle strobe instead of `done` for a bad command
);
    initial begin
        if (WIDTH < 3) $error("%m: WIDTH must be at least 3");
        if (ACCEL != 0 && ACCEL != 1) $error("%m: ACCEL must be 0 or 1");
    end

    localparam integer HW = WIDTH + 1;      // halves and counters: |value| < 2^(WIDTH-1), signed
    localparam integer FW = 2 * WIDTH + 1;  // F: |x^2 + y^2 - R^2| < 2^(2*WIDTH-1), signed
    localparam integer MW = WIDTH + 1;      // seq_mult operands (m < 2^WIDTH where it matters)
    localparam integer SW = 2 * MW;         // set-up sums: a, b < 2^(2*WIDTH-1), m^2 < 2^(2*WIDTH)
    localparam [1:0] IDLE = 2'd0, SETUP = 2'd1, RUN = 2'd2;   // SETUP ends with circle_setup's check

    reg  [1:0]       state_q;
    reg  [WIDTH-1:0] x0_q, y0_q, x1_q, y1_q;
    reg              ccw_q;
    reg              trig_x_q, trig_y_q;
    reg              form_bad_q;            // a coordinate negative, start at the origin, wrong way

    wire load = start & (state_q == IDLE);
    assign busy = state_q != IDLE;

    // ---- set-up: R^2, |End|^2, band test ----
    wire          check, on_band, setup_busy;
    circle_setup #(.MW(MW), .SW(SW)) u_setup (
        .clk(clk), .rst(rst), .start(load),
        .x0({1'b0, x0_q}), .y0({1'b0, y0_q}), .x1({1'b0, x1_q}), .y1({1'b0, y1_q}),
        .busy(setup_busy), .check(check), .on_band(on_band)
    );

    // ---- command check (CHECK cycle) ----
    wire negative = x0_q[WIDTH-1] | y0_q[WIDTH-1] | x1_q[WIDTH-1] | y1_q[WIDTH-1];
    wire wrong_way = ccw_q ? ($signed(x1_q) > $signed(x0_q) || $signed(y1_q) < $signed(y0_q))
                           : ($signed(x1_q) < $signed(x0_q) || $signed(y1_q) > $signed(y0_q));
    wire at_origin = x0_q == {WIDTH{1'b0}} && y0_q == {WIDTH{1'b0}};
    wire bad = form_bad_q || !on_band;      // the command's own flags settle during the set-up
    wire begin_run = check && !bad;
    wire [HW-1:0] sx0 = {x0_q[WIDTH-1], x0_q}, sy0 = {y0_q[WIDTH-1], y0_q};
    wire [HW-1:0] sx1 = {x1_q[WIDTH-1], x1_q}, sy1 = {y1_q[WIDTH-1], y1_q};
    wire [HW-1:0] count_x = ccw_q ? sx0 - sx1 : sx1 - sx0;
    wire [HW-1:0] count_y = ccw_q ? sy1 - sy0 : sy0 - sy1;

    // ---- registers 1, 2 (halves), counters ----
    wire [HW-1:0] half1, half2, half1_n, half2_n, kox, koy, kox_n, koy_n;
    wire act_x, act_y;
    updown_counter #(.WIDTH(HW)) u_reg1 (
        .clk(clk), .rst(rst), .load(begin_run), .load_value(ccw_q ? -sx0 : sx0),
        .inc(act_x), .dec(1'b0), .dec2(1'b0), .q(half1), .q_n(half1_n)
    );
    updown_counter #(.WIDTH(HW)) u_reg2 (
        .clk(clk), .rst(rst), .load(begin_run), .load_value(ccw_q ? sy0 : -sy0),
        .inc(act_y), .dec(1'b0), .dec2(1'b0), .q(half2), .q_n(half2_n)
    );
    updown_counter #(.WIDTH(HW)) u_kox (
        .clk(clk), .rst(rst), .load(begin_run), .load_value(count_x),
        .inc(1'b0), .dec(act_x), .dec2(1'b0), .q(kox), .q_n(kox_n)
    );
    updown_counter #(.WIDTH(HW)) u_koy (
        .clk(clk), .rst(rst), .load(begin_run), .load_value(count_y),
        .inc(1'b0), .dec(act_y), .dec2(1'b0), .q(koy), .q_n(koy_n)
    );
    wire [HW-1:0] one = {{(HW-1){1'b0}}, 1'b1};

    // ---- step choice: in/out axes, octant, triggers ----
    wire f_negative, f_non_negative;
    wire running = state_q == RUN;
    wire at_end = running & ~trig_x_q & ~trig_y_q;                  // END
    wire go = running & tick;
    wire [HW-1:0] half_in  = ccw_q ? half1 : half2;
    wire [HW-1:0] half_out = ccw_q ? half2 : half1;
    wire trig_in  = ccw_q ? trig_x_q : trig_y_q;
    wire trig_out = ccw_q ? trig_y_q : trig_x_q;
    wire [HW-1:0] half_sum = half_in + half_out;                    // out - in
    wire want_in, want_out;
    generate
        if (ACCEL != 0) begin : g_accel
            wire out_leads = half_sum[HW-1];                        // in > out
            assign want_in  = out_leads ? f_non_negative : 1'b1;
            assign want_out = out_leads ? 1'b1 : f_negative;
        end else begin : g_standard
            assign want_in  = f_non_negative;
            assign want_out = f_negative;
        end
    endgenerate
    wire act_in  = go & trig_in  & (want_in  | ~trig_out);
    wire act_out = go & trig_out & (want_out | ~trig_in);
    assign act_x = ccw_q ? act_in : act_out;
    assign act_y = ccw_q ? act_out : act_in;

    // ---- adder: F += 2*operand + 1 (the 1 through the carry-in) ----
    wire [HW-1:0] operand = act_in & act_out ? half_sum : act_in ? half_in : half_out;
    wire          diagonal = act_in & act_out;
    wire [FW-1:0] f;
    accum_addsub #(.WIDTH(FW)) u_adder (
        .clk(clk), .rst(rst), .clear(1'b0), .load(begin_run), .load_value({FW{1'b0}}),
        .add(act_in | act_out), .operand({{(FW-HW-1){operand[HW-1]}}, operand, diagonal}), .cin(1'b1),
        .f(f), .negative(f_negative), .non_negative(f_non_negative)
    );

    always @(posedge clk) begin
        if (rst) begin
            state_q  <= IDLE;
            x0_q     <= {WIDTH{1'b0}};
            y0_q     <= {WIDTH{1'b0}};
            x1_q     <= {WIDTH{1'b0}};
            y1_q     <= {WIDTH{1'b0}};
            ccw_q    <= 1'b0;
            trig_x_q <= 1'b0;
            trig_y_q <= 1'b0;
            form_bad_q <= 1'b0;
            dir_x    <= 1'b0;
            dir_y    <= 1'b0;
            step_x   <= 1'b0;
            step_y   <= 1'b0;
            done     <= 1'b0;
            error    <= 1'b0;
        end else begin
            case (state_q)
                IDLE: if (load) begin
                    x0_q    <= x0;
                    y0_q    <= y0;
                    x1_q    <= x1;
                    y1_q    <= y1;
                    ccw_q   <= ccw;
                    state_q <= SETUP;
                end
                SETUP: if (check) begin
                    state_q  <= bad ? IDLE : RUN;
                    trig_x_q <= !bad && count_x != {HW{1'b0}};
                    trig_y_q <= !bad && count_y != {HW{1'b0}};
                    dir_x    <= ccw_q;
                    dir_y    <= ~ccw_q;
                end
                RUN: begin
                    if (act_x && kox == one) trig_x_q <= 1'b0;
                    if (act_y && koy == one) trig_y_q <= 1'b0;
                    if (at_end) state_q <= IDLE;
                end
                default: state_q <= IDLE;
            endcase
            form_bad_q <= negative || at_origin || wrong_way;
            step_x <= act_x;
            step_y <= act_y;
            done   <= at_end;
            error  <= check && bad;
        end
    end

    // Inverted counter outputs and the set-up's busy flag are not used; f is for
    // benches and waves.
    wire unused = &{1'b0, half1_n, half2_n, kox_n, koy_n, f, setup_busy};
endmodule
`default_nettype wire
