`default_nettype none
// Linear interpolator after USSR patent SU 1571551 (diagonal + axial steps).
//   counters 1, 2 ......... updown_counter u_ctr1, u_ctr2
//   node 19 (adder 3, mux 12) accum_addsub u_adder + mux2 u_mux
//   node 18 (AND 5, 6) .... sign_analysis u_sign; generator 4 is `tick`
//   node 20 (AND 7, 8, OR 10, 11) increment_former u_route; trigger 15 is x_is_long_q
//   node 21 (AND 9, OR 13, trigger 14) start_stop u_run; AND 9 is `at_end`
// F is held doubled (one extra LSB carries the patent's 0.5).
//
// Timing: `start` in an idle cycle loads the counters, F and trigger 15 from
// X, Y (the patent's inputs 22-26); the next cycle is the "start of frame"
// pulse, which sets trigger 14 and takes 1 from counter 2 (OR 13); from then
// on every cycle with `tick` high makes one step, shown on the registered
// step_x/step_y strobes one cycle later.  `done` is a one-cycle strobe after
// the last step.  `start` while busy is ignored.
module su1571551 #(
    parameter integer WIDTH = 32,   // width of the signed X, Y inputs (>= 2)
    parameter integer EXACT = 1     // 0: faithful (the patent's live counters, expression (5))
                                    // 1: exact (operands held in registers, expression (1))
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             start,
    input  wire             tick,
    input  wire [WIDTH-1:0] x,      // signed X increment
    input  wire [WIDTH-1:0] y,      // signed Y increment
    output reg              step_x,
    output reg              step_y,
    output reg              dir_x,  // 1 = negative direction
    output reg              dir_y,
    output wire             busy,
    output reg              done
);
    initial begin
        if (WIDTH < 2) $error("%m: WIDTH must be at least 2");
        if (EXACT != 0 && EXACT != 1) $error("%m: EXACT must be 0 or 1");
    end

    localparam integer CW = WIDTH + 1;  // counters: 0 .. 2^(WIDTH-1), and -1 for counter 2
    localparam integer FW = WIDTH + 2;  // doubled F: |2F| <= 2^WIDTH

    // ---- load values (the patent's external constants) ----
    wire [WIDTH-1:0] abs_x = x[WIDTH-1] ? -x : x;
    wire [WIDTH-1:0] abs_y = y[WIDTH-1] ? -y : y;
    wire             x_is_long = abs_x >= abs_y;
    wire [CW-1:0]    long_len  = {1'b0, x_is_long ? abs_x : abs_y};
    wire [CW-1:0]    short_len = {1'b0, x_is_long ? abs_y : abs_x};
    wire [CW-1:0]    axial_count = long_len - short_len;            // counter 1: |L - S|
    wire [FW-1:0]    f_initial = {1'b0, long_len} - {short_len, 1'b0};  // 2 * (L/2 - S)

    // ---- node 21: start-stop ----
    wire run, accept, finish, at_end;
    reg  frame_q;           // "start of frame" pulse, the cycle after the load
    reg  x_is_long_q;       // trigger 15
    wire load = start & ~busy;
    start_stop u_run (
        .clk(clk), .rst(rst), .start(frame_q), .stop(at_end),
        .run(run), .accept(accept), .finish(finish)
    );
    assign busy = frame_q | run;

    // ---- node 18: sign analysis ----
    wire f_negative, f_non_negative, axial, diagonal;
    sign_analysis u_sign (
        .tick(tick), .enable(run & ~at_end), .negative(f_negative),
        .pulse_pos(axial), .pulse_neg(diagonal)
    );

    // ---- counters 1, 2 ----
    wire [CW-1:0] ctr1, ctr1_n, ctr2, ctr2_n;
    updown_counter #(.WIDTH(CW)) u_ctr1 (
        .clk(clk), .rst(rst), .load(load | finish), .load_value(load ? axial_count : {CW{1'b0}}),
        .inc(1'b0), .dec(axial), .dec2(1'b0), .q(ctr1), .q_n(ctr1_n)
    );
    updown_counter #(.WIDTH(CW)) u_ctr2 (
        .clk(clk), .rst(rst), .load(load | finish), .load_value(load ? short_len : {CW{1'b0}}),
        .inc(1'b0), .dec(diagonal | frame_q), .dec2(1'b0), .q(ctr2), .q_n(ctr2_n)   // OR 13
    );
    // AND 9: counter 1 all zeros (inverted outputs all ones), counter 2 all ones.
    assign at_end = run & (&ctr1_n) & (&ctr2);

    // ---- node 19: mux 12 + adder 3 ----
    wire [CW-1:0] op_diagonal, op_axial, operand;
    generate
        if (EXACT != 0) begin : g_exact
            // Expression (1): |L - S| and -S held for the whole move.
            reg [CW-1:0] diagonal_q, axial_q;
            always @(posedge clk) begin
                if (rst) begin
                    diagonal_q <= {CW{1'b0}};
                    axial_q    <= {CW{1'b0}};
                end else if (load) begin
                    diagonal_q <= axial_count;
                    axial_q    <= -short_len;
                end
            end
            assign op_diagonal = diagonal_q;
            assign op_axial    = axial_q;
        end else begin : g_faithful
            // Expression (5): counter 1 direct, counter 2 inverted (= -S while
            // counter 2 holds S - 1), live as they count down.
            assign op_diagonal = ctr1;
            assign op_axial    = ctr2_n;
        end
    endgenerate

    mux2 #(.WIDTH(CW)) u_mux (.sel(diagonal), .in0(op_axial), .in1(op_diagonal), .out(operand));

    wire [FW-1:0] f;
    accum_addsub #(.WIDTH(FW)) u_adder (
        .clk(clk), .rst(rst), .clear(finish), .load(load), .load_value(f_initial),
        .add(axial | diagonal), .operand({operand, 1'b0}), .cin(1'b0),
        .f(f), .negative(f_negative), .non_negative(f_non_negative)
    );

    // ---- node 20: increment former and registered outputs ----
    wire inc_x, inc_y;
    increment_former u_route (
        .axial(axial), .diagonal(diagonal), .x_is_long(x_is_long_q),
        .inc_x(inc_x), .inc_y(inc_y)
    );

    always @(posedge clk) begin
        if (rst) begin
            frame_q     <= 1'b0;
            x_is_long_q <= 1'b0;
            dir_x       <= 1'b0;
            dir_y       <= 1'b0;
            step_x      <= 1'b0;
            step_y      <= 1'b0;
            done        <= 1'b0;
        end else begin
            frame_q <= load;
            if (load) begin
                x_is_long_q <= x_is_long;
                dir_x       <= x[WIDTH-1];
                dir_y       <= y[WIDTH-1];
            end else if (finish) begin
                x_is_long_q <= 1'b0;
            end
            step_x <= inc_x;
            step_y <= inc_y;
            done   <= finish;
        end
    end

    // Not every output is used in both modes; f is kept for benches and waves.
    wire unused = &{1'b0, accept, f_non_negative, ctr1, ctr2_n, f};
endmodule
`default_nettype wire
