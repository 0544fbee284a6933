// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ULX3S board top (ECP5 CABGA381; the build targets the LFE5U-25F variant, which
// holds the whole controller, curve core included; the 45F and 85F share the pins):
// the portable controller design rtl/uart_controller.v (UART link + controller) on
// the board's pins (boards/ulx3s/ulx3s.lpf).
//   clock ....... EHXPLLL from the 25 MHz oscillator (feedback from CLKOP):
//                 CLK_HZ = 25 MHz * PLL_CLKFB_DIV / PLL_CLKI_DIV, VCO = CLK_HZ * PLL_CLKOP_DIV
//                 (400 .. 800 MHz).  15 MHz (25 MHz x 3 / 5, VCO 600 MHz): the controller
//                 at the compiler's widths reaches about 49 MHz routed on the 25F, and a
//                 bit at 3 Mbaud is exactly 5 clocks (at 25 MHz it would be 8.33)
//   reset ....... held until the PLL locks, then 2^RESET_BITS - 1 clocks, and
//                 while the FIRE1 button is pressed (LOCK and the button
//                 synchronized by two flip-flops)
//   UART ........ the FT231X USB serial port (ftdi_txd in, ftdi_rxd out)
//   ESP32 ....... its GPIO0 held high (both board revisions' pins), as the board's
//                 reference designs do: low, it can reset the board into the ESP32's loader
//   machine ..... step/dir/enable, inputs, spindle, coolant, digital outputs on
//                 the GPIO headers; the LEDs show uart_controller's led[7:0]
module top #(
    parameter integer CLK_HZ     = 15000000,  // system clock in Hz, = 25 MHz * PLL_CLKFB_DIV / PLL_CLKI_DIV
    parameter integer PLL_CLKI_DIV  = 5,      // PLL reference divider (1 .. 8: the phase detector needs >= 3.125 MHz)
    parameter integer PLL_CLKFB_DIV = 3,      // PLL feedback divider (1 .. 128)
    parameter integer PLL_CLKOP_DIV = 40,     // PLL output divider: VCO / CLK_HZ (1 .. 128)
    parameter integer BAUD       = 115200,    // UART bit rate (host side: interp send --baud)
    parameter integer CURVES     = 0,         // curve core (kind 3): 0 left out (kind 3 refused with error 1), 1 present (3400 LUT4s more: a 45F or 85F)
    parameter integer INPUT_INVERT  = 0,      // active-low inputs from the reset on: INPUT_INVERT's bits (0 .. 31)
    parameter integer OUTPUT_INVERT = 0,      // active-low pins from the reset on: OUTPUT_INVERT's bits (0 .. 65535)
    parameter integer RESET_BITS = 4          // power-on reset lasts 2^RESET_BITS - 1 clocks (1 .. 24)
) (
    input  wire       clk_25mhz,
    input  wire       reset_button,   // FIRE1, high while pressed
    input  wire       ftdi_txd,       // host -> FPGA
    output wire       ftdi_rxd,       // FPGA -> host
    output wire       wifi_gpio0,     // ESP32 GPIO0 on PCB v2.x / v3.0.x: held high
    output wire       wifi_gpio0_v31, // ESP32 GPIO0 on PCB v3.1.x (its enable on v3.0.x): held high
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
        if (PLL_CLKI_DIV < 1 || PLL_CLKI_DIV > 8 || PLL_CLKFB_DIV < 1 || PLL_CLKFB_DIV > 128
            || PLL_CLKOP_DIV < 1 || PLL_CLKOP_DIV > 128) $error("%m: PLL_CLKI_DIV must be 1 .. 8, the other PLL dividers 1 .. 128");
        if (CLK_HZ * PLL_CLKI_DIV != 25000000 * PLL_CLKFB_DIV)
            $error("%m: CLK_HZ must be exactly 25 MHz * PLL_CLKFB_DIV / PLL_CLKI_DIV");
        if (CLK_HZ / 1000 * PLL_CLKOP_DIV < 400000 || CLK_HZ / 1000 * PLL_CLKOP_DIV > 800000)
            $error("%m: the VCO (CLK_HZ * PLL_CLKOP_DIV) must be 400 .. 800 MHz");
        if (BAUD < 1 || BAUD * 4 > CLK_HZ) $error("%m: BAUD must be 1 .. CLK_HZ / 4");
        if (CURVES != 0 && CURVES != 1) $error("%m: CURVES must be 0 or 1");
        if (INPUT_INVERT < 0 || INPUT_INVERT > 31) $error("%m: INPUT_INVERT must be 0 .. 31");
        if (OUTPUT_INVERT < 0 || OUTPUT_INVERT > 65535) $error("%m: OUTPUT_INVERT must be 0 .. 65535");
        if (RESET_BITS < 1 || RESET_BITS > 24) $error("%m: RESET_BITS must be 1 .. 24");
    end

    wire clk, locked;
    // Only CLKOP is used: the other outputs stay open, their enables low.
    /* verilator lint_off PINCONNECTEMPTY */
    EHXPLLL #(
        .PLLRST_ENA("DISABLED"),
        .INTFB_WAKE("DISABLED"),
        .STDBY_ENABLE("DISABLED"),
        .DPHASE_SOURCE("DISABLED"),
        .OUTDIVIDER_MUXA("DIVA"),
        .OUTDIVIDER_MUXB("DIVB"),
        .OUTDIVIDER_MUXC("DIVC"),
        .OUTDIVIDER_MUXD("DIVD"),
        .CLKI_DIV(PLL_CLKI_DIV),
        .CLKOP_ENABLE("ENABLED"),
        .CLKOP_DIV(PLL_CLKOP_DIV),
        .CLKOP_CPHASE(PLL_CLKOP_DIV / 2 - 1),
        .CLKOP_FPHASE(0),
        .FEEDBK_PATH("CLKOP"),
        .CLKFB_DIV(PLL_CLKFB_DIV)
    ) u_pll (
        .RST(1'b0),
        .STDBY(1'b0),
        .CLKI(clk_25mhz),
        .CLKOP(clk),
        .CLKFB(clk),
        .CLKINTFB(),
        .PHASESEL0(1'b0),
        .PHASESEL1(1'b0),
        .PHASEDIR(1'b1),
        .PHASESTEP(1'b1),
        .PHASELOADREG(1'b1),
        .PLLWAKESYNC(1'b0),
        .ENCLKOP(1'b0),
        .ENCLKOS(1'b0),
        .ENCLKOS2(1'b0),
        .ENCLKOS3(1'b0),
        .CLKOS(),
        .CLKOS2(),
        .CLKOS3(),
        .LOCK(locked),
        .INTLOCK(),
        .REFCLK()
    );
    /* verilator lint_on PINCONNECTEMPTY */

    // Reset: until the PLL locks, then 2^RESET_BITS - 1 clocks; again while FIRE1
    // is pressed.  The FPGA loads these registers with the given values (registers
    // that need an initial value instead of a reset, hence the waiver).
    /* verilator lint_off PROCASSINIT */
    reg [RESET_BITS-1:0] por_q = {RESET_BITS{1'b0}};
    reg [1:0]            button_q = 2'b00;
    reg [1:0]            locked_q = 2'b00;
    reg                  rst_q = 1'b1;
    /* verilator lint_on PROCASSINIT */
    always @(posedge clk) begin
        button_q <= {button_q[0], reset_button};
        locked_q <= {locked_q[0], locked};
        if (button_q[1] || !locked_q[1]) por_q <= {RESET_BITS{1'b0}};
        else if (!(&por_q))              por_q <= por_q + {{(RESET_BITS-1){1'b0}}, 1'b1};
        rst_q <= ~&por_q;
    end

    assign wifi_gpio0     = 1'b1;
    assign wifi_gpio0_v31 = 1'b1;

    uart_controller #(.CLK_HZ(CLK_HZ), .BAUD(BAUD), .CURVES(CURVES), .INPUT_INVERT_RESET(INPUT_INVERT),
                      .OUTPUT_INVERT_RESET(OUTPUT_INVERT)) u_controller (
        .clk(clk), .rst(rst_q),
        .uart_rx(ftdi_txd), .uart_tx(ftdi_rxd),
        .step(step), .dir(dir), .enable(enable),
        .estop(estop), .limit(limit), .probe(probe),
        .spindle_on(spindle_on), .spindle_ccw(spindle_ccw), .spindle_pwm(spindle_pwm),
        .mist(mist), .flood(flood), .dout(dout),
        .led(led)
    );
endmodule
