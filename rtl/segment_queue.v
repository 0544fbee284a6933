// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Segment queue of the controller: a byte FIFO of 2^AW bytes in block RAM (one write
// port, one synchronous read port with a read enable, as iCE40 / ECP5 block RAM is
// inferred), first-word-fall-through at its output.
// `in_valid` & `in_ready` writes `in_data`; `out_data` shows the oldest byte while
// `out_valid` is high and `out_ready` takes it.  The byte at the output sits in the
// RAM's read register, so a byte written into an empty queue shows at the output two
// cycles later; after that one byte per cycle flows through.  `level` counts every
// byte held (the one at the output included), `free` = 2^AW - level; `in_ready` is
// low when the queue holds 2^AW bytes.  `free_records` = free / RECORD_BYTES (whole
// command records there is room for), counted as bytes come and go (no divider).
// `flush` empties the queue (like rst).
module segment_queue #(
    parameter integer AW = 12,          // address width: the queue holds 2^AW bytes (4 .. 15)
    parameter integer RECORD_BYTES = 68 // bytes of a record, for free_records (1 .. 2^AW)
) (
    input  wire          clk,
    input  wire          rst,
    input  wire          flush,     // empty the queue now
    input  wire          in_valid,
    input  wire [7:0]    in_data,
    output wire          in_ready,  // room for a byte
    output wire          out_valid, // a byte at the output
    output wire [7:0]    out_data,  // the oldest byte
    input  wire          out_ready, // take the byte at the output
    output reg  [AW:0]   level,     // bytes held (0 .. 2^AW)
    output wire [AW:0]   free,      // 2^AW - level
    output reg  [15:0]   free_records   // free / RECORD_BYTES
);
    initial begin
        if (AW < 4 || AW > 15) $error("%m: AW must be 4 .. 15");
        if (RECORD_BYTES < 1 || RECORD_BYTES > (1 << AW)) $error("%m: RECORD_BYTES must be 1 .. 2^AW");
    end

    localparam [AW:0] SIZE = {1'b1, {AW{1'b0}}};
    localparam integer EMPTY_RECORDS = (1 << AW) / RECORD_BYTES, EMPTY_REST = (1 << AW) % RECORD_BYTES;
    localparam integer LAST_REST = RECORD_BYTES - 1;
    localparam [AW:0] LAST = LAST_REST[AW:0];

    reg  [7:0]  memory [0:(1 << AW) - 1];
    reg  [7:0]  read_data;
    reg  [AW:0] write_pointer, read_pointer;    // one bit more than the address: full vs empty
    reg         held;                           // read_data holds a byte not yet taken

    wire        write  = in_valid & in_ready;
    wire        take   = held & out_ready;
    wire        fetch  = write_pointer != read_pointer & (~held | out_ready);  // a byte in the RAM

    // level = the RAM's bytes + held, counted as bytes come and go, so that in_ready is a flip-flop
    // (level = 2^AW is its top bit alone)
    assign free      = SIZE - level;
    assign in_ready  = ~level[AW];
    assign out_valid = held;
    assign out_data  = read_data;

    // the RAM: written and read in separate always blocks, as the FPGA tools infer it
    always @(posedge clk) begin
        if (write)
            memory[write_pointer[AW-1:0]] <= in_data;
    end

    always @(posedge clk) begin
        if (fetch)
            read_data <= memory[read_pointer[AW-1:0]];
    end

    // free bytes = free_records * RECORD_BYTES + rest
    reg  [AW:0] rest;
    always @(posedge clk) begin
        if (rst | flush) begin
            free_records <= EMPTY_RECORDS[15:0];
            rest         <= EMPTY_REST[AW:0];
        end else if (write & ~take) begin
            if (rest == {(AW+1){1'b0}}) begin
                free_records <= free_records - 1'b1;
                rest         <= LAST;
            end else begin
                rest <= rest - 1'b1;
            end
        end else if (take & ~write) begin
            if (rest == LAST) begin
                free_records <= free_records + 1'b1;
                rest         <= {(AW+1){1'b0}};
            end else begin
                rest <= rest + 1'b1;
            end
        end
    end

    always @(posedge clk) begin
        if (rst | flush) begin
            write_pointer <= {(AW+1){1'b0}};
            read_pointer  <= {(AW+1){1'b0}};
            held          <= 1'b0;
            level         <= {(AW+1){1'b0}};
        end else begin
            if (write & ~take)
                level <= level + 1'b1;
            else if (take & ~write)
                level <= level - 1'b1;
            if (write)
                write_pointer <= write_pointer + 1'b1;
            if (fetch)
                read_pointer <= read_pointer + 1'b1;
            if (fetch)
                held <= 1'b1;
            else if (take)
                held <= 1'b0;
        end
    end
endmodule
`default_nettype wire
