// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Speed harness for `make bench`: one long SU 1571551 line at full speed.
// Counts cycles and steps; +x=<X> +y=<Y> set the move (defaults 1000000, 377777).
// The core: the production one, lin_exact, with -DBENCH_LIN_EXACT; otherwise
// the patent's circuit su1571551 in the mode -DBENCH_EXACT=0|1 sets.
module bench_su1571551;
    localparam integer WIDTH = 32;
    reg clk = 1'b0;
    reg rst = 1'b1;
    reg start = 1'b0;
    reg [WIDTH-1:0] x = 32'd1000000;
    reg [WIDTH-1:0] y = 32'd377777;
    wire step_x, step_y, dir_x, dir_y, busy, done;
    reg [63:0] cycles = 64'd0, steps_x = 64'd0, steps_y = 64'd0;

`ifdef BENCH_LIN_EXACT
    lin_exact #(.WIDTH(WIDTH)) dut (
`else
    su1571551 #(.WIDTH(WIDTH), .EXACT(`BENCH_EXACT)) dut (
`endif
        .clk(clk), .rst(rst), .start(start), .tick(1'b1), .x(x), .y(y),
        .step_x(step_x), .step_y(step_y), .dir_x(dir_x), .dir_y(dir_y),
        .busy(busy), .done(done)
    );

    always #5 clk = ~clk;

    initial begin
        if (!$value$plusargs("x=%d", x)) x = 32'd1000000;
        if (!$value$plusargs("y=%d", y)) y = 32'd377777;
        repeat (2) @(posedge clk);
        rst <= 1'b0;
        start <= 1'b1;
        @(posedge clk);
        start <= 1'b0;
    end

    always @(posedge clk) begin
        if (!rst) cycles <= cycles + 64'd1;
        if (!rst) begin
            steps_x <= steps_x + {63'd0, step_x};
            steps_y <= steps_y + {63'd0, step_y};
        end
        if (done) begin
            $display("cycles=%0d steps_x=%0d steps_y=%0d", cycles, steps_x, steps_y);
            $finish;
        end
    end
endmodule
`default_nettype wire
