// SPDX-License-Identifier: Apache-2.0
// Register byte addresses of the controller (a hand-written stand-in with the names of
// the generated file: `python -m interp.regs` writes this file from regs/controller.rdl).
localparam [7:0] REG_ID             = 8'h00;
localparam [7:0] REG_VERSION        = 8'h04;
localparam [7:0] REG_BUILD0         = 8'h08;
localparam [7:0] REG_BUILD1         = 8'h0C;
localparam [7:0] REG_CLOCK_HZ       = 8'h10;
localparam [7:0] REG_QUEUE_SIZE     = 8'h14;
localparam [7:0] REG_STATUS         = 8'h18;
localparam [7:0] REG_ERROR          = 8'h1C;
localparam [7:0] REG_QUEUE_FREE     = 8'h20;
localparam [7:0] REG_POS_X          = 8'h24;
localparam [7:0] REG_POS_Y          = 8'h28;
localparam [7:0] REG_POS_Z          = 8'h2C;
localparam [7:0] REG_PROBE_X        = 8'h30;
localparam [7:0] REG_PROBE_Y        = 8'h34;
localparam [7:0] REG_PROBE_Z        = 8'h38;
localparam [7:0] REG_INPUTS         = 8'h3C;
localparam [7:0] REG_CONTROL        = 8'h40;
localparam [7:0] REG_OVERRIDE       = 8'h44;
localparam [7:0] REG_PULSE_WIDTH    = 8'h48;
localparam [7:0] REG_DIR_SETUP      = 8'h4C;
localparam [7:0] REG_DIR_HOLD       = 8'h50;
localparam [7:0] REG_QUANTUM_LO     = 8'h54;
localparam [7:0] REG_QUANTUM_HI     = 8'h58;
localparam [7:0] REG_MOTION         = 8'h5C;
localparam [7:0] REG_INPUT_INVERT   = 8'h60;
localparam [7:0] REG_SPINDLE_PERIOD = 8'h64;
localparam [7:0] REG_OUTPUTS        = 8'h68;
localparam [7:0] REG_LINK_FRAMES    = 8'h6C;
localparam [7:0] REG_LINK_ERRORS    = 8'h70;
localparam [7:0] REG_CMD_DATA       = 8'h74;
localparam [7:0] REG_EXECUTED       = 8'h78;
