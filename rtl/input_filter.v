// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Input filter of the controller's machine inputs (no patent element: the switches'
// debounce, as the input filters of Mesa's cards): a limit switch or an e-stop line
// that picks up the noise of a spindle or of the motor cables must not stop a job.
//
// A shared prescaler gives a sample strobe every `period` clocks.  Each filtered
// input keeps its level until a new level is seen at SAMPLES (4) samples in a row;
// a sample showing the kept level starts the count again.  So a change that lasts
// 4 x period clocks always passes, one of 3 x period clocks or less never does,
// and a change passes 3 x period + 1 to 4 x period clocks after it reached `raw`.
// period 0 or a clear `mask` bit: that input passes at once (out = raw, no clock),
// and its kept level follows `raw`, so switching the filter on makes no edge.
module input_filter #(
    parameter integer N  = 5,   // inputs (>= 1)
    parameter integer PW = 16   // width of `period` (1 .. 32)
) (
    input  wire          clk,
    input  wire          rst,
    input  wire [PW-1:0] period,   // clocks between two samples; 0: no filter
    input  wire [N-1:0]  mask,     // 1: the input is filtered
    input  wire [N-1:0]  raw,      // synchronized inputs
    output wire [N-1:0]  filtered
);
    initial begin
        if (N < 1) $error("%m: N must be at least 1");
        if (PW < 1 || PW > 32) $error("%m: PW must be 1 .. 32");
    end

    localparam [1:0] LAST = 2'd3;   // SAMPLES - 1: the count of the sample that takes the level

    reg  [PW-1:0]  prescale;        // clocks since the last sample
    reg            sample;          // strobe: sample the inputs in this clock
    reg  [N-1:0]   level;           // the kept levels
    reg  [2*N-1:0] count;           // per input: samples in a row that showed the other level
    wire           off   = period == {PW{1'b0}};
    wire [PW:0]    ahead = {1'b0, prescale} + 1'b1;
    wire           due   = ahead >= {1'b0, period};

    assign filtered = off ? raw : (mask & level) | (~mask & raw);

    always @(posedge clk) begin
        if (rst | off) begin
            prescale <= {PW{1'b0}};
            sample   <= 1'b0;
        end else begin
            prescale <= due ? {PW{1'b0}} : ahead[PW-1:0];
            sample   <= due;
        end
    end

    genvar i;
    generate
        for (i = 0; i < N; i = i + 1) begin : g_input
            wire [1:0] seen = count[2*i +: 2];
            always @(posedge clk) begin
                if (rst | off | ~mask[i]) begin
                    level[i]        <= raw[i];
                    count[2*i +: 2] <= 2'd0;
                end else if (sample) begin
                    if (raw[i] == level[i]) begin
                        count[2*i +: 2] <= 2'd0;
                    end else if (seen == LAST) begin
                        level[i]        <= raw[i];
                        count[2*i +: 2] <= 2'd0;
                    end else begin
                        count[2*i +: 2] <= seen + 2'd1;
                    end
                end
            end
        end
    endgenerate
endmodule
`default_nettype wire
