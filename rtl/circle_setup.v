// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Set-up sequencer of a circle command (circ_quadrant, circ_arc): the half-step band
// test of the end point against the circle through the start point, without a
// combinational multiplier.  Four seq_mult instances, two rounds:
//   round 1: x0^2, y0^2, x1^2, y1^2  ->  a = x0^2 + y0^2 (R^2), b = x1^2 + y1^2
//            (|End|^2), d = b - a and -d;
//   round 2: m^2 with m = |d| (multiplier 3), as d^2 from the registered d;
//   band:    |sqrt(b) - sqrt(a)| <= 1/2 (the half-step test)  <=>  d = 0 or
//            (m < 2^(SW/2 - 1) and m^2 <= min(a, b) + (m - 1) div 2),
//            t = min(a, b) + (m - 1) div 2 - m^2 with a carry-save step in front
//            (registered every cycle: its inputs hold from MUL2's last cycle on).
// The parent keeps a, b below 2^(SW-2) by its coordinate range, so a larger m is
// off the band and m^2 and t fit in SW bits.  Sums of SW bits take two cycles, two
// chunks of SW/2 bits with a registered carry (ADD1: a, b; ADD2: d, -d; ADD3: t), each
// sum its own carry register, so a chain ends at a register (no state select behind it).
//
// Timing (states IDLE, PREP, MUL1, ADD1, ADD2, MUL2, ADD3, CHECK): `start` in an
// idle cycle (cycle 0) begins; x0 .. y1 are captured by round 1 in cycle 1 (PREP);
// ADD1 in cycles MW+5, MW+6; ADD2 in MW+7, MW+8; round 2 starts in MW+9, the first
// MUL2 cycle, which also takes min(a, b) (the sign of d is a register by then, not
// the end of a carry chain); ADD3 in 2*MW+13, 2*MW+14; `check` is high in cycle
// 2*MW+15, with on_band valid; idle again in the next cycle.  `start` while busy is
// ignored; `rst` returns to idle at once.
module circle_setup #(
    parameter integer MW    = 33,   // seq_mult operand width (signed inputs; m = |d| fits)
    parameter integer SW    = 66    // sum width: even, MW < SW <= 2*MW
) (
    input  wire            clk,
    input  wire            rst,
    input  wire            start,   // begin a set-up (ignored while busy)
    input  wire [MW-1:0]   x0,      // round 1 operands (signed): a = x0^2 + y0^2
    input  wire [MW-1:0]   y0,
    input  wire [MW-1:0]   x1,      // b = x1^2 + y1^2
    input  wire [MW-1:0]   y1,
    output wire            busy,
    output wire            check,   // one-cycle strobe: on_band valid
    output wire            on_band  // the end point is within half a step of the circle
);
    initial begin
        if (MW < 2) $error("%m: MW must be at least 2");
        if (SW % 2 != 0 || SW <= MW || SW > 2 * MW) $error("%m: SW out of range");
    end

    localparam integer SK = SW / 2;         // chunk
    localparam integer PW = 2 * MW;         // seq_mult product
    localparam [2:0] IDLE = 3'd0, PREP = 3'd1, MUL1 = 3'd2, ADD1 = 3'd3, ADD2 = 3'd4, MUL2 = 3'd5,
                     ADD3 = 3'd6, CHECK = 3'd7;

    reg  [2:0]    state_q;
    reg           idle_q;                   // state IDLE, as a flag of its own (the start's path)
    reg           sub_q;                    // second cycle of a two-cycle sum
    reg           check_q;                  // state CHECK, as a flag of its own
    reg  [SW-1:0] a_q, b_q;                 // R^2, |End|^2
    reg  [SW-1:0] s_q;                      // min(a, b) (a register of its own: a_q's input is a sum)
    reg  [SW-1:0] d_q, nd_q, t_q;           // b - a, a - b, min(a, b) + (m - 1) div 2 - m^2
    reg           ca_q, cb_q, cd_q, cnd_q, ct_q;   // chunk carries of the two-cycle sums
    reg  [SW-1:0] tcs_s_q, tcs_c_q;         // ADD3's carry-save step (sum, carries)
    reg  [MW-1:0] m_q, h_q;                 // m = |d|, (m - 1) div 2
    reg           dzero_q, msmall_q;
    // Their first stage, zero flags of 4-bit groups (d, and the bits of d and -d that
    // msmall reads), then ANDs of four: the wide compares take three cycles of MUL2 (d
    // holds still in it).
    localparam integer NZ = (SW + 3) / 4, NS = (SK + 4) / 4, NZ2 = (NZ + 3) / 4;
    reg  [NZ-1:0] dz_q;
    reg  [NS-1:0] dhz_q, ndhz_q;
    reg  [NZ2-1:0] dz2_q, dhz2_q, ndhz2_q;  // their second stage: ANDs of four
    function automatic [NZ2-1:0] all_groups(input [NZ-1:0] f);
        integer i;
        reg [4*NZ2-1:0] w;
        begin
            w = {{(4*NZ2-NZ){1'b1}}, f};
            for (i = 0; i < NZ2; i = i + 1) all_groups[i] = &w[4*i +: 4];
        end
    endfunction
    function automatic [NZ-1:0] zero_groups(input [SW-1:0] x);
        integer i;
        reg [4*NZ-1:0] w;
        begin
            w = {{(4*NZ-SW){1'b0}}, x};
            for (i = 0; i < NZ; i = i + 1) zero_groups[i] = w[4*i +: 4] == 4'd0;
        end
    endfunction
    // (continuous assignments: simulators evaluate the functions only when d changes)
    wire [NZ-1:0] dz_w = zero_groups(d_q);
    wire [NZ-1:0] dhz_w = zero_groups({{(SK-1){1'b0}}, d_q[SW-1:SK-1]}),
                  ndhz_w = zero_groups({{(SK-1){1'b0}}, nd_q[SW-1:SK-1]});

    wire go = idle_q && start;
    assign busy = !idle_q;
    assign check = check_q;
    assign on_band = dzero_q || (msmall_q && !t_q[SW-1]);

    // ---- multipliers: round 1 in PREP, round 2 in MUL2's first cycle ----
    wire [MW-1:0] m_abs = d_q[SW-1] ? nd_q[MW-1:0] : d_q[MW-1:0];            // |d|
    // Round 1 in PREP, round 2 in MUL2's first cycle, as registers set on the way in (the
    // starts reach every multiplier's control flags).
    reg           round1_q, round12_q;          // round 1; round 1 or 2
    wire [3*MW-1:0] op1 = {x1, y0, x0};      // round 1 of multipliers 2, 1, 0
    wire [4*PW-1:0] p;                      // products of multipliers 3, 2, 1, 0
    wire          mdone;
    wire [3:0]    mbusy;
    wire [2:0]    mdone_other;
    genvar k;
    generate
        for (k = 0; k < 3; k = k + 1) begin : g_mul
            seq_mult #(.WIDTH(MW)) u_mul (.clk(clk), .rst(rst), .start(round1_q),
                                          .a(op1[k*MW +: MW]), .b(op1[k*MW +: MW]), .busy(mbusy[k]),
                                          .done(mdone_other[k]), .product(p[k*PW +: PW]));
        end
    endgenerate
    // m^2 = d^2: the signed multiplier squares d's low MW bits, which are d itself
    // whenever m^2 matters (m < 2^(SW/2 - 1) <= 2^(MW - 1)), so no |d| select before it.
    // Its operand: y1 until ADD2, d from then on (a register selects: the select fans out).
    reg           sq_d_q;
    wire [MW-1:0] mop3 = sq_d_q ? d_q[MW-1:0] : y1;
    seq_mult #(.WIDTH(MW)) u_mul3 (.clk(clk), .rst(rst), .start(round12_q), .a(mop3), .b(mop3),
                                   .busy(mbusy[3]), .done(mdone), .product(p[3*PW +: PW]));
    wire [SW-1:0] msq = p[3*PW +: SW];

    // Two-cycle sum x + y (difference x - y = x + ~y + 1): the low chunk with its carry
    // in, the high chunk with the low chunk's carry registered the cycle before (chain_add:
    // one chain, or cut in two by iCE40's form).
    wire [SW-1:0] a_w, b_w, d_w, nd_w, t_w;
    wire [4:0]    carry_w;                  // the low chunks' carries out: a, b, d, nd, t
    wire [4:0]    unused_carry;             // the high chunks'
    wire [5*SW-1:0] chunk_x = {tcs_s_q, a_q, b_q, msq, p[0 +: SW]};           // t, nd, d, b, a
    wire [5*SW-1:0] chunk_y = {tcs_c_q, b_q, a_q, p[2*PW +: SW], p[PW +: SW]};
    wire [5*SW-1:0] chunk_s;
    wire [4:0]      high_cin = {ct_q, cnd_q, cd_q, cb_q, ca_q};
    genvar j;
    generate
        for (j = 0; j < 5; j = j + 1) begin : g_sum
            localparam integer SUB = (j == 2 || j == 3) ? 1 : 0;      // ADD2: d, -d
            chain_add #(.WIDTH(SK), .SUBTRACT(SUB)) u_low (
                .a(chunk_x[j*SW +: SK]), .b(chunk_y[j*SW +: SK]), .cin(SUB != 0),
                .sum(chunk_s[j*SW +: SK]), .cout(carry_w[j]));
            chain_add #(.WIDTH(SK), .SUBTRACT(SUB)) u_high (
                .a(chunk_x[j*SW+SK +: SK]), .b(chunk_y[j*SW+SK +: SK]), .cin(high_cin[j]),
                .sum(chunk_s[j*SW+SK +: SK]), .cout(unused_carry[j]));
        end
    endgenerate
    assign {t_w, nd_w, d_w, b_w, a_w} = chunk_s;
    wire [SW-1:0] h_w = {{(SW-MW){1'b0}}, h_q};                               // ADD3: s + h - m^2
    wire [SW-1:0] tcs_s = s_q ^ h_w ^ ~msq;
    wire [SW-1:0] tcs_c = {(s_q[SW-2:0] & h_w[SW-2:0]) | (s_q[SW-2:0] & ~msq[SW-2:0]) |
                           (h_w[SW-2:0] & ~msq[SW-2:0]), 1'b1};               // + 1: -m^2 = ~m^2 + 1

    always @(posedge clk) begin
        tcs_s_q <= tcs_s;
        tcs_c_q <= tcs_c;
        dz_q    <= dz_w;
        dhz_q   <= dhz_w[NS-1:0];
        ndhz_q  <= ndhz_w[NS-1:0];
        dz2_q   <= all_groups(dz_q);
        dhz2_q  <= all_groups({{(NZ-NS){1'b1}}, dhz_q});
        ndhz2_q <= all_groups({{(NZ-NS){1'b1}}, ndhz_q});
    end

    always @(posedge clk) begin
        if (rst) begin
            state_q  <= IDLE;
            idle_q   <= 1'b1;
            check_q  <= 1'b0;
            sq_d_q   <= 1'b0;
            sub_q    <= 1'b0;
            round1_q  <= 1'b0;
            round12_q <= 1'b0;
            a_q      <= {SW{1'b0}};
            b_q      <= {SW{1'b0}};
            s_q      <= {SW{1'b0}};
            d_q      <= {SW{1'b0}};
            nd_q     <= {SW{1'b0}};
            t_q      <= {SW{1'b0}};
            ca_q     <= 1'b0;
            cb_q     <= 1'b0;
            cd_q     <= 1'b0;
            cnd_q    <= 1'b0;
            ct_q     <= 1'b0;
            m_q      <= {MW{1'b0}};
            h_q      <= {MW{1'b0}};
            dzero_q  <= 1'b0;
            msmall_q <= 1'b0;
        end else begin
            sub_q   <= 1'b0;
            check_q <= state_q == ADD3 && sub_q;
            sq_d_q  <= state_q == ADD2 || state_q == MUL2;
            idle_q  <= idle_q ? !start : state_q == CHECK;
            round1_q  <= go;                                   // PREP is next
            round12_q <= go || (state_q == ADD2 && sub_q);     // or MUL2's first cycle
            case (state_q)
                IDLE: if (go) state_q <= PREP;
                PREP: state_q <= MUL1;          // round 1 starts
                MUL1: if (mdone) state_q <= ADD1;
                ADD1: begin
                    a_q     <= a_w;
                    b_q     <= b_w;
                    ca_q    <= carry_w[0];
                    cb_q    <= carry_w[1];
                    sub_q   <= !sub_q;
                    if (sub_q) state_q <= ADD2;
                end
                ADD2: begin
                    d_q     <= d_w;
                    nd_q    <= nd_w;
                    cd_q    <= carry_w[2];
                    cnd_q   <= carry_w[3];
                    sub_q   <= 1'b1;            // in ADD2's second cycle: MUL2's first is next
                    if (sub_q) state_q <= MUL2;
                end
                MUL2: begin                     // round 2 starts in the first cycle
                    if (sub_q) begin
                        s_q <= d_q[SW-1] ? b_q : a_q;           // s = min(a, b)
                        m_q <= m_abs;
                    end
                    h_q      <= (m_q - 1'b1) >> 1;
                    dzero_q  <= &dz2_q;
                    msmall_q <= d_q[SW-1] ? &ndhz2_q : &dhz2_q;
                    if (mdone) state_q <= ADD3;
                end
                ADD3: begin
                    t_q     <= t_w;
                    ct_q    <= carry_w[4];
                    sub_q   <= !sub_q;
                    if (sub_q) state_q <= CHECK;
                end
                default: state_q <= IDLE;       // CHECK
            endcase
        end
    end

    // Busy flags are implied by the state; product bits above SW and nd_q's middle
    // bits (its low part is m, its high part feeds msmall) are not needed.
    wire unused = &{1'b0, unused_carry, mbusy, mdone_other, nd_q, p, dhz_w, ndhz_w};
endmodule
`default_nettype wire
