// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Self-running sweep for tb/circ_su1665343 (test_sweep) and `make bench`:
// every R in +rlo .. +rhi from (R, 0) at full speed, one line per R written
// to +out=<file>:  "R path x y cycles", path in {Y, X, D}, (x, y) the end
// point, cycles the `done` sample's cycle (cycle 0 = start), sampled at the
// falling edge like the cocotb benches.
module sweep_su1665343;
`ifdef SWEEP_WIDTH
    localparam integer WIDTH = `SWEEP_WIDTH;
`else
    localparam integer WIDTH = 12;
`endif
    reg clk = 1'b0;
    reg rst = 1'b1;
    reg start = 1'b0;
    reg [WIDTH-1:0] r = {WIDTH{1'b0}};
    wire step_x, step_y, dir_x, dir_y, busy, done, error;
    integer rlo, rhi, radius, fd, cycles, x, y, total_cycles, total_steps;
    reg [8*512-1:0] out;

    circ_su1665343 #(.WIDTH(WIDTH)) dut (
        .clk(clk), .rst(rst), .start(start), .tick(1'b1), .r(r), .x0(r), .y0({WIDTH{1'b0}}),
        .step_x(step_x), .step_y(step_y), .dir_x(dir_x), .dir_y(dir_y),
        .busy(busy), .done(done), .error(error)
    );

    always #5 clk = ~clk;

    initial begin
        if (!$value$plusargs("rlo=%d", rlo)) rlo = 1;
        if (!$value$plusargs("rhi=%d", rhi)) rhi = 2000;
        if (!$value$plusargs("out=%s", out)) out = "sweep_su1665343.txt";
        fd = $fopen(out, "w");
        total_cycles = 0;
        total_steps = 0;
        repeat (2) @(negedge clk);
        rst = 1'b0;
        for (radius = rlo; radius <= rhi; radius = radius + 1) begin
            r = radius[WIDTH-1:0];
            start = 1'b1;
            x = radius;
            y = 0;
            cycles = 0;
            $fwrite(fd, "%0d ", radius);
            @(negedge clk);
            start = 1'b0;
            cycles = 1;
            while (!done && !error) begin
                if (step_x || step_y) begin
                    $fwrite(fd, "%s", step_x && step_y ? "D" : (step_x ? "X" : "Y"));
                    x = x - (step_x ? 1 : 0);
                    y = y + (step_y ? 1 : 0);
                    total_steps = total_steps + 1;
                end
                @(negedge clk);
                cycles = cycles + 1;
            end
            $fwrite(fd, " %0d %0d %0d\n", x, y, cycles);
            total_cycles = total_cycles + cycles;
        end
        $fclose(fd);
        $display("cycles=%0d steps=%0d", total_cycles, total_steps);
        $finish;
    end
endmodule
`default_nettype wire
