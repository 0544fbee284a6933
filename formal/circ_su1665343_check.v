// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Formal harness of the SU 1665343 circular core (formal/circ_su1665343.sby):
// follows the step/dir outputs from the start point and checks that every
// move from (R, 0), the patent's start, ends at `done` exactly at (0, R); no
// step while idle.  (Start points off the circle by up to a step are taken by
// the core and end when X reaches 0, not necessarily at (0, R): e.g. R = 4
// from (0, 5) is done at once at (0, 5), so those are left out here.)
module circ_su1665343_check #(
    parameter integer WIDTH = 4,    // core width (R <= 2^(WIDTH-1) - 2)
    parameter integer RMAX  = 4     // largest radius tried (bounds the proof's depth)
) (
    input wire             clk,
    input wire             rst,
    input wire             start,
    input wire             tick,
    input wire [WIDTH-1:0] r,
    input wire [WIDTH-1:0] x0,
    input wire [WIDTH-1:0] y0
);
    wire step_x, step_y, dir_x, dir_y, busy, done, error;
    circ_su1665343 #(.WIDTH(WIDTH)) dut (
        .clk(clk), .rst(rst), .start(start), .tick(tick), .r(r), .x0(x0), .y0(y0),
        .step_x(step_x), .step_y(step_y), .dir_x(dir_x), .dir_y(dir_y),
        .busy(busy), .done(done), .error(error)
    );

`ifdef FORMAL
    reg f_past_valid = 1'b0;
    always @(posedge clk) f_past_valid <= 1'b1;
    always @(*) if (!f_past_valid) assume (rst);
    always @(*) if (start) assume (x0 == r && y0 == {WIDTH{1'b0}} && r <= RMAX);

    localparam integer PW = WIDTH + 2;
    reg signed [PW-1:0] pos_x, pos_y, radius;
    always @(posedge clk) begin
        if (rst) begin
            pos_x <= 0; pos_y <= 0; radius <= 0;
        end else if (start && !busy) begin
            pos_x  <= $signed({2'b00, x0});
            pos_y  <= $signed({2'b00, y0});
            radius <= $signed({2'b00, r});
        end else begin
            if (step_x) pos_x <= dir_x ? pos_x - 1 : pos_x + 1;
            if (step_y) pos_y <= dir_y ? pos_y - 1 : pos_y + 1;
        end
    end
    always @(posedge clk) if (f_past_valid && !rst && !$past(rst)) begin
        if (done) assert (pos_x == 0 && pos_y == radius);
        if (step_x || step_y) assert (busy || done);
    end
    wire unused = &{1'b0, error};
`endif
endmodule
`default_nettype wire
