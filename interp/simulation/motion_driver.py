# SPDX-License-Identifier: Apache-2.0
"""cocotb test module that feeds a job of commands to rtl/motion_top.v.

The job is a JSON file whose path is in $INTERP_JOB_FILE: the commands, the
output-stage timing (port values), max_cycles and the output files.  Commands
are pushed whenever the previous cycle's sample showed cmd_full low (and, with
"push_interval" K in the job, at least K cycles after the previous push); inputs
are driven and outputs sampled at the falling edge, the first cycle after
reset counts 1 (the native harness, interp/simulation/native/motion_main.cpp,
counts the same way).  Two kinds of job:

- "commands" as rows of 16 integers (kind plane feed x y z i j k l limit exit
  rate cost length budget) and a "steps" CSV path
  (interp.simulation.native.run_cocotb_job): writes the steps CSV
  ("cycle,dx,dy,dz", one row per cycle with a rising step edge) and, to "out",
  the native harness's result: cycles, position, errors [[cycle, code]], events
  [[cycle, code, value]], steps, stopped (max_cycles reached), pushed,
  dispatched, commands, hold_stops [[cycle_hold, cycle_stopped, steps]].
- "commands" as port dicts without "steps" (interp gcode): writes to "out"
  the pulses (cycle, step bits, dir bits at each rising edge), the errors, the
  position and the cycle count; max_cycles reached is an error.
Both: "settings" (speed_quantum, block_shift, jerk_shift, override: port values
held the whole run) and "controls" [[cycle, "hold" | "resume" | "override",
value]] applied after the sample of that cycle, as the native harness does.
"""
import json

import cocotb
from cocotb.triggers import FallingEdge

from ..models.speed_ramp import BLOCK_SHIFT_MIN
from ..testing.tbkit import TB, read
from .jobs import job_from_env

FIELDS = ("cmd_kind", "cmd_plane", "cmd_feed", "cmd_x", "cmd_y", "cmd_z", "cmd_i", "cmd_j", "cmd_k", "cmd_l",
          "cmd_limit", "cmd_exit", "cmd_rate", "cmd_cost", "cmd_length", "cmd_budget")
SETTINGS = {"speed_quantum": 1, "block_shift": BLOCK_SHIFT_MIN, "jerk_shift": 0, "override": 100}


def bits(dut, prefix: str) -> int:
    return sum(int(getattr(dut, f"{prefix}_{a}").value) << n for n, a in enumerate("xyz"))


@cocotb.test()
async def run_commands(dut):
    job = job_from_env("INTERP_JOB")
    has_plane, has_events = hasattr(dut, "cmd_plane"), hasattr(dut, "event_valid")
    ports = [f for f in FIELDS if f != "cmd_plane" or has_plane]
    native = "steps" in job
    commands = []
    for c in job["commands"]:
        if native:
            if c[1] and not has_plane:
                raise ValueError(f"plane {c[1]}, but this motion_top has no cmd_plane port")
            commands.append(dict((name, v) for name, v in zip(FIELDS, c) if name in ports))
        else:
            commands.append(c)
    settings = {**SETTINGS, **job.get("settings", {})}
    controls = [tuple(c) for c in job.get("controls", [])]
    tb = TB(dut)
    await tb.reset({"rst": 0, "cmd_valid": 0, "hold": 0, **{p: 0 for p in ports}, **job["timing"], **settings})
    width = len(dut.cmd_x)
    pending, next_index = commands, 0
    pulses, rows, errors, events, stops = [], [], [], [], []
    prev_step, cycle, stopped, next_control, awaiting, hold = 0, 0, False, 0, False, 0
    push_interval, last_push = int(job.get("push_interval", 1)), 0
    steps_file = open(job["steps"], "w") if native else None
    if steps_file:
        steps_file.write("cycle,dx,dy,dz\n")
    try:
        while True:
            while next_control < len(controls) and controls[next_control][0] <= cycle:
                at, kind, value = controls[next_control]
                next_control += 1
                if kind == "override":
                    tb.drive({"override": value})
                    continue
                if kind == "hold" and not hold:
                    stops.append([at, None, len(rows) if native else len(pulses)])
                    awaiting = True
                if kind == "resume":
                    awaiting = False
                hold = int(kind == "hold")
                tb.drive({"hold": hold})
            paced = next_index != 0 and cycle + 1 < last_push + push_interval
            push = next_index < len(pending) and not int(dut.cmd_full.value) and not paced
            if push:
                last_push = cycle + 1
                tb.drive({**pending[next_index], "cmd_valid": 1})
                next_index += 1
            else:
                tb.drive({"cmd_valid": 0})
            await FallingEdge(dut.clk)
            cycle += 1
            step = bits(dut, "step")
            rise = step & ~prev_step
            prev_step = step
            if rise:
                dirs = bits(dut, "dir")
                if steps_file:
                    d = [(-1 if dirs >> k & 1 else 1) if rise >> k & 1 else 0 for k in range(3)]
                    steps_file.write(f"{cycle},{d[0]},{d[1]},{d[2]}\n")
                    rows.append(cycle)
                else:
                    pulses.append((cycle, rise, dirs))
            if int(dut.error.value):
                errors.append((cycle, int(dut.error_code.value)))
            if awaiting and int(dut.stopped.value):
                stops[-1][1] = cycle
                stops[-1][2] = (len(rows) if native else len(pulses)) - stops[-1][2]
                awaiting = False
            if has_events and int(dut.event_valid.value):
                value = int(dut.event_value.value)
                events.append((cycle, int(dut.event_code.value), value - (value >> (width - 1) << width)))
            if next_index == len(pending) and not push and not int(dut.busy.value):
                break
            if native and cycle >= job["max_cycles"]:
                stopped = True
                break
            if not native and cycle > job["max_cycles"]:
                raise RuntimeError(f"motion_top not done after {cycle} cycles")
    finally:
        if steps_file:
            steps_file.close()
    position = [read(dut, f"pos_{a}", signed=True) for a in "xyz"]
    if native:
        dispatched = next_index - int(dut.queue_level.value)
        result = {"cycles": cycle, "position": position, "errors": errors, "events": events,
                  "steps": len(rows), "stopped": stopped, "pushed": next_index, "dispatched": dispatched,
                  "commands": len(pending), "skipped": 0,
                  "hold_stops": [s if s[1] is not None else [s[0], None, None] for s in stops]}
    else:
        result = {"pulses": pulses, "errors": errors, "cycles": cycle, "position": position,
                  "hold_stops": [s if s[1] is not None else [s[0], None, None] for s in stops]}
    with open(job["out"], "w") as f:
        json.dump(result, f)
