// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Waveform dump for Icarus runs: a second root module that dumps the design
// top (`DUMP_TOP`) into the file named by +vcd=<path>. Verilator runs use
// its own --trace instead.
module dump;
    reg [8*512-1:0] path;
    initial begin
        if ($value$plusargs("vcd=%s", path)) begin
            $dumpfile(path);
            $dumpvars(0, `DUMP_TOP);
        end
    end
endmodule
`default_nettype wire
