// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Step/dir output stage: turns each released step into step pulses and
// direction levels that meet a stepper driver's timing (all in clock cycles,
// set at run time from the timing registers `pulse_width`, `setup`, `hold`).
//
//   pulse_width  every step pulse is high for exactly max(pulse_width, 1) cycles
//   setup        dir of an axis changes >= setup cycles before its step rises
//   hold         dir of an axis changes >= hold cycles after its step fell
//
// A step on several axes pulses them together.  Only the axes that step may
// change direction.  A step in the same direction as before rises at the
// clock edge that accepts it; a direction change first waits for the hold
// time (state HOLD) and the setup time (state SETUP).  Between two pulses the
// step line is low for at least one cycle.  At the minimum settings (1, 0, 0)
// the stage takes one step every 2 cycles (3 when the direction reverses).
// The timing registers must not change while `ready` is low.
module step_dir #(
    parameter integer AXES = 3,     // number of axes (>= 1)
    parameter integer TW   = 8      // width of the timing registers (>= 1)
) (
    input  wire            clk,
    input  wire            rst,
    input  wire [TW-1:0]   pulse_width,
    input  wire [TW-1:0]   setup,
    input  wire [TW-1:0]   hold,
    input  wire            valid,     // a step is offered (taken when `ready`)
    input  wire [AXES-1:0] step_in,
    input  wire [AXES-1:0] dir_in,    // 1 = negative direction
    output wire            ready,     // idle: the next step is taken at once
    output reg  [AXES-1:0] step,      // to the driver
    output reg  [AXES-1:0] dir
);
    initial begin
        if (AXES < 1) $error("%m: AXES must be at least 1");
        if (TW < 1) $error("%m: TW must be at least 1");
    end

    localparam [1:0] IDLE = 2'd0, HOLD = 2'd1, SETUP = 2'd2, PULSE = 2'd3;

    reg [1:0]      state;
    reg [TW-1:0]   count;       // SETUP: cycles left with the new dir; PULSE: high cycles left
    reg [TW-1:0]   since_fall;  // cycles since the last falling edge (saturates)
    reg [AXES-1:0] pend_step, pend_dir;

    wire [TW-1:0] width     = (pulse_width == {TW{1'b0}}) ? {{(TW-1){1'b0}}, 1'b1} : pulse_width;
    wire          take      = valid & (state == IDLE);
    wire          turn      = |(step_in & (dir_in ^ dir));          // a stepping axis reverses
    wire          held      = {1'b0, since_fall} + 1'b1 >= {1'b0, hold};  // a dir change now keeps hold
    wire [AXES-1:0] new_dir = (dir & ~pend_step) | (pend_dir & pend_step);
    wire          saturated = &since_fall;
    assign ready = state == IDLE;

    always @(posedge clk) begin
        if (rst) begin
            state      <= IDLE;
            count      <= {TW{1'b0}};
            since_fall <= {TW{1'b1}};
            pend_step  <= {AXES{1'b0}};
            pend_dir   <= {AXES{1'b0}};
            step       <= {AXES{1'b0}};
            dir        <= {AXES{1'b0}};
        end else begin
            if (~saturated)
                since_fall <= since_fall + 1'b1;
            case (state)
                IDLE: if (take) begin
                    pend_step <= step_in;
                    pend_dir  <= dir_in;
                    if (turn) begin
                        state <= HOLD;
                    end else begin
                        step  <= step_in;
                        count <= width;
                        state <= PULSE;
                    end
                end
                HOLD: if (held) begin
                    dir <= new_dir;
                    if (setup == {TW{1'b0}}) begin
                        step  <= pend_step;
                        count <= width;
                        state <= PULSE;
                    end else begin
                        count <= setup;
                        state <= SETUP;
                    end
                end
                SETUP: begin
                    if (count == {{(TW-1){1'b0}}, 1'b1}) begin
                        step  <= pend_step;
                        count <= width;
                        state <= PULSE;
                    end else begin
                        count <= count - 1'b1;
                    end
                end
                PULSE: begin
                    if (count == {{(TW-1){1'b0}}, 1'b1}) begin
                        step       <= {AXES{1'b0}};
                        since_fall <= {TW{1'b0}};
                        state      <= IDLE;
                    end else begin
                        count <= count - 1'b1;
                    end
                end
                default: state <= IDLE;
            endcase
        end
    end
endmodule
`default_nettype wire
