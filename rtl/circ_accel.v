`default_nettype none
// The lecture's accelerated: octants, diagonal steps (seed 004, SPEC §5),
// first quadrant, clockwise and counter-clockwise.  The datapath is circ_quadrant
// (ACCEL = 1); its header names the lecture's registers, counters and triggers.
module circ_accel #(
    parameter integer WIDTH = 32    // width of the signed coordinate inputs (>= 3)
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             start,
    input  wire             tick,
    input  wire [WIDTH-1:0] x0,     // start point (signed, must be >= 0)
    input  wire [WIDTH-1:0] y0,
    input  wire [WIDTH-1:0] x1,     // end point
    input  wire [WIDTH-1:0] y1,
    input  wire             ccw,    // 1 = counter-clockwise
    output wire             step_x,
    output wire             step_y,
    output wire             dir_x,  // 1 = negative direction
    output wire             dir_y,
    output wire             busy,
    output wire             done,
    output wire             error   // one-cycle strobe instead of `done` for a bad command
);
    initial begin
        if (WIDTH < 3) $error("%m: WIDTH must be at least 3");
    end

    circ_quadrant #(.WIDTH(WIDTH), .ACCEL(1)) u_core (
        .clk(clk), .rst(rst), .start(start), .tick(tick),
        .x0(x0), .y0(y0), .x1(x1), .y1(y1), .ccw(ccw),
        .step_x(step_x), .step_y(step_y), .dir_x(dir_x), .dir_y(dir_y),
        .busy(busy), .done(done), .error(error)
    );
endmodule
`default_nettype wire
