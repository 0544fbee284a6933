// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Synchronous first-in first-out buffer: the command queue of motion_top and
// the store of the lecture's synchronization buffer (step_sync).
// `dout` shows the oldest entry while `valid` is high; `pop` removes it.  A
// `push` and a `pop` in the same cycle are both taken, also when full.  A push
// into a full queue without a pop is refused: nothing stored is touched and
// `overflow` is high in that cycle.
// The entries are a memory with one write port and an asynchronous read, and
// reset does not clear them (they start at zero): synthesis may map them to
// distributed RAM (ECP5) or, the read address being a register, to block RAM
// (iCE40) instead of WIDTH x DEPTH flip-flops and a DEPTH-way read multiplexer.
// While empty, `dout` is zero.
// HEAD_REG 1 keeps the oldest entry in a register as well (WIDTH more flip-flops):
// the memory is read a clock ahead, at the entry after the oldest, so `dout` comes
// straight from a flip-flop and the read is off the path of whatever `dout`
// feeds.  `dout` is the same in every cycle (formal/sync_fifo.sby proves either
// form's `dout` equal to mem[rd_q] while valid, zero while empty).
module sync_fifo #(
    parameter integer WIDTH    = 8,    // bits per entry (>= 1)
    parameter integer DEPTH    = 4,    // number of entries (>= 1, any value)
    parameter integer LW       = 3,    // width of `level` (2^LW > DEPTH)
    parameter integer HEAD_REG = 0     // 1: `dout` from a register (see above); 0 or 1
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             push,
    input  wire [WIDTH-1:0] din,
    input  wire             pop,        // ignored while empty
    output wire [WIDTH-1:0] dout,       // oldest entry (zero while empty)
    output wire             valid,      // not empty
    output wire             full,
    output wire [LW-1:0]    level,      // entries stored
    output wire             overflow    // push refused this cycle (full, no pop)
);
    initial begin
        if (WIDTH < 1) $error("%m: WIDTH must be at least 1");
        if (DEPTH < 1) $error("%m: DEPTH must be at least 1");
        if (LW < 1 || (1 << LW) <= DEPTH) $error("%m: LW must satisfy 2^LW > DEPTH");
        if (HEAD_REG != 0 && HEAD_REG != 1) $error("%m: HEAD_REG must be 0 or 1");
    end

    localparam integer PW = LW;         // pointers 0 .. DEPTH-1 fit in LW bits

    // Indexed by the full pointer width; only entries 0 .. DEPTH-1 are used.
    reg [WIDTH-1:0] mem [0:(1<<PW)-1];
    reg [PW-1:0]    rd_q, wr_q;
    reg [LW-1:0]    level_q;

    assign valid    = level_q != {LW{1'b0}};
    assign full     = level_q == DEPTH[LW-1:0];
    wire   take     = pop & valid;
    wire   put      = push & (~full | take);
    assign overflow = push & ~put;
    assign level    = level_q;

    function [PW-1:0] next_ptr(input [PW-1:0] p);
        next_ptr = (p == DEPTH[PW-1:0] - 1'b1) ? {PW{1'b0}} : p + 1'b1;
    endfunction

    integer i;
    initial
        for (i = 0; i < (1 << PW); i = i + 1)
            mem[i] = {WIDTH{1'b0}};

    always @(posedge clk)
        if (put & ~rst)
            mem[wr_q] <= din;

    always @(posedge clk) begin
        if (rst) begin
            rd_q    <= {PW{1'b0}};
            wr_q    <= {PW{1'b0}};
            level_q <= {LW{1'b0}};
        end else begin
            if (put)
                wr_q <= next_ptr(wr_q);
            if (take)
                rd_q <= next_ptr(rd_q);
            if (put & ~take)
                level_q <= level_q + 1'b1;
            else if (take & ~put)
                level_q <= level_q - 1'b1;
        end
    end

    generate
        if (HEAD_REG == 0) begin : g_read
            assign dout = valid ? mem[rd_q] : {WIDTH{1'b0}};
        end else begin : g_head
            // head_q = mem[rd_q] while valid (stale while empty: `dout` is gated).  After a
            // take the next oldest is mem[after_q] if a second entry was stored, else the
            // entry pushed now.  (Clearing head_q when the queue empties, instead of the
            // gate, cost 337 LUT4s more on ECP5 at 56 x 2: Yosys kept a wide read mux.)
            reg [PW-1:0]    after_q;     // next_ptr(rd_q), kept so the read address is a flip-flop
            reg [WIDTH-1:0] head_q;
            localparam [LW-1:0] ONE = 1;
            wire second = level_q != ONE;    // with `take` (level >= 1): a second entry stored
            always @(posedge clk) begin
                if (rst) begin
                    after_q <= next_ptr({PW{1'b0}});
                    head_q  <= {WIDTH{1'b0}};
                end else begin
                    if (take)
                        after_q <= next_ptr(after_q);
                    if (take & second)
                        head_q <= mem[after_q];
                    else if ((take | ~valid) & put)
                        head_q <= din;
                end
            end
            assign dout = valid ? head_q : {WIDTH{1'b0}};
`ifdef FORMAL
            always @(*) if (f_reset_seen) assert (after_q == next_ptr(rd_q));
`endif
        end
    endgenerate

`ifdef FORMAL
    // (formal/sync_fifo.sby) after a reset: the level is at most DEPTH, the write
    // pointer is the read pointer plus the level (mod DEPTH), and `dout` is mem[rd_q]
    // while valid, zero while empty, in either read form.
    reg f_reset_seen = 1'b0;
    always @(posedge clk) if (rst) f_reset_seen <= 1'b1;
    wire [LW:0] f_end = {1'b0, rd_q} + {1'b0, level_q};
    always @(*) if (f_reset_seen) begin
        assert (level_q <= DEPTH[LW-1:0]);
        assert (rd_q < DEPTH[PW-1:0] && wr_q < DEPTH[PW-1:0]);
        assert ({1'b0, wr_q} == (f_end >= DEPTH[LW:0] ? f_end - DEPTH[LW:0] : f_end));
        assert (dout == (valid ? mem[rd_q] : {WIDTH{1'b0}}));
    end
`endif
endmodule
`default_nettype wire
