// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Machine inputs of the controller: e-stop, three limit switches and the probe, each
// through a 2-flop synchronizer, the input filter (input_filter u_filter: off while
// filter_period is 0) and then `invert` (bit set: the input is active low).
// E-stop active, or a limit switch becoming active, gates the step outputs off in the
// same cycle as the synchronized input shows it (`trip` asks the controller to latch its
// error and abort the motion; the controller's `alarm` then keeps them gated).  The
// e-stop trips as long as it is active; a limit switch trips on its active edge, so the
// machine can move off a switch after the error is cleared.
// Probe: `probe_arm` clears `probe_valid` and arms; the next active edge of the probe
// latches pos_x/y/z into probe_x/y/z and sets `probe_valid` (and disarms); `probe_hit`
// strobes in that clock (the controller may hold the motion there: G38.2).
module input_guard #(
    parameter integer POS_W = 32    // width of the position counters (>= 2)
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             estop,          // raw pins
    input  wire [2:0]       limit,          // x, y, z
    input  wire             probe,
    input  wire [4:0]       invert,         // estop, limit x/y/z, probe: 1 = active low
    input  wire [15:0]      filter_period,  // input_filter: clocks a sample, 0 = no filter
    input  wire [4:0]       filter_mask,    // estop, limit x/y/z, probe: 1 = filtered
    input  wire             alarm,          // an error is latched: keep the steps gated
    input  wire             probe_arm,      // strobe
    input  wire [2:0]       step_in,        // motion_top's step pulses
    output wire [2:0]       step_out,       // to the drives
    output wire [4:0]       inputs,         // synchronized, polarity applied
    output wire             estop_trip,     // the e-stop is active
    output wire [2:0]       limit_trip,     // strobes: a limit switch became active
    input  wire [POS_W-1:0] pos_x,
    input  wire [POS_W-1:0] pos_y,
    input  wire [POS_W-1:0] pos_z,
    output reg              probe_valid,
    output wire             probe_hit,      // strobe: the armed probe latched the position
    output reg  [POS_W-1:0] probe_x,
    output reg  [POS_W-1:0] probe_y,
    output reg  [POS_W-1:0] probe_z
);
    initial begin
        if (POS_W < 2) $error("%m: POS_W must be at least 2");
    end

    reg  [4:0] meta, synced, previous;
    reg        armed;
    wire [4:0] filtered;

    input_filter #(.N(5), .PW(16)) u_filter (
        .clk(clk), .rst(rst), .period(filter_period), .mask(filter_mask), .raw(synced),
        .filtered(filtered)
    );

    assign inputs     = filtered ^ invert;
    wire [4:0] rising = inputs & ~previous;
    assign estop_trip = inputs[0];
    assign limit_trip = rising[3:1];
    wire       gate   = alarm | estop_trip | |limit_trip;    // rising[0]: the e-stop trips by level
    assign step_out   = step_in & ~{3{gate}};

    always @(posedge clk) begin
        if (rst) begin
            meta     <= 5'd0;
            synced   <= 5'd0;
            previous <= 5'd0;
        end else begin
            meta     <= {probe, limit, estop};
            synced   <= meta;
            previous <= inputs;
        end
    end

    assign probe_hit = armed & rising[4] & ~probe_arm;

    always @(posedge clk) begin
        if (rst) begin
            armed       <= 1'b0;
            probe_valid <= 1'b0;
            probe_x     <= {POS_W{1'b0}};
            probe_y     <= {POS_W{1'b0}};
            probe_z     <= {POS_W{1'b0}};
        end else if (probe_arm) begin
            armed       <= 1'b1;
            probe_valid <= 1'b0;
        end else if (armed & rising[4]) begin
            armed       <= 1'b0;
            probe_valid <= 1'b1;
            probe_x     <= pos_x;
            probe_y     <= pos_y;
            probe_z     <= pos_z;
        end
    end
    wire unused = &{1'b0, rising[0]};
endmodule
`default_nettype wire
