// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// iCE40-HX8K breakout board top: the portable controller design
// rtl/uart_controller.v (UART link + controller) on the board's pins
// (boards/hx8k_breakout/hx8k_breakout.pcf).
//   clock ....... SB_PLL40_CORE from the 12 MHz oscillator:
//                 CLK_HZ = 12 MHz * (PLL_DIVF + 1) / 2^PLL_DIVQ (reference divider 1;
//                 the VCO, 12 MHz * (PLL_DIVF + 1), must be 533 .. 1066 MHz)
//   reset ....... held until the PLL locks, then 2^RESET_BITS - 1 clocks more
//   UART ........ the FT2232H's channel B (uart_rx in, uart_tx out)
//   machine ..... step/dir/enable, inputs, spindle, coolant, digital outputs on
//                 headers J2 and J3; the LEDs show uart_controller's led[7:0]
module top #(
    parameter integer CLK_HZ     = 18000000,  // system clock in Hz, = 12 MHz * (PLL_DIVF + 1) / 2^PLL_DIVQ
    parameter integer PLL_DIVF   = 47,        // PLL feedback divider - 1 (0 .. 127)
    parameter integer PLL_DIVQ   = 5,         // PLL output divider: 2^PLL_DIVQ (1 .. 6)
    parameter integer BAUD       = 115200,    // UART bit rate (host side: interp send --baud)
    parameter integer CURVES     = 0,         // curve core (kind 3): 0 leaves it out (kind 3 refused with error 1), to save area
    parameter integer INPUT_INVERT  = 0,      // active-low inputs from the reset on: INPUT_INVERT's bits (0 .. 31)
    parameter integer OUTPUT_INVERT = 0,      // active-low pins from the reset on: OUTPUT_INVERT's bits (0 .. 65535)
    parameter integer RESET_BITS = 4          // reset lasts 2^RESET_BITS - 1 clocks after lock (1 .. 24)
) (
    input  wire       clk_12mhz,
    input  wire       uart_rx,        // host -> FPGA
    output wire       uart_tx,        // FPGA -> host
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
    localparam integer VCO_HZ = 12000000 * (PLL_DIVF + 1);
    initial begin
        if (PLL_DIVF < 0 || PLL_DIVF > 127) $error("%m: PLL_DIVF must be 0 .. 127");
        if (PLL_DIVQ < 1 || PLL_DIVQ > 6) $error("%m: PLL_DIVQ must be 1 .. 6");
        if (VCO_HZ < 533000000 || VCO_HZ > 1066000000) $error("%m: the VCO (12 MHz * (PLL_DIVF + 1)) must be 533 .. 1066 MHz");
        if (CLK_HZ != VCO_HZ / (1 << PLL_DIVQ) || CLK_HZ * (1 << PLL_DIVQ) != VCO_HZ)
            $error("%m: CLK_HZ must be exactly 12 MHz * (PLL_DIVF + 1) / 2^PLL_DIVQ");
        if (BAUD < 1 || BAUD * 4 > CLK_HZ) $error("%m: BAUD must be 1 .. CLK_HZ / 4");
        if (CURVES != 0 && CURVES != 1) $error("%m: CURVES must be 0 or 1");
        if (INPUT_INVERT < 0 || INPUT_INVERT > 31) $error("%m: INPUT_INVERT must be 0 .. 31");
        if (OUTPUT_INVERT < 0 || OUTPUT_INVERT > 65535) $error("%m: OUTPUT_INVERT must be 0 .. 65535");
        if (RESET_BITS < 1 || RESET_BITS > 24) $error("%m: RESET_BITS must be 1 .. 24");
    end

    wire clk, locked;
    // PLLOUTCORE (the same clock on local routing) and SDO stay open.
    /* verilator lint_off PINCONNECTEMPTY */
    SB_PLL40_CORE #(
        .FEEDBACK_PATH("SIMPLE"),
        .DIVR(4'd0),
        .DIVF(PLL_DIVF[6:0]),
        .DIVQ(PLL_DIVQ[2:0]),
        .FILTER_RANGE(3'd1)
    ) u_pll (
        .REFERENCECLK(clk_12mhz),
        .PLLOUTCORE(),
        .PLLOUTGLOBAL(clk),
        .LOCK(locked),
        .RESETB(1'b1),
        .BYPASS(1'b0),
        .EXTFEEDBACK(1'b0),
        .DYNAMICDELAY(8'd0),
        .LATCHINPUTVALUE(1'b0),
        .SDI(1'b0),
        .SCLK(1'b0),
        .SDO()
    );
    /* verilator lint_on PINCONNECTEMPTY */

    // Reset: until the PLL locks (LOCK synchronized by two flip-flops), then
    // 2^RESET_BITS - 1 clocks.  The FPGA loads these registers with zeros / the
    // given values (registers that need an initial value instead of a reset,
    // hence the waiver).
    /* verilator lint_off PROCASSINIT */
    reg [RESET_BITS-1:0] por_q = {RESET_BITS{1'b0}};
    reg [1:0]            locked_q = 2'b00;
    reg                  rst_q = 1'b1;
    /* verilator lint_on PROCASSINIT */
    always @(posedge clk) begin
        locked_q <= {locked_q[0], locked};
        if (!locked_q[1])   por_q <= {RESET_BITS{1'b0}};
        else if (!(&por_q)) por_q <= por_q + {{(RESET_BITS-1){1'b0}}, 1'b1};
        rst_q <= ~&por_q;
    end

    uart_controller #(.CLK_HZ(CLK_HZ), .BAUD(BAUD), .CURVES(CURVES), .INPUT_INVERT_RESET(INPUT_INVERT),
                      .OUTPUT_INVERT_RESET(OUTPUT_INVERT)) u_controller (
        .clk(clk), .rst(rst_q),
        .uart_rx(uart_rx), .uart_tx(uart_tx),
        .step(step), .dir(dir), .enable(enable),
        .estop(estop), .limit(limit), .probe(probe),
        .spindle_on(spindle_on), .spindle_ccw(spindle_ccw), .spindle_pwm(spindle_pwm),
        .mist(mist), .flood(flood), .dout(dout),
        .led(led)
    );
endmodule
