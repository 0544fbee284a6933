// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Coordinate-increment former: routes long- and short-projection pulses to the
// X and Y outputs.  A diagonal step is a short-axis pulse; OR 10/11 add it to
// the long axis so both axes step in the same cycle.
// SU1571551: node 20 (AND 7, 8, OR 10, 11), steered by trigger 15 (|X| >= |Y|).
module increment_former (
    input  wire axial,      // AND 5: step along the long projection only
    input  wire diagonal,   // AND 6: step along both projections
    input  wire x_is_long,  // trigger 15
    output wire inc_x,
    output wire inc_y
);
    wire long_pulse  = axial | diagonal;   // OR 10 / OR 11 on the long axis
    wire short_pulse = diagonal;
    assign inc_x = x_is_long ? long_pulse : short_pulse;   // AND 7 / AND 8
    assign inc_y = x_is_long ? short_pulse : long_pulse;
`ifdef FORMAL
    // The long axis steps on every pulse, the short one on diagonals only.
    always @(*) if (!(axial && diagonal)) begin
        assert ((inc_x | inc_y) == (axial | diagonal));
        assert ((inc_x & inc_y) == diagonal);
        if (axial) assert (x_is_long ? inc_x : inc_y);
    end
`endif
endmodule
`default_nettype wire
