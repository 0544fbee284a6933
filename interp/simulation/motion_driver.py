# SPDX-License-Identifier: Apache-2.0
"""cocotb test module behind `interp gcode`: feeds commands to rtl/motion_top.v.

The job comes in $INTERP_JOB as JSON: the commands (ports of
interp.models.motion.Command), the output-stage timing and the output file.
It writes, as JSON, the drive's pulses (cycle, step bits, dir bits at each
rising edge), the error strobes (cycle, code), the final position and the
cycle count.
"""
import json
import os

import cocotb
from cocotb.triggers import FallingEdge

from ..testing.tbkit import TB, read

IDLE = {"rst": 0, "cmd_valid": 0, "hold": 0, "cmd_kind": 0, "cmd_plane": 0, "cmd_feed": 0,
        **{f"cmd_{f}": 0 for f in "xyzijkl"}}


def bits(dut, prefix: str) -> int:
    return sum(int(getattr(dut, f"{prefix}_{a}").value) << n for n, a in enumerate("xyz"))


@cocotb.test()
async def run_commands(dut):
    job = json.loads(os.environ["INTERP_JOB"])
    timing = job["timing"]
    tb = TB(dut)
    await tb.reset({**IDLE, **timing})
    pending = list(job["commands"])
    pulses, errors = [], []
    prev_step, cycle = 0, 0
    while True:
        push = bool(pending) and not int(dut.cmd_full.value)
        tb.drive({**pending.pop(0), "cmd_valid": 1} if push else {"cmd_valid": 0})
        await FallingEdge(dut.clk)
        cycle += 1
        step, dirs = bits(dut, "step"), bits(dut, "dir")
        if step & ~prev_step:
            pulses.append((cycle, step & ~prev_step, dirs))
        prev_step = step
        if int(dut.error.value):
            errors.append((cycle, int(dut.error_code.value)))
        if not pending and not push and not int(dut.busy.value):
            break
        if cycle > job["max_cycles"]:
            raise RuntimeError(f"motion_top not done after {cycle} cycles")
    with open(job["out"], "w") as f:
        json.dump({"pulses": pulses, "errors": errors, "cycles": cycle,
                   "position": [read(dut, f"pos_{a}", signed=True) for a in "xyz"]}, f)
