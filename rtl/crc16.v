// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// CRC-16/CCITT-FALSE of a byte stream, one byte per clock (the UART link's
// frame check): polynomial 0x1021, initial value 0xFFFF, no reflection, no
// final XOR.  `clear` restarts at 0xFFFF (a byte given in the same cycle is
// the first byte of the new message); each `valid` byte is shifted in MSB
// first.  Shifting in a message followed by its own CRC (high byte first)
// leaves `crc` = 0, which is how the receiver checks a frame.
module crc16 (
    input  wire        clk,
    input  wire        rst,
    input  wire        clear,       // start a new message
    input  wire        valid,       // `data` is the next byte of the message
    input  wire [7:0]  data,
    output wire [15:0] crc          // CRC of the bytes since `clear`
);
    localparam [15:0] POLY = 16'h1021;
    localparam [15:0] INIT = 16'hFFFF;

    reg [15:0] crc_q;
    assign crc = crc_q;

    // The CRC after one more byte: eight shifts of the MSB-first LFSR.
    function [15:0] next_crc(input [15:0] value, input [7:0] byte_in);
        integer bit_index;
        reg [15:0] c;
        begin
            c = value ^ {byte_in, 8'h00};
            for (bit_index = 0; bit_index < 8; bit_index = bit_index + 1)
                c = c[15] ? {c[14:0], 1'b0} ^ POLY : {c[14:0], 1'b0};
            next_crc = c;
        end
    endfunction

    wire [15:0] start = clear ? INIT : crc_q;

    always @(posedge clk) begin
        if (rst)
            crc_q <= INIT;
        else if (valid)
            crc_q <= next_crc(start, data);
        else if (clear)
            crc_q <= INIT;
    end
endmodule
`default_nettype wire
