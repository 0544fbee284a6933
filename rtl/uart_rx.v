// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// UART receiver, 8N1, LSB first.  `rx` passes a two-flop synchronizer; a
// falling edge starts a character, the start bit is checked at its middle (a
// glitch shorter than half a bit is ignored) and every data bit and the stop
// bit are sampled at their middles, CLKS_PER_BIT clocks apart.  A good stop
// bit (1) delivers the byte on `data` with a one-clock `valid`; a stop bit 0
// (framing error, or a break) drops the byte, pulses `frame_error`, and the
// receiver waits for the line to return high before looking for the next
// start bit.
module uart_rx #(
    parameter integer CLKS_PER_BIT = 104     // clocks per bit = CLK_HZ / BAUD (>= 4)
) (
    input  wire       clk,
    input  wire       rst,
    input  wire       rx,             // the serial line (asynchronous; idle high)
    output wire [7:0] data,           // the last byte received
    output wire       valid,          // one clock: `data` is a new byte
    output wire       frame_error     // one clock: a byte was dropped (stop bit 0)
);
    initial begin
        if (CLKS_PER_BIT < 4) $error("%m: CLKS_PER_BIT must be at least 4");
    end

    localparam integer CW = $clog2(CLKS_PER_BIT + 1);
    localparam integer  HALF_CLOCKS = CLKS_PER_BIT / 2 - 1;
    localparam integer  FULL_CLOCKS = CLKS_PER_BIT - 1;
    localparam [CW-1:0] HALF = HALF_CLOCKS[CW-1:0];
    localparam [CW-1:0] FULL = FULL_CLOCKS[CW-1:0];

    localparam [2:0] IDLE = 3'd0, START = 3'd1, DATA = 3'd2, STOP = 3'd3, BREAK = 3'd4;

    reg [1:0]    sync_q;             // synchronizer: sync_q[1] is the line as seen here
    reg [2:0]    state_q;
    reg [CW-1:0] count_q;            // clocks left to the next sample
    reg [2:0]    bit_q;              // data bit being received
    reg [7:0]    shift_q;
    reg [7:0]    data_q;
    reg          valid_q, error_q;

    assign data        = data_q;
    assign valid       = valid_q;
    assign frame_error = error_q;

    wire line = sync_q[1];
    wire due  = count_q == {CW{1'b0}};

    always @(posedge clk) begin
        if (rst) begin
            sync_q  <= 2'b11;
            state_q <= IDLE;
            count_q <= {CW{1'b0}};
            bit_q   <= 3'd0;
            shift_q <= 8'd0;
            data_q  <= 8'd0;
            valid_q <= 1'b0;
            error_q <= 1'b0;
        end else begin
            sync_q  <= {sync_q[0], rx};
            valid_q <= 1'b0;
            error_q <= 1'b0;
            if (!due)
                count_q <= count_q - 1'b1;
            case (state_q)
                IDLE:
                    if (!line) begin
                        state_q <= START;
                        count_q <= HALF;
                    end
                START:
                    if (due) begin
                        if (line) begin
                            state_q <= IDLE;            // a glitch, not a start bit
                        end else begin
                            state_q <= DATA;
                            count_q <= FULL;
                            bit_q   <= 3'd0;
                        end
                    end
                DATA:
                    if (due) begin
                        shift_q <= {line, shift_q[7:1]};
                        count_q <= FULL;
                        bit_q   <= bit_q + 1'b1;
                        if (bit_q == 3'd7)
                            state_q <= STOP;
                    end
                STOP:
                    if (due) begin
                        if (line) begin
                            data_q  <= shift_q;
                            valid_q <= 1'b1;
                            state_q <= IDLE;
                        end else begin
                            error_q <= 1'b1;
                            state_q <= BREAK;
                        end
                    end
                default:                                // BREAK: wait for the idle line
                    if (line)
                        state_q <= IDLE;
            endcase
        end
    end
endmodule
`default_nettype wire
