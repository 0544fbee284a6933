// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Board wrapper: the production linear core lin_exact (SU 1571551's exact mode) with step/dir pins
// and a serial command port, for the iCE40-HX8K breakout board
// (constraints/hx8k_breakout.pcf) and the ULX3S 25F (constraints/ulx3s.lpf).
//
// Command port (SPI mode 0 from a microcontroller): with cmd_cs_n low, shift
// 2*WIDTH bits in on the rising edges of cmd_sck, X first, MSB first (signed
// step counts); raising cmd_cs_n starts the move.  A command sent while the
// core is busy is ignored (the core ignores start while busy); cmd_busy says
// when to send the next one.
// Step pins: each step is a PULSE_CYCLES-long high pulse, at STEP_HZ steps per
// second (the core's `tick`), dir pins high for the negative direction.
// LEDs: 0 busy, 1 toggles at every done, 2/3 follow the X/Y step pins.
module board_top #(
    parameter integer WIDTH        = 32,        // coordinate width in bits (>= 2)
    parameter integer CLK_HZ       = 12000000,  // board clock frequency
    parameter integer STEP_HZ      = 10000,     // tick rate: steps per second per axis
    parameter integer PULSE_CYCLES = 24         // step pulse length in clock cycles (2 us at 12 MHz)
) (
    input  wire       clk,
    input  wire       cmd_sck,
    input  wire       cmd_mosi,
    input  wire       cmd_cs_n,
    output wire       cmd_busy,
    output wire       step_x_pin,
    output wire       dir_x_pin,
    output wire       step_y_pin,
    output wire       dir_y_pin,
    output wire [7:0] led
);
    localparam integer DIV = CLK_HZ / STEP_HZ;   // clocks per tick
    initial begin
        if (WIDTH < 2) $error("%m: WIDTH must be at least 2");
        if (DIV < 2) $error("%m: STEP_HZ must be at most CLK_HZ / 2");
        if (PULSE_CYCLES < 1 || PULSE_CYCLES >= DIV) $error("%m: PULSE_CYCLES must be 1 .. CLK_HZ / STEP_HZ - 1");
    end

    // Power-on reset: the FPGA loads the register with zeros (the one
    // register that needs an initial value instead of a reset, hence the waiver).
    /* verilator lint_off PROCASSINIT */
    reg [3:0] por_q = 4'd0;
    /* verilator lint_on PROCASSINIT */
    wire rst = ~&por_q;
    always @(posedge clk) if (rst) por_q <= por_q + 4'd1;

    // Command port: two-flop synchronizers, then edge detection.
    reg [2:0] sck_q, cs_q;
    reg [1:0] mosi_q;
    reg [2*WIDTH-1:0] cmd_q;
    always @(posedge clk) begin
        if (rst) begin
            sck_q <= 3'b000; cs_q <= 3'b111; mosi_q <= 2'b00; cmd_q <= {2*WIDTH{1'b0}};
        end else begin
            sck_q  <= {sck_q[1:0], cmd_sck};
            cs_q   <= {cs_q[1:0], cmd_cs_n};
            mosi_q <= {mosi_q[0], cmd_mosi};
            if (!cs_q[1] && sck_q[1] && !sck_q[2])
                cmd_q <= {cmd_q[2*WIDTH-2:0], mosi_q[1]};
        end
    end
    wire start = cs_q[1] && !cs_q[2];            // chip select released

    // Tick: one in DIV clocks.
    reg [31:0] div_q;
    wire tick = div_q == 32'd0;
    always @(posedge clk) begin
        if (rst || tick) div_q <= DIV - 1;
        else             div_q <= div_q - 32'd1;
    end

    wire step_x, step_y, dir_x, dir_y, busy, done;
    lin_exact #(.WIDTH(WIDTH)) u_core (
        .clk(clk), .rst(rst), .start(start), .tick(tick),
        .x(cmd_q[2*WIDTH-1:WIDTH]), .y(cmd_q[WIDTH-1:0]),
        .step_x(step_x), .step_y(step_y), .dir_x(dir_x), .dir_y(dir_y),
        .busy(busy), .done(done)
    );

    // Step pulses long enough for a stepper driver.
    reg [15:0] pulse_x_q, pulse_y_q;
    reg        done_led_q;
    always @(posedge clk) begin
        if (rst) begin
            pulse_x_q <= 16'd0; pulse_y_q <= 16'd0; done_led_q <= 1'b0;
        end else begin
            pulse_x_q <= step_x ? PULSE_CYCLES[15:0] : pulse_x_q - {15'd0, pulse_x_q != 16'd0};
            pulse_y_q <= step_y ? PULSE_CYCLES[15:0] : pulse_y_q - {15'd0, pulse_y_q != 16'd0};
            done_led_q <= done_led_q ^ done;
        end
    end
    assign step_x_pin = pulse_x_q != 16'd0;
    assign step_y_pin = pulse_y_q != 16'd0;
    assign dir_x_pin  = dir_x;
    assign dir_y_pin  = dir_y;
    assign cmd_busy   = busy;
    assign led        = {4'b0000, step_y_pin, step_x_pin, done_led_q, busy};

endmodule
`default_nettype wire
