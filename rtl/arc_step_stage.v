// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// The step stage of circ_arc's run loop (arc_stepper): a cycle behind the decision loop,
// it takes the loop's decisions as tokens and keeps the point, the octant and the
// outputs.
//
// The point is kept as D = P - End (End: the end point), which moves by the step's
// vector (registered a cycle ahead from the loop's decision and the octant's steps, so
// that registers feed D's adder); while idle D takes its load value, start - End.  The
// octant (x major, a < 0, b < 0, q > 0) is the start point's while idle; after a step
// into a new octant it changes in the reload's third cycle: q > 0: b turns (TURN);
// q < 0: a and b swap (SWAP), and b turns as well when q reaches 0 (SWAP_TURN).
//
// A step token is the axial step a or the diagonal a + b, unless the end test says it
// is the last step: that one goes to the end point itself (each axis moves by -D, one
// of -1, 0, +1).  The strobes and dir levels are registered together; `fin` comes with
// the last step's strobes and later tokens are dropped.  E (the evaluation function at
// the point, for the benches) is registered with each step; the point P = End + D that
// the benches compare is position_u, position_v (wires, not ports).
module arc_step_stage #(
    parameter integer WIDTH = 32            // circ_arc's coordinate width (>= 6)
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             idle,           // not running (registered): follow the inputs
    input  wire             go,             // the loop decides a step in this cycle
    input  wire             diagonal,       // and it is diagonal
    input  wire             reload_cycle_3, // the new octant loads
    input  wire             swap_turn,      // the reload is a SWAP_TURN
    input  wire [2:0]       first_octant,   // {x major, a < 0, b < 0} of the start point
    input  wire             start_q_negative,
    input  wire [WIDTH:0]   start_u,        // the start point and End (registered)
    input  wire [WIDTH:0]   start_v,
    input  wire [WIDTH:0]   end_u,
    input  wire [WIDTH:0]   end_v,
    input  wire             axial_last,     // arc_end_window's flags
    input  wire             diagonal_last,
    input  wire             offset_u_zero,
    input  wire             offset_v_zero,
    input  wire             offset_u_one,
    input  wire             offset_v_one,
    input  wire [WIDTH+1:0] e_next,         // E after the decided step (for the benches)
    output reg              step_token,     // a step was decided a cycle ago
    output reg              diagonal_token, // and it was diagonal
    output reg              x_major,        // the octant
    output reg              major_negative,
    output reg              minor_negative,
    output wire [2:0]       next_octant,    // the next octant (TURN or SWAP) and SWAP_TURN's
    output wire [2:0]       swap_turn_octant,
    output reg  [WIDTH:0]   offset_u,       // D = P - End
    output reg  [WIDTH:0]   offset_v,
    output reg              step_x,
    output reg              step_y,
    output reg              dir_x,          // 1 = negative direction
    output reg              dir_y,
    output reg              fin             // the last step's strobes are out
);
    initial begin
        if (WIDTH < 6) $error("%m: WIDTH must be at least 6");
    end

    localparam integer UW = WIDTH + 1;
    localparam integer NW = WIDTH + 2;

    reg           finished;                 // the last step is out: later tokens are dropped
    reg           octant_q_positive;        // the octant's q > 0
    reg  [3:0]    new_octant;               // the new octant and its q > 0 (a reload's third cycle)
    reg  [UW-1:0] start_offset_u, start_offset_v;   // start - End (D's load value)
    reg  [UW-1:0] step_u, step_v;           // the decided step's vector
    reg  [NW-1:0] e_value;                  // E (for the benches)
    reg           loaded;                   // loading a cycle ago: start_u, start_v hold P

    function automatic [UW-1:0] unit(input move, negative);      // -1, 0, +1
        unit = {{(UW-1){move && negative}}, move};
    endfunction

    wire loading = idle || rst;
    wire step = step_token && !finished;
    wire last = diagonal_token ? diagonal_last : axial_last;
    // The axial step a, the diagonal step a + b: x, y negative.
    wire x_axial_negative = major_negative, x_diagonal_negative = x_major ? major_negative : minor_negative;
    wire y_axial_negative = major_negative, y_diagonal_negative = x_major ? minor_negative : major_negative;
    // The token's step (at the last step the end point is one step away: D in -1 .. 1 per axis).
    wire move_x = diagonal_token || x_major, move_y = diagonal_token || !x_major;
    wire x_negative = diagonal_token ? x_diagonal_negative : x_axial_negative;
    wire y_negative = diagonal_token ? y_diagonal_negative : y_axial_negative;
    wire act_x = step && (last ? !offset_u_zero : move_x);
    wire act_y = step && (last ? !offset_v_zero : move_y);
    wire negative_x = last ? offset_u_one : x_negative;
    wire negative_y = last ? offset_v_one : y_negative;
    // The next octants: q > 0: b turns; q < 0: a and b swap (and b turns: SWAP_TURN).
    assign next_octant = octant_q_positive ? {x_major, major_negative, !minor_negative}
                                           : {!x_major, minor_negative, major_negative};
    assign swap_turn_octant = {!x_major, minor_negative, !major_negative};

    // D's adder: while idle its load value (mux_add LOAD), else D + the step's vector.
    wire [UW-1:0] offset_u_next, offset_v_next, start_offset_u_w, start_offset_v_w;
    wire [1:0]    unused_carries;
    mux_add #(.WIDTH(UW), .LOAD(1)) u_offset_u_add (
        .a(offset_u), .sel(idle), .c(start_offset_u), .d(step_u), .sum(offset_u_next));
    mux_add #(.WIDTH(UW), .LOAD(1)) u_offset_v_add (
        .a(offset_v), .sel(idle), .c(start_offset_v), .d(step_v), .sum(offset_v_next));
    chain_add #(.WIDTH(UW), .SUBTRACT(1)) u_start_u_add (
        .a(start_u), .b(end_u), .cin(1'b1), .sum(start_offset_u_w), .cout(unused_carries[0]));
    chain_add #(.WIDTH(UW), .SUBTRACT(1)) u_start_v_add (
        .a(start_v), .b(end_v), .cin(1'b1), .sum(start_offset_v_w), .cout(unused_carries[1]));

    // The point the benches compare: the start point while loading, then End + D.
    wire [UW-1:0] position_u = loaded ? start_u : finished ? end_u : end_u + offset_u;
    wire [UW-1:0] position_v = loaded ? start_v : finished ? end_v : end_v + offset_v;

    always @(posedge clk) begin
        if (rst) begin
            step_token <= 1'b0;
            fin        <= 1'b0;
            step_x     <= 1'b0;
            step_y     <= 1'b0;
            dir_x      <= 1'b0;
            dir_y      <= 1'b0;
        end else begin
            step_token <= go;
            fin        <= step && last;
            step_x     <= act_x;
            step_y     <= act_y;
            if (act_x) dir_x <= negative_x;
            if (act_y) dir_y <= negative_y;
        end
    end
    // Data registers without reset: they follow the inputs while not running (or in reset).
    always @(posedge clk) begin
        diagonal_token <= diagonal;
        step_u <= diagonal ? unit(1'b1, x_diagonal_negative) : unit(x_major, x_axial_negative);
        step_v <= diagonal ? unit(1'b1, y_diagonal_negative) : unit(!x_major, y_axial_negative);
        loaded <= loading;
        start_offset_u <= start_offset_u_w;
        start_offset_v <= start_offset_v_w;
        if (idle || step) begin             // (after the last step the point shows End)
            offset_u <= offset_u_next;
            offset_v <= offset_v_next;
        end
        if (loading) begin
            finished <= 1'b0;
            e_value  <= {NW{1'b0}};
        end else if (step) begin
            finished <= last;
            e_value  <= e_next;
        end
        if (idle) begin
            {x_major, major_negative, minor_negative} <= first_octant;
            octant_q_positive <= !start_q_negative;         // q = P.b is never 0
        end else if (reload_cycle_3) begin
            {x_major, major_negative, minor_negative, octant_q_positive} <= new_octant;
        end
        // The new octant, in the reload's third cycle (the kind is found in the first);
        // the step stage's next step comes after the reload.
        new_octant <= {swap_turn ? swap_turn_octant : next_octant, !octant_q_positive && !swap_turn};
    end

    wire unused = &{1'b0, unused_carries, position_u, position_v, e_value};
endmodule
`default_nettype wire
