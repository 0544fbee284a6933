// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Delay line of the S-curve filter (jerk_filter) in the speed-setting block of
// the lecture ("БЗС"): a simple dual-port memory of 2^AW words of WIDTH bits,
// one write port and one registered read port, written in the form Yosys maps
// to block RAM on iCE40 (SB_RAM40_4K) and ECP5 (DP16KD): no reset of the
// array, the read data registered under its enable.  A read of the word being
// written in the same clock returns the old word (the filter never relies on
// it).  The array's contents after power-up are unknown: the user masks words
// not yet written.
module code_delay #(
    parameter integer AW    = 6,    // address width: 2^AW words (1 .. 16)
    parameter integer WIDTH = 2     // word width (>= 1)
) (
    input  wire             clk,
    input  wire             write,     // store `data` at `write_address`
    input  wire [AW-1:0]    write_address,
    input  wire [WIDTH-1:0] data,
    input  wire             read,      // load `q` from `read_address`
    input  wire [AW-1:0]    read_address,
    output reg  [WIDTH-1:0] q
);
    initial begin
        if (AW < 1 || AW > 16) $error("%m: AW must be 1 .. 16");
        if (WIDTH < 1) $error("%m: WIDTH must be at least 1");
    end

    reg [WIDTH-1:0] words [0:(1 << AW) - 1];

    always @(posedge clk) begin
        if (write) words[write_address] <= data;
        if (read) q <= words[read_address];
    end
endmodule
`default_nettype wire
