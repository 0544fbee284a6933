// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Sign-analysis node: passes the generator pulse (`tick`) to one of two
// outputs by the sign of the evaluation function, while the run trigger is set.
// SU1571551: node 18 (AND 5 for F >= 0, AND 6 for F < 0; generator 4 is `tick`).
// SU1665343: AND 2, 3 (and AND 10, 11 with the expander's inhibit as `enable`).
module sign_analysis (
    input  wire tick,       // generator pulse (clock enable)
    input  wire enable,     // run trigger / inhibit
    input  wire negative,   // sign of F
    output wire pulse_pos,  // AND 5: F >= 0
    output wire pulse_neg   // AND 6: F < 0
);
    assign pulse_pos = tick & enable & ~negative;
    assign pulse_neg = tick & enable & negative;
`ifdef FORMAL
    // At most one pulse, only with tick and enable, chosen by the sign.
    always @(*) begin
        assert (!(pulse_pos && pulse_neg));
        assert ((pulse_pos | pulse_neg) == (tick & enable));
        if (pulse_neg) assert (negative);
        if (pulse_pos) assert (!negative);
    end
`endif
endmodule
`default_nettype wire
