// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ULX3S board top (ECP5 CABGA381; the build targets the LFE5U-85F variant, the
// only one large enough for the controller): the portable controller design
// rtl/uart_controller.v (UART link + controller) on the board's pins
// (boards/ulx3s/ulx3s.lpf).
//   clock ....... the 25 MHz oscillator, used directly (CLK_HZ = 25 MHz)
//   reset ....... power-on reset: held for 2^RESET_BITS clocks after the
//                 bitstream loads, and while the FIRE1 button is pressed
//                 (button synchronized by two flip-flops)
//   UART ........ the FT231X USB serial port (ftdi_txd in, ftdi_rxd out)
//   machine ..... step/dir/enable, inputs, spindle, coolant, digital outputs on
//                 the GPIO headers; the LEDs show uart_controller's led[7:0]
module top #(
    parameter integer CLK_HZ     = 25000000,  // system clock in Hz: the oscillator's 25 MHz
    parameter integer BAUD       = 115200,    // UART bit rate (host side: interp send --baud)
    parameter integer CURVES     = 1,         // curve core (kind 3): 1 present, 0 left out (kind 3 refused with error 1)
    parameter integer RESET_BITS = 4          // power-on reset lasts 2^RESET_BITS - 1 clocks (1 .. 24)
) (
    input  wire       clk_25mhz,
    input  wire       reset_button,   // FIRE1, high while pressed
    input  wire       ftdi_txd,       // host -> FPGA
    output wire       ftdi_rxd,       // FPGA -> host
    output wire [7:0] led,
    output wire [2:0] step,
    output wire [2:0] dir,
    output wire       enable,
    input  wire       estop,
    input  wire [2:0] limit,
    input  wire       probe,
    output wire       spindle_on,
    output wire       spindle_ccw,
    output wire       spindle_pwm,
    output wire       mist,
    output wire       flood,
    output wire [3:0] dout
);
    initial begin
        if (CLK_HZ != 25000000) $error("%m: CLK_HZ must be 25000000 (the oscillator, no PLL)");
        if (BAUD < 1 || BAUD * 4 > CLK_HZ) $error("%m: BAUD must be 1 .. CLK_HZ / 4");
        if (CURVES != 0 && CURVES != 1) $error("%m: CURVES must be 0 or 1");
        if (RESET_BITS < 1 || RESET_BITS > 24) $error("%m: RESET_BITS must be 1 .. 24");
    end

    wire clk = clk_25mhz;

    // Power-on reset: the FPGA loads these registers with zeros (the registers
    // that need an initial value instead of a reset, hence the waiver).
    /* verilator lint_off PROCASSINIT */
    reg [RESET_BITS-1:0] por_q = {RESET_BITS{1'b0}};
    reg [1:0]            button_q = 2'b00;
    reg                  rst_q = 1'b1;
    /* verilator lint_on PROCASSINIT */
    always @(posedge clk) begin
        button_q <= {button_q[0], reset_button};
        if (button_q[1])    por_q <= {RESET_BITS{1'b0}};
        else if (!(&por_q)) por_q <= por_q + {{(RESET_BITS-1){1'b0}}, 1'b1};
    end
    always @(posedge clk) rst_q <= ~&por_q;

    uart_controller #(.CLK_HZ(CLK_HZ), .BAUD(BAUD), .CURVES(CURVES)) u_controller (
        .clk(clk), .rst(rst_q),
        .uart_rx(ftdi_txd), .uart_tx(ftdi_rxd),
        .step(step), .dir(dir), .enable(enable),
        .estop(estop), .limit(limit), .probe(probe),
        .spindle_on(spindle_on), .spindle_ccw(spindle_ccw), .spindle_pwm(spindle_pwm),
        .mist(mist), .flood(flood), .dout(dout),
        .led(led)
    );
endmodule
