// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Accelerated linear interpolator of the lecture: a leading
// axis steps on every tick, the other one joins it (a diagonal step) when F < 0.
//   register 1 (|L| - |S|), register 2 (-|S|) ........ reg1_q, reg2_q
//   multiplexer (AND 1, 2, OR) + accumulating adder .. mux2 u_mux + accum_addsub u_adder
//   AND 3 (every tick), AND 4 (F < 0), AND 5, NOT .... sign_analysis u_sign
//   counter KOX of the leading axis + SR trigger ..... updown_counter u_kol, start_stop u_run
//   routing of leading/other pulses to X/Y ........... increment_former u_route
//   |L|, |S| and |L| - |S| from dX, dY ................ axis_order u_order
// F >= 0: axial step, F -= |S|;  F < 0: diagonal step, F += |L| - |S|, with
// L the leading (longer) increment and S the other one; "mirrored when dY > dX"
// (the lecture) is done by routing, as in SU 1571551's trigger 15.  F starts at 0
// (the lecture), except for |dX| = |dY|, where it starts at -1: the lecture's
// F = 0 with "F >= 0: axial" would end one step short of a 45-degree line.
//
// Timing as lin_std: `start` loads; from the next cycle one step per `tick`,
// on the registered strobes one cycle later; `done` one cycle after the last step.
module lin_accel #(
    parameter integer WIDTH = 32    // width of the signed X, Y inputs (>= 2)
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
    output reg              done
);
    initial begin
        if (WIDTH < 2) $error("%m: WIDTH must be at least 2");
    end

    localparam integer CW = WIDTH + 1;  // counter and operands: 0 .. 2^(WIDTH-1), signed
    localparam integer FW = WIDTH + 2;  // F stays within -|S| .. |L| - |S|

    wire             x_leads;
    wire [CW-1:0]    long_len, short_len, difference;
    axis_order #(.WIDTH(WIDTH)) u_order (
        .x(x), .y(y), .x_is_long(x_leads), .long_len(long_len), .short_len(short_len),
        .difference(difference)
    );
    wire             equal = long_len == short_len;
    wire [FW-1:0]    f_initial = {FW{equal & |long_len}};      // -1 or 0

    // ---- SR trigger: set by START, reset when KOX reaches 0 (END) ----
    wire run, accept, finish;
    wire load = start & ~run;
    wire [CW-1:0] kol, kol_n;
    wire at_end = &kol_n;                                      // KOX = 0
    start_stop u_run (
        .clk(clk), .rst(rst), .start(load), .stop(at_end),
        .run(run), .accept(accept), .finish(finish)
    );
    assign busy = run;

    // ---- AND 3 / AND 4 by the sign of F ----
    wire f_negative, f_non_negative, axial, diagonal;
    sign_analysis u_sign (
        .tick(tick), .enable(run & ~at_end), .negative(f_negative),
        .pulse_pos(axial), .pulse_neg(diagonal)
    );

    updown_counter #(.WIDTH(CW)) u_kol (
        .clk(clk), .rst(rst), .load(load), .load_value(long_len),
        .inc(1'b0), .dec(axial | diagonal), .dec2(1'b0), .q(kol), .q_n(kol_n)
    );

    // ---- registers 1, 2, multiplexer, adder ----
    reg  [CW-1:0] reg1_q, reg2_q;
    reg           x_leads_q;
    wire [CW-1:0] operand;
    mux2 #(.WIDTH(CW)) u_mux (.sel(diagonal), .in0(reg2_q), .in1(reg1_q), .out(operand));
    wire [FW-1:0] f;
    accum_addsub #(.WIDTH(FW)) u_adder (
        .clk(clk), .rst(rst), .clear(1'b0), .load(load), .load_value(f_initial),
        .add(axial | diagonal), .operand({operand[CW-1], operand}), .cin(1'b0),
        .f(f), .negative(f_negative), .non_negative(f_non_negative)
    );

    wire inc_x, inc_y;
    increment_former u_route (
        .axial(axial), .diagonal(diagonal), .x_is_long(x_leads_q),
        .inc_x(inc_x), .inc_y(inc_y)
    );

    always @(posedge clk) begin
        if (rst) begin
            reg1_q    <= {CW{1'b0}};
            reg2_q    <= {CW{1'b0}};
            x_leads_q <= 1'b0;
            dir_x     <= 1'b0;
            dir_y     <= 1'b0;
            step_x    <= 1'b0;
            step_y    <= 1'b0;
            done      <= 1'b0;
        end else begin
            if (load) begin
                reg1_q    <= difference;
                reg2_q    <= -short_len;
                x_leads_q <= x_leads;
                dir_x     <= x[WIDTH-1];
                dir_y     <= y[WIDTH-1];
            end
            step_x <= inc_x;
            step_y <= inc_y;
            done   <= finish;
        end
    end

    // kol is watched through kol_n; f is for benches and waves.
    wire unused = &{1'b0, accept, f_non_negative, kol, f};
endmodule
`default_nettype wire
