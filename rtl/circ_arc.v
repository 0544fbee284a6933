// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Production arc interpolator: any start point to any end point on a circle about
// an integer centre, clockwise or counter-clockwise, across quadrant and octant
// boundaries (a full circle included), one step per tick, diagonal steps allowed.
// Built on the lecture's accelerated circular algorithm (a leading axis per octant,
// F = x^2 + y^2 - R^2 = 0 at the start point) with the midpoint choice of the patent
// SU 1665343 generalised to all eight octants:
//   E = u^2 + v^2 - R^2 at the current point (u, v) = (x - cx, y - cy);
//   leading (major) step a and minor step b from the tangent's octant;
//   midpoint M = P + a + b/2:  F(M) < 0  <=>  T = E + 2 P.a + P.b + 1 < 0;
//   F(M) < 0 (M inside): take the outer of the axial (P + a) and diagonal
//   (P + a + b) candidates, else the inner one.
// End: when the next point would reach or pass the ray from the centre through the
// end point (cross(P, End) changes sign with dot(P, End) > 0), the last step goes
// to the end point itself.  R^2 = |start - centre|^2 (an integer; R need not be one).
//
//   set-up: R^2, |End|^2 and the half-step band test ......... circle_setup (shared
//           with circ_quadrant; sequential multipliers, no combinational one)
//   run:    the steps, in octant-local counters, with the end test from tables
//           of the command ......................................... arc_stepper
//   (the adders' family forms, rtl/ecp5/ and rtl/ice40/, are picked by the synthesis
//   file list: mux_add in the loop, chain_add off it)
//
// Timing: `start` in an idle cycle captures the command (cycle 0); the set-up checks
// it in cycle 2*WIDTH + 17; the stepper loads its loop in the next four cycles; from
// cycle 2*WIDTH + 22 one step per `tick`, its strobes and dir levels registered
// together a cycle later (the first in cycle 2*WIDTH + 23), except that the six cycles
// after a step into a new octant reload the stepper (at most 9 octants per arc) and
// take no step (`tick` is an enable).  `done` one cycle after the last step's
// strobes.  Bad
// command (error strobe instead of done, no steps): start = centre (R = 0); end
// point more than half a step off the circle; a start or end coordinate relative
// to the centre outside -2^(WIDTH-3) < u < 2^(WIDTH-3) (radius limit of the
// internal widths).  End = start: a full circle when `full`, else `done` with no
// step.  `start` while busy is ignored; `rst` returns to idle at once.  While idle the
// command's registers follow the inputs (the stepper shows the start point as its
// position); `start` keeps the command of its cycle.
module circ_arc #(
    parameter integer WIDTH = 32    // width of the signed absolute coordinates (>= 6)
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             start,
    input  wire             tick,
    input  wire [WIDTH-1:0] cx,     // centre (signed)
    input  wire [WIDTH-1:0] cy,
    input  wire [WIDTH-1:0] x0,     // start point
    input  wire [WIDTH-1:0] y0,
    input  wire [WIDTH-1:0] x1,     // end point
    input  wire [WIDTH-1:0] y1,
    input  wire             ccw,    // 1 = counter-clockwise
    input  wire             full,   // with end == start: a full circle
    output wire             step_x,
    output wire             step_y,
    output wire             dir_x,  // 1 = negative direction
    output wire             dir_y,
    output wire             busy,
    output reg              done,
    output reg              error   // one-cycle strobe instead of `done` for a bad command
);
    initial begin
        if (WIDTH < 6) $error("%m: WIDTH must be at least 6");
    end

    localparam integer UW = WIDTH + 1;      // relative coordinates (exact differences)
    localparam integer SW = 2 * WIDTH - 2;  // set-up sums: R^2, |End|^2 < 2^(2*WIDTH-5)
    localparam [1:0] IDLE = 2'd0, SETUP = 2'd1, RUN = 2'd2, LAST = 2'd3;  // SETUP ends with `check`

    reg  [1:0]    state_q, state_d;
    reg           idle_q;                   // state IDLE, as a flag of its own (the start's path)
    reg  [UW-1:0] u0_q, v0_q, u1_q, v1_q;   // start and end point relative to the centre
    reg           ccw_q, full_q;

    wire load = start & idle_q;
    assign busy = !idle_q;

    wire check, on_band, setup_busy;
    circle_setup #(.MW(UW), .SW(SW)) u_setup (
        .clk(clk), .rst(rst), .start(load), .x0(u0_q), .y0(v0_q), .x1(u1_q), .y1(v1_q),
        .busy(setup_busy), .check(check), .on_band(on_band)
    );

    // Command check (in the `check` cycle).  The command's registers hold still through
    // the set-up, so the checks are registered in stages of one or two LUT levels (settled
    // long before `check`): wide compares straight from the command's registers, which
    // fan out across the chip, would be the slowest paths of the core.
    localparam integer LB = WIDTH - 3;      // range: -2^LB < value < 2^LB
    localparam integer NG = (LB + 3) / 4;   // 4-bit groups of a value's low LB bits
    localparam integer DG = (UW + 1) / 2;   // 2-bit groups of a coordinate
    // {top bits all ones, all zeros, low groups nonzero}
    function automatic [NG+1:0] range_flags(input [UW-1:0] x);
        integer i;
        reg [4*NG-1:0] low;
        begin
            low = {(4*NG){1'b0}};
            for (i = 0; i < LB; i = i + 1) low[i] = x[i];
            for (i = 0; i < NG; i = i + 1) range_flags[i] = |low[4*i +: 4];
            range_flags[NG+1:NG] = {&x[UW-1:LB], ~|x[UW-1:LB]};
        end
    endfunction
    function automatic [DG-1:0] differs(input [UW-1:0] a, b);      // per 2-bit group
        integer i;
        reg [2*DG-1:0] d;
        begin
            d = {(2*DG){1'b0}};
            for (i = 0; i < UW; i = i + 1) d[i] = a[i] ^ b[i];
            for (i = 0; i < DG; i = i + 1) differs[i] = |d[2*i +: 2];
        end
    endfunction
    function automatic in_range(input [NG+1:0] f);
        in_range = f[NG] || (f[NG+1] && |f[NG-1:0]);
    endfunction
    function automatic is_zero(input [NG+1:0] f);
        is_zero = f[NG] && !(|f[NG-1:0]);
    endfunction
    reg [NG+1:0]   rf_u0_q, rf_v0_q, rf_u1_q, rf_v1_q;   // stage 1
    reg [2*DG-1:0] dif_q;
    reg [3:0]      fit_q;                                // stage 2
    reg            zero_u0_q, zero_v0_q;
    reg            fits_q, at_centre_q, at_start_q;      // stage 3 (at_start_q: 2)
    reg            cmd_ok_q;                             // stage 4: fits and off the centre
    // (continuous assignments: simulators evaluate the functions only when the command changes)
    wire [NG+1:0]   rf_u0 = range_flags(u0_q), rf_v0 = range_flags(v0_q);
    wire [NG+1:0]   rf_u1 = range_flags(u1_q), rf_v1 = range_flags(v1_q);
    wire [2*DG-1:0] dif = {differs(u0_q, u1_q), differs(v0_q, v1_q)};
    always @(posedge clk) begin
        rf_u0_q     <= rf_u0;
        rf_v0_q     <= rf_v0;
        rf_u1_q     <= rf_u1;
        rf_v1_q     <= rf_v1;
        dif_q       <= dif;
        fit_q       <= {in_range(rf_u0_q), in_range(rf_v0_q), in_range(rf_u1_q), in_range(rf_v1_q)};
        zero_u0_q   <= is_zero(rf_u0_q);
        zero_v0_q   <= is_zero(rf_v0_q);
        at_start_q  <= !(|dif_q);
        fits_q      <= &fit_q;
        at_centre_q <= zero_u0_q && zero_v0_q;
        cmd_ok_q    <= fits_q && !at_centre_q;
    end
    wire bad = !cmd_ok_q || !on_band;

    // The stepper follows the command's registers through the set-up and steps in RUN (the
    // benches read its point and E inside it: u_stepper.u_step_stage.position_u, ...).
    wire          fin;
    // The stepper registers `run`: it follows RUN from the cycle after the check (its `rst`
    // clears it), so the check's band flag and command flags stay off the path into its
    // step enable.
    wire run_d = state_q == RUN && !fin;
    arc_stepper #(.WIDTH(WIDTH)) u_stepper (
        .clk(clk), .rst(rst), .run(run_d), .tick(tick), .u0(u0_q), .v0(v0_q), .u1(u1_q), .v1(v1_q),
        .ccw(ccw_q), .step_x(step_x), .step_y(step_y), .dir_x(dir_x), .dir_y(dir_y), .fin(fin)
    );

    always @(*) begin
        case (state_q)
            IDLE:    state_d = load ? SETUP : IDLE;
            SETUP:   state_d = !check ? SETUP : bad ? IDLE : at_start_q && !full_q ? LAST : RUN;
            RUN:     state_d = fin ? IDLE : RUN;
            default: state_d = IDLE;            // LAST: done
        endcase
    end
    always @(posedge clk) begin
        if (rst) begin
            state_q <= IDLE;
            idle_q  <= 1'b1;
            u0_q    <= {UW{1'b0}};
            v0_q    <= {UW{1'b0}};
            u1_q    <= {UW{1'b0}};
            v1_q    <= {UW{1'b0}};
            ccw_q   <= 1'b0;
            full_q  <= 1'b0;
            done    <= 1'b0;
            error   <= 1'b0;
        end else begin
            if (idle_q) begin                   // (idle: the command follows the inputs)
                u0_q    <= {x0[WIDTH-1], x0} - {cx[WIDTH-1], cx};
                v0_q    <= {y0[WIDTH-1], y0} - {cy[WIDTH-1], cy};
                u1_q    <= {x1[WIDTH-1], x1} - {cx[WIDTH-1], cx};
                v1_q    <= {y1[WIDTH-1], y1} - {cy[WIDTH-1], cy};
                ccw_q   <= ccw;
                full_q  <= full;
            end
            state_q <= state_d;
            idle_q  <= state_d == IDLE;
            done  <= state_q == LAST || fin;
            error <= check && bad;
        end
    end

    wire unused = &{1'b0, setup_busy};
endmodule
`default_nettype wire
