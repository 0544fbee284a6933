// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Start-stop trigger: set by `start` when idle, reset by the end detector.
// `start` while running is ignored.  `finish` is a one-cycle strobe when the
// trigger resets; it clears the datapath (the patents reset counters and adder).
// SU1571551: node 21 (OR 13, AND 9 is `stop`, trigger 14).  SU1665343: trigger 4.
module start_stop (
    input  wire clk,
    input  wire rst,
    input  wire start,      // "start of frame"
    input  wire stop,       // end detector (AND 9)
    output wire run,        // trigger state
    output wire accept,     // start taken this cycle (trigger was idle)
    output wire finish      // stop taken this cycle (trigger was running)
);
    reg run_q;
    assign accept = start & ~run_q;
    assign finish = stop & run_q;

    always @(posedge clk) begin
        if (rst)
            run_q <= 1'b0;
        else if (accept)
            run_q <= 1'b1;
        else if (finish)
            run_q <= 1'b0;
    end

    assign run = run_q;
`ifdef FORMAL
    // The trigger is set only by an accepted start and cleared only by a
    // taken stop; start and stop are never both taken (formal/blocks.sby).
    reg f_past_valid = 1'b0;
    always @(posedge clk) f_past_valid <= 1'b1;
    always @(*) assert (!(accept && finish));
    always @(posedge clk) if (f_past_valid && !$past(rst))
        assert (run_q == ($past(accept) | ($past(run_q) & ~$past(finish))));
`endif
endmodule
`default_nettype wire
