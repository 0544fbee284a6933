// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// UART transmitter, 8N1, LSB first: a byte offered on `data` with `valid`
// is taken when `ready` is high and sent as a start bit (0), eight data bits
// and a stop bit (1), each CLKS_PER_BIT clocks long.  `ready` is high while
// the line is idle; the next byte may be taken right after a stop bit, so
// bytes offered back to back leave without a gap.
module uart_tx #(
    parameter integer CLKS_PER_BIT = 104     // clocks per bit = CLK_HZ / BAUD (>= 4)
) (
    input  wire       clk,
    input  wire       rst,
    input  wire [7:0] data,
    input  wire       valid,          // `data` is offered
    output wire       ready,          // the offered byte is taken in this cycle
    output wire       tx              // the serial line (idle high)
);
    initial begin
        if (CLKS_PER_BIT < 4) $error("%m: CLKS_PER_BIT must be at least 4");
    end

    localparam integer CW = $clog2(CLKS_PER_BIT + 1);
    localparam integer  FULL_CLOCKS = CLKS_PER_BIT - 1;
    localparam [CW-1:0] FULL = FULL_CLOCKS[CW-1:0];

    reg [8:0]    shift_q;            // {stop, data} still to send after the current bit
    reg [3:0]    bits_q;             // bits left including the current one (0: idle)
    reg [CW-1:0] count_q;
    reg          tx_q;

    assign ready = bits_q == 4'd0;
    assign tx    = tx_q;

    always @(posedge clk) begin
        if (rst) begin
            shift_q <= 9'h1FF;
            bits_q  <= 4'd0;
            count_q <= {CW{1'b0}};
            tx_q    <= 1'b1;
        end else if (bits_q == 4'd0) begin
            if (valid) begin
                tx_q    <= 1'b0;                    // start bit
                shift_q <= {1'b1, data};
                bits_q  <= 4'd10;
                count_q <= FULL;
            end
        end else if (count_q != {CW{1'b0}}) begin
            count_q <= count_q - 1'b1;
        end else begin
            bits_q <= bits_q - 1'b1;
            if (bits_q != 4'd1) begin
                tx_q    <= shift_q[0];
                shift_q <= {1'b1, shift_q[8:1]};
                count_q <= FULL;
            end else begin
                tx_q <= 1'b1;                       // idle (the stop bit's level)
            end
        end
    end
endmodule
`default_nettype wire
