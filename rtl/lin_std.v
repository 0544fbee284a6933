// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Standard linear interpolator of the lecture "Linear and circular interpolation
// by the evaluation-function method": one axis per tick.
//   register 1 (+|dX|), register 2 (-|dY|) ... reg1_q, reg2_q
//   multiplexer (AND 1, 2, OR) + accumulating adder (memory F) mux2 u_mux + accum_addsub u_adder
//   logic NOT, AND 3, AND 4 (X / Y pulses) ........... x_pulse, y_pulse
//   counters KOX, KOY and their SR triggers .......... updown_counter u_kox/u_koy, trig_x_q/trig_y_q
//   registers 3, 4 (current coordinates) ............. pos_x, pos_y
// F >= 0: X step, F -= |dY|;  F < 0: Y step, F += |dX|  (F = 0 at the start).
// All four quadrants: the magnitudes drive the algorithm, the signs set dir_x/dir_y.
// An axis whose trigger is reset (its counter reached 0) gives its tick to the
// other axis, so a move along one axis (dX = 0 or dY = 0) cannot stall.
//
// Timing: `start` in an idle cycle loads the counters, registers and F; from the
// next cycle each cycle with `tick` high makes one step, shown on the registered
// step_x/step_y strobes one cycle later; `done` is a one-cycle strobe in the
// cycle after the last step (END: both triggers reset).  X = Y = 0 gives `done`
// with no step.  `start` while busy is ignored; `rst` returns to idle at once.
module lin_std #(
    parameter integer WIDTH = 32    // width of the signed X, Y inputs and of registers 3, 4 (>= 2)
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             start,
    input  wire             tick,
    input  wire [WIDTH-1:0] x,      // signed X increment
    input  wire [WIDTH-1:0] y,      // signed Y increment
    output reg              step_x,
    output reg              step_y,
    output reg              dir_x,  // 1 = negative direction
    output reg              dir_y,
    output wire             busy,
    output reg              done,
    output reg  [WIDTH-1:0] pos_x,  // register 3: X position since reset (wraps modulo 2^WIDTH)
    output reg  [WIDTH-1:0] pos_y   // register 4
);
    initial begin
        if (WIDTH < 2) $error("%m: WIDTH must be at least 2");
    end

    localparam integer CW = WIDTH + 1;  // counters and operands: 0 .. 2^(WIDTH-1), signed
    localparam integer FW = WIDTH + 2;  // F stays within -|dY| .. |dX|

    wire [WIDTH-1:0] abs_x = x[WIDTH-1] ? -x : x;
    wire [WIDTH-1:0] abs_y = y[WIDTH-1] ? -y : y;

    // ---- start / END ----
    wire run, accept, finish;
    reg  trig_x_q, trig_y_q;                 // SR triggers of KOX, KOY
    wire load = start & ~run;
    wire at_end = ~trig_x_q & ~trig_y_q;     // END
    start_stop u_run (
        .clk(clk), .rst(rst), .start(load), .stop(at_end),
        .run(run), .accept(accept), .finish(finish)
    );
    assign busy = run;

    // ---- NOT, AND 3, AND 4 ----
    wire f_negative, f_non_negative;
    wire go = run & tick;
    wire x_pulse = go & trig_x_q & (f_non_negative | ~trig_y_q);
    wire y_pulse = go & trig_y_q & (f_negative | ~trig_x_q);

    // ---- counters KOX, KOY ----
    wire [CW-1:0] kox, koy, kox_n, koy_n;
    updown_counter #(.WIDTH(CW)) u_kox (
        .clk(clk), .rst(rst), .load(load), .load_value({1'b0, abs_x}),
        .inc(1'b0), .dec(x_pulse), .dec2(1'b0), .q(kox), .q_n(kox_n)
    );
    updown_counter #(.WIDTH(CW)) u_koy (
        .clk(clk), .rst(rst), .load(load), .load_value({1'b0, abs_y}),
        .inc(1'b0), .dec(y_pulse), .dec2(1'b0), .q(koy), .q_n(koy_n)
    );
    wire kox_last = kox == {{(CW-1){1'b0}}, 1'b1};
    wire koy_last = koy == {{(CW-1){1'b0}}, 1'b1};

    // ---- registers 1, 2, multiplexer, adder ----
    reg  [CW-1:0] reg1_q, reg2_q;            // +|dX|, -|dY|
    wire [CW-1:0] operand;
    mux2 #(.WIDTH(CW)) u_mux (.sel(y_pulse), .in0(reg2_q), .in1(reg1_q), .out(operand));
    wire [FW-1:0] f;
    accum_addsub #(.WIDTH(FW)) u_adder (
        .clk(clk), .rst(rst), .clear(1'b0), .load(load), .load_value({FW{1'b0}}),
        .add(x_pulse | y_pulse), .operand({operand[CW-1], operand}), .cin(1'b0),
        .f(f), .negative(f_negative), .non_negative(f_non_negative)
    );

    always @(posedge clk) begin
        if (rst) begin
            reg1_q   <= {CW{1'b0}};
            reg2_q   <= {CW{1'b0}};
            trig_x_q <= 1'b0;
            trig_y_q <= 1'b0;
            dir_x    <= 1'b0;
            dir_y    <= 1'b0;
            step_x   <= 1'b0;
            step_y   <= 1'b0;
            done     <= 1'b0;
            pos_x    <= {WIDTH{1'b0}};
            pos_y    <= {WIDTH{1'b0}};
        end else begin
            if (load) begin
                reg1_q   <= {1'b0, abs_x};
                reg2_q   <= -{1'b0, abs_y};
                trig_x_q <= |abs_x;
                trig_y_q <= |abs_y;
                dir_x    <= x[WIDTH-1];
                dir_y    <= y[WIDTH-1];
            end else begin
                if (x_pulse & kox_last) trig_x_q <= 1'b0;
                if (y_pulse & koy_last) trig_y_q <= 1'b0;
            end
            if (x_pulse) pos_x <= dir_x ? pos_x - 1'b1 : pos_x + 1'b1;
            if (y_pulse) pos_y <= dir_y ? pos_y - 1'b1 : pos_y + 1'b1;
            step_x <= x_pulse;
            step_y <= y_pulse;
            done   <= finish;
        end
    end

    // Inverted counter outputs are not needed (the triggers watch for 1); f is for benches and waves.
    wire unused = &{1'b0, accept, kox_n, koy_n, f};
endmodule
`default_nettype wire
