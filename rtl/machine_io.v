// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Machine outputs of the controller, set by motion_top's events (applied in program
// order, when the drive has stopped before them): spindle on / direction / speed as a
// PWM duty 0 .. 65535 of `period` clocks, mist and flood coolant, four digital outputs.
// Event codes: 1 spindle clockwise (value = duty), 2 counter-clockwise (duty), 3 spindle
// off, 4 spindle speed (duty), 5 mist on, 6 flood on, 7 coolant off, 8 output on
// (value = output 0 .. 3), 9 output off, 10 pause, 12 program end (spindle and coolant
// off), 13 laser mode (value 0 off, else on); other codes, 11 tool change among them (the
// host's M6 sends it, then a pause), are ignored.  In laser mode the spindle pins (on and
// PWM: the beam) are low while `held` (a feed hold at rest), as Grbl's laser mode; the
// spindle_on register keeps the program's state; and M4 (spindle_ccw) is Grbl's dynamic
// power: the PWM runs at `scaled` (power_scale: duty x speed / feed) instead of duty.  A duty below 0 counts as 0, above 65535 as 65535.  `pause` strobes for
// code 10 (the controller holds).
// `off` (abort, alarm) switches spindle and coolant off at once and ends laser mode; the
// outputs keep.
// PWM: a counter runs over `period` clocks (0 counts as 1); `pwm` is high while the
// counter is below level * period / 65536, where level = duty x scale / 256 (the spindle
// override, 256 = 100 %; above 65535 it counts as 65535, always high), and low while the
// spindle is off.  The spindle pin and the PWM are registers (a clock after the state they
// show: no glitch reaches the drive).  One adder makes both products by shift and add, from the start of a
// period: level over 10 clocks, then the threshold over 16, 29 clocks in all (a new duty,
// scale or period takes effect within two periods and 58 clocks).
module machine_io #(
    parameter integer W = 32        // width of the event value, signed (>= 4)
) (
    input  wire         clk,
    input  wire         rst,
    input  wire         event_valid,    // motion_top's event strobe
    input  wire [7:0]   event_code,
    input  wire [W-1:0] event_value,    // signed
    input  wire         off,            // spindle and coolant off (abort, alarm)
    input  wire         held,           // a feed hold has stopped the machine
    input  wire [15:0]  scaled,         // duty x speed / feed (power_scale), for M4 in laser mode
    input  wire [15:0]  period,         // PWM period, clocks
    input  wire [9:0]   scale,          // spindle override: the PWM's duty x scale / 256
    output reg          spindle_on,     // the program's spindle state
    output reg          spindle_pin,    // spindle_on, low while held in laser mode (a clock later: a register)
    output reg          spindle_ccw,
    output reg  [15:0]  duty,           // 0 .. 65535
    output reg          spindle_pwm,    // the PWM (a register: no glitch at the pin)
    output reg          mist,
    output reg          flood,
    output reg  [3:0]   dout,
    output wire         pause           // strobe: a pause event (code 10)
);
    initial begin
        if (W < 4) $error("%m: W must be at least 4");
    end

    localparam [7:0] SPINDLE_CW = 8'd1, SPINDLE_CCW = 8'd2, SPINDLE_OFF = 8'd3, SPINDLE_SPEED = 8'd4,
                     MIST_ON = 8'd5, FLOOD_ON = 8'd6, COOLANT_OFF = 8'd7, OUTPUT_ON = 8'd8,
                     OUTPUT_OFF = 8'd9, PAUSE = 8'd10, PROGRAM_END = 8'd12, LASER = 8'd13;
    reg         laser;              // laser mode

    // the value as a duty: clamped to 0 .. 65535
    wire        negative = event_value[W-1];
    wire        above;              // above 65535
    wire [15:0] low;                // the value's bits 15:0 (zero-extended if W < 16)
    generate
        if (W > 17) begin : g_wide
            assign above = |event_value[W-2:16];
            assign low   = event_value[15:0];
        end else if (W == 17) begin : g_17
            assign above = 1'b0;
            assign low   = event_value[15:0];
        end else begin : g_narrow
            assign above = 1'b0;
            assign low   = {{(17 - W){1'b0}}, event_value[W-2:0]};
        end
    endgenerate
    wire [15:0] clamped  = negative ? 16'd0 : above ? 16'hFFFF : low;
    wire [3:0]  select   = 4'd1 << event_value[1:0];
    wire        output_number = event_value[W-1:2] == {(W-2){1'b0}};   // 0 .. 3

    assign pause = event_valid & (event_code == PAUSE);

    always @(posedge clk) begin
        if (rst) begin
            spindle_on  <= 1'b0;
            spindle_ccw <= 1'b0;
            duty        <= 16'd0;
            mist        <= 1'b0;
            flood       <= 1'b0;
            dout        <= 4'd0;
            laser       <= 1'b0;
        end else if (off) begin
            spindle_on <= 1'b0;
            mist       <= 1'b0;
            flood      <= 1'b0;
            laser      <= 1'b0;         // an aborted laser job leaves no laser mode behind
        end else if (event_valid) begin
            case (event_code)
                SPINDLE_CW:    begin spindle_on <= 1'b1; spindle_ccw <= 1'b0; duty <= clamped; end
                SPINDLE_CCW:   begin spindle_on <= 1'b1; spindle_ccw <= 1'b1; duty <= clamped; end
                SPINDLE_OFF:   spindle_on <= 1'b0;
                SPINDLE_SPEED: duty <= clamped;
                MIST_ON:       mist <= 1'b1;
                FLOOD_ON:      flood <= 1'b1;
                COOLANT_OFF:   begin mist <= 1'b0; flood <= 1'b0; end
                OUTPUT_ON:     if (output_number) dout <= dout | select;
                OUTPUT_OFF:    if (output_number) dout <= dout & ~select;
                PROGRAM_END:   begin spindle_on <= 1'b0; mist <= 1'b0; flood <= 1'b0; end
                LASER:         laser <= event_value != {W{1'b0}};
                default:       ;
            endcase
        end
    end

    // ---------------- PWM ----------------
    // round 28 .. 19: product = power x scale; 18: the level (product / 256, at most 65535)
    // becomes the multiplier; 17 .. 2: product = level x period; 1: the threshold
    reg  [15:0] counter, threshold;
    reg  [31:0] product;            // the product being made
    reg  [15:0] multiplier;         // its multiplier's bits still to add (lowest first)
    reg  [31:0] multiplicand;       // its multiplicand, shifted
    reg  [4:0]  round;              // 28 .. 1 while the products are made, 0 idle
    reg         full_next, full;    // the level is 65535: always high (full: of the threshold)
    wire [15:0] last = (period == 16'd0 ? 16'd1 : period) - 1'b1;
    wire [15:0] power = laser & spindle_ccw ? scaled : duty;    // the PWM's duty
    wire        wrap = counter >= last;
    wire        over = product[31:24] != 8'd0;                  // power x scale / 256 > 65535
    wire [15:0] level = over ? 16'hFFFF : product[23:8];

    always @(posedge clk) begin
        if (rst) begin
            counter      <= 16'd0;
            threshold    <= 16'd0;
            product      <= 32'd0;
            multiplier   <= 16'd0;
            multiplicand <= 32'd0;
            round        <= 5'd0;
            full_next    <= 1'b0;
            full         <= 1'b0;
        end else begin
            counter <= wrap ? 16'd0 : counter + 1'b1;
            if (round == 5'd0) begin
                if (wrap) begin
                    product      <= 32'd0;
                    multiplier   <= {6'd0, scale};
                    multiplicand <= {16'd0, power};
                    round        <= 5'd28;
                end
            end else if (round == 5'd18) begin
                product      <= 32'd0;
                multiplier   <= level;
                multiplicand <= {16'd0, period};
                full_next    <= level == 16'hFFFF;
                round        <= 5'd17;
            end else if (round == 5'd1) begin
                threshold <= product[31:16];
                full      <= full_next;
                round     <= 5'd0;
            end else begin
                if (multiplier[0])
                    product <= product + multiplicand;
                multiplier   <= multiplier >> 1;
                multiplicand <= multiplicand << 1;
                round        <= round - 1'b1;
            end
        end
    end

    // the pins from registers, a clock after the state they show: a comparator's or a gate's
    // glitch never reaches the spindle drive or the laser
    wire beam = spindle_on & ~(laser & held);
    always @(posedge clk) begin
        if (rst) begin
            spindle_pin <= 1'b0;
            spindle_pwm <= 1'b0;
        end else begin
            spindle_pin <= beam;
            spindle_pwm <= beam & (full || counter < threshold);
        end
    end
endmodule
`default_nettype wire
