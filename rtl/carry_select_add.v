`default_nettype none
// Carry-select adder: sum = a + b (mod 2^WIDTH) with the carry chain cut in
// two.  The low half and both versions of the high half (carry in 0 and 1)
// are added at the same time; the low half's carry picks one.  The caller
// supplies b's high half plus one (usually a register loaded with b), so the
// two high adders are separate and Yosys does not merge them into one chain
// with a late carry-in.  The low half is the shorter one by default: its
// carry still has to fan out to every high-half mux.  SPLIT = 0 gives one
// plain adder instead (b_high_plus1 unused): better where the carry chain is
// fast and the mux's routing is not (ECP5).
module carry_select_add #(
    parameter integer WIDTH = 34,               // operand width in bits (>= 2)
    parameter integer LOW   = 0,                // bits in the low half (1 .. WIDTH-1); 0: 2/5 of WIDTH
    parameter integer SPLIT = 1                 // 1: carry select; 0: one carry chain
) (
    input  wire [WIDTH-1:0]     a,
    input  wire [WIDTH-1:0]     b,
    // b's high part (above the low part's LO bits) + 1
    input  wire [WIDTH-(LOW != 0 ? LOW : WIDTH < 5 ? 1 : WIDTH * 2 / 5)-1:0] b_high_plus1,
    output wire [WIDTH-1:0]     sum
);
    initial begin
        if (WIDTH < 2) $error("%m: WIDTH must be at least 2");
        if (LOW < 0 || LOW > WIDTH - 1) $error("%m: LOW must be 0 (automatic) or 1 .. WIDTH-1");
        if (SPLIT != 0 && SPLIT != 1) $error("%m: SPLIT must be 0 or 1");
    end

    localparam integer LO = LOW != 0 ? LOW : WIDTH < 5 ? 1 : WIDTH * 2 / 5;
    localparam integer HI = WIDTH - LO;

    generate
        if (SPLIT != 0) begin : g_split
            wire [LO:0]   low    = {1'b0, a[LO-1:0]} + {1'b0, b[LO-1:0]};
            wire [HI-1:0] high_0 = a[WIDTH-1:LO] + b[WIDTH-1:LO];
            wire [HI-1:0] high_1 = a[WIDTH-1:LO] + b_high_plus1;
            assign sum = {low[LO] ? high_1 : high_0, low[LO-1:0]};
        end else begin : g_chain
            assign sum = a + b;
            wire unused = &{1'b0, b_high_plus1};
        end
    endgenerate
`ifdef FORMAL
    always @(*) if (b_high_plus1 == b[WIDTH-1:LO] + 1'b1) assert (sum == a + b);
`endif
endmodule
`default_nettype wire
