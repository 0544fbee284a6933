// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Synchronization buffer of the lecture ("synchronization scheme"):
// the interpolator runs at full speed into a small store and is held by STOP
// while the store is full; each feed tick sends the oldest stored step to the
// drive and frees a place.  The lecture's circuit is two D flip-flops per
// axis (DEPTH = 2) plus AND 1-3 and a delay line; here the store holds one
// entry per step for all axes together, so a diagonal step stays one step.
//
// STOP must be raised before the store is full, because the core's step
// strobe comes LATENCY cycles after the tick that made it: `stop` is high
// when the stored steps plus the ticks given in the last LATENCY cycles
// (each may still bring a step) reach DEPTH.  So no step ever finds the
// store full; if one does (a core that breaks its LATENCY), it is refused
// and the sticky `overflow` flag is set.
module step_sync #(
    parameter integer AXES    = 3,  // axes per step (>= 1)
    parameter integer DEPTH   = 2,  // steps stored (>= 1); the lecture has 2
    parameter integer LATENCY = 1,  // cycles from the core's tick to its step strobe (>= 1)
    parameter integer DATA_W  = 1,  // bits stored with each step (motion_top: the feed)
    parameter integer LW      = 2   // width of `level` (2^LW > DEPTH)
) (
    input  wire              clk,
    input  wire              rst,
    input  wire [AXES-1:0]   in_step,   // step strobes from the core
    input  wire [AXES-1:0]   in_dir,
    input  wire [DATA_W-1:0] in_data,
    output wire              stop,      // STOP: the core must not tick
    input  wire              tick,      // feed tick: release the oldest step
    output wire              out_valid, // a step is waiting
    output wire [AXES-1:0]   out_step,  // the oldest step (leaves in a cycle with `tick`)
    output wire [AXES-1:0]   out_dir,
    output wire [DATA_W-1:0] out_data,
    output wire [LW-1:0]     level,
    output reg               overflow   // a step found the store full (sticky until rst)
);
    initial begin
        if (AXES < 1) $error("%m: AXES must be at least 1");
        if (DEPTH < 1) $error("%m: DEPTH must be at least 1");
        if (LATENCY < 1) $error("%m: LATENCY must be at least 1");
        if (DATA_W < 1) $error("%m: DATA_W must be at least 1");
        if (LW < 1 || (1 << LW) <= DEPTH) $error("%m: LW must satisfy 2^LW > DEPTH");
    end

    localparam integer EW = DATA_W + 2 * AXES;
    localparam integer CW = 32;         // level + ticks in flight, compared with DEPTH

    wire [EW-1:0] head;
    wire          refused, full;
    // The oldest step comes from a register (HEAD_REG): the drive side (the step pacer's
    // compare of its cost, the output stage) starts at a flip-flop, not at a memory read.
    sync_fifo #(.WIDTH(EW), .DEPTH(DEPTH), .LW(LW), .HEAD_REG(1)) u_store (
        .clk(clk), .rst(rst), .push(|in_step), .din({in_data, in_dir, in_step}),
        .pop(tick), .dout(head), .valid(out_valid), .full(full), .level(level),
        .overflow(refused)
    );
    assign {out_data, out_dir, out_step} = head;

    // Ticks given to the core in the last LATENCY cycles.
    reg [LATENCY-1:0] given_q;
    reg [CW-1:0]      in_flight;
    integer i;
    always @* begin
        in_flight = {CW{1'b0}};
        for (i = 0; i < LATENCY; i = i + 1)
            in_flight = in_flight + {{(CW-1){1'b0}}, given_q[i]};
    end
    assign stop = ({{(CW-LW){1'b0}}, level} + in_flight) >= DEPTH;

    wire [LATENCY-1:0] shifted;
    generate
        if (LATENCY == 1) begin : g_one
            assign shifted = ~stop;
        end else begin : g_many
            assign shifted = {given_q[LATENCY-2:0], ~stop};
        end
    endgenerate

    always @(posedge clk) begin
        if (rst) begin
            given_q  <= {LATENCY{1'b0}};
            overflow <= 1'b0;
        end else begin
            given_q  <= shifted;
            if (refused)
                overflow <= 1'b1;
        end
    end
    wire unused = &{1'b0, full};   // `stop` already keeps the store from filling
endmodule
`default_nettype wire
