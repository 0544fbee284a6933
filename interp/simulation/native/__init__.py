# SPDX-License-Identifier: Apache-2.0
"""Native Verilator harness for rtl/motion_top.v: whole G-code jobs without cocotb.

  run_native(commands_path, *, steps_path (None: no file), timing, max_cycles, progress=None, vcd=None,
             settings=None, controls=None)
      -> {"cycles", "position": [x, y, z], "errors": [[cycle, code]],
          "events": [[cycle, code, value]], "steps": rows, "stopped", "pushed",
          "dispatched", "commands", "skipped", "hold_stops": [[cycle_hold, cycle_stopped, steps_after_hold]]}

The command file has one command per line, 16 decimal integers
"kind plane feed x y z i j k l limit exit rate cost length budget" (write_commands
writes one).  `settings`: {"speed_quantum", "block_shift", "jerk_shift", "override"}
(defaults 1, 0, 0, 100); `controls`: [(cycle, "hold" | "resume" | "override", value)],
cycles not decreasing, each applied after the sample of that cycle; hold_stops: for
each hold, the cycle it came, the first cycle `stopped` was high (None if resumed
before) and the step rows in between.  The harness
(motion_main.cpp, built once per parameter set by build.py) pushes the
commands whenever cmd_full is low (and push_interval cycles or more after the
previous push), counts cycles as the cocotb driver
interp/simulation/motion_driver.py does, writes the steps CSV
("cycle,dx,dy,dz") and returns the result.  `stopped` is true when it gave up
at max_cycles (cycles = max_cycles; `pushed` / `dispatched` say how far the
job got), which is not an error of the RTL.  run_cocotb_job runs the same job
on Icarus or Verilator under cocotb and returns the same dict.
"""
from __future__ import annotations

import json
import os
import subprocess
import tempfile
from pathlib import Path
from typing import Callable, Iterable, Mapping

from ...cores import UsageError
from ...models.speed_ramp import BLOCK_SHIFT_MIN
from ..runner import RTL
from .build import CLI_PARAMETERS, executable, full_parameters

__all__ = ["CLI_PARAMETERS", "SETTINGS", "run_native", "run_cocotb_job", "write_commands", "read_commands",
           "timing_values", "settings_values", "control_rows", "executable"]

PROGRESS_LOG2 = 22          # a progress line every 2^22 cycles
NFIELDS = 16
FIELDS_TEXT = "kind plane feed x y z i j k l limit exit rate cost length budget"
SETTINGS = {"speed_quantum": 1, "block_shift": BLOCK_SHIFT_MIN, "jerk_shift": 0, "override": 100}
CONTROLS = ("hold", "resume", "override")


def settings_values(settings) -> tuple[int, int, int, int]:
    """(speed_quantum, block_shift, jerk_shift, override) with the defaults for what is left out."""
    unknown = set(settings or {}) - set(SETTINGS)
    if unknown:
        raise UsageError(f"unknown settings: {', '.join(sorted(unknown))} (know {', '.join(SETTINGS)})")
    s = {**SETTINGS, **(settings or {})}
    return tuple(int(s[k]) for k in SETTINGS)


def control_rows(controls) -> list[tuple[int, str, int]]:
    """The controls checked: (cycle, kind, value), cycles not decreasing."""
    rows, last = [], 0
    for item in controls or ():
        cycle, kind, *rest = item
        value = int(rest[0]) if rest and rest[0] is not None else 0
        if kind not in CONTROLS:
            raise UsageError(f"unknown control {kind!r} (hold, resume, override)")
        if int(cycle) < last:
            raise UsageError("controls must come in cycle order")
        if kind == "override" and not 0 <= value <= 255:
            raise UsageError(f"override {value} is out of 0 .. 255")
        last = int(cycle)
        rows.append((int(cycle), kind, value))
    return rows


def timing_values(timing) -> tuple[int, int, int]:
    """(pulse_width, setup, hold) from a tuple or a dict (hold or hold_time)."""
    if isinstance(timing, Mapping):
        hold = timing["hold"] if "hold" in timing else timing["hold_time"]
        return int(timing["pulse_width"]), int(timing["setup"]), int(hold)
    pulse_width, setup, hold = timing
    return int(pulse_width), int(setup), int(hold)


def command_row(command) -> tuple[int, ...]:
    """The 16 fields of a command: a sequence of 16 integers, or an object with ports()."""
    if hasattr(command, "ports"):
        p = command.ports()
        return (p["cmd_kind"], p.get("cmd_plane", getattr(command, "plane", 0)), p["cmd_feed"],
                *(p[f"cmd_{f}"] for f in "xyzijkl"),
                *(p.get(f"cmd_{f}", 0) for f in ("limit", "exit", "rate", "cost", "length", "budget")))
    row = tuple(int(v) for v in command)
    if len(row) != NFIELDS:
        raise ValueError(f"a command has {NFIELDS} fields ({FIELDS_TEXT}), got {len(row)}")
    return row


def write_commands(path, commands: Iterable) -> int:
    """Write the command file; return the number of commands."""
    n = 0
    with open(path, "w") as f:
        for command in commands:
            f.write(" ".join(str(v) for v in command_row(command)) + "\n")
            n += 1
    return n


def read_commands(path) -> list[tuple[int, ...]]:
    """The command file's rows (for the cocotb path; the native harness reads it itself)."""
    rows = []
    for number, line in enumerate(Path(path).read_text().splitlines(), 1):
        if not line.strip():
            continue
        try:
            row = tuple(int(v) for v in line.split())
        except ValueError:
            row = ()
        if len(row) != NFIELDS:
            raise UsageError(f"{path} line {number}: want {NFIELDS} integers \"{FIELDS_TEXT}\", "
                             f"got \"{line.strip()[:60]}\"")
        rows.append(row)
    return rows


def run_native(commands_path, *, steps_path, timing, max_cycles: int,
               progress: Callable[[int, int, int], None] | None = None, vcd=None,
               parameters: dict | None = None, rtl: Path = RTL, exact: bool = False,
               settings: Mapping | None = None, controls=None, push_interval: int = 1) -> dict:
    """Run a command file through the native model of motion_top (see the module text).

    `timing`: (pulse_width, setup, hold) cycles, or a dict with those keys (hold or hold_time);
    `progress(cycle, steps, dispatched)` is called every 2^22 cycles while it runs;
    `vcd`: a waveform file (a separate build with tracing); `parameters`: motion_top's
    (default the CLI build's); `exact`: simulate every cycle (no quiet-stretch skipping;
    same results, for cross-checks); `settings`, `controls`: see the module text;
    `push_interval`: a command is pushed at least this many cycles after the previous one
    (interp gcode: the controller's record unpacker, interp.link.records.unpack_interval)."""
    pulse_width, setup, hold = timing_values(timing)
    quantum, block_shift, jerk_shift, override = settings_values(settings)
    control_list = control_rows(controls)
    if max_cycles < 0:
        raise UsageError("max_cycles must be >= 0")
    if not Path(commands_path).is_file():
        raise UsageError(f"cannot read the command file {commands_path}")
    exe = executable(parameters if parameters is not None else CLI_PARAMETERS, trace=vcd is not None, rtl=rtl)
    with tempfile.TemporaryDirectory(prefix="interp-native-") as tmp:
        result_path = Path(tmp) / "result.json"
        cmd = [str(exe), "--commands", str(commands_path), "--steps", str(steps_path or os.devnull),
               "--result", str(result_path), "--max-cycles", str(int(max_cycles)),
               "--timing", f"{pulse_width},{setup},{hold}", "--progress-log2", str(PROGRESS_LOG2),
               "--exact", "1" if exact else "0",
               "--settings", f"{quantum},{block_shift},{jerk_shift},{override}",
               "--push-interval", str(int(push_interval))]
        if control_list:
            controls_path = Path(tmp) / "controls.txt"
            controls_path.write_text("".join(f"{c} {k} {v}\n" for c, k, v in control_list))
            cmd += ["--controls", str(controls_path)]
        if vcd is not None:
            cmd += ["--vcd", str(vcd)]
        err_path = Path(tmp) / "stderr"
        with open(err_path, "w") as err:
            proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=err, text=True, bufsize=1)
            for line in proc.stdout:
                words = line.split()
                if progress and len(words) == 4 and words[0] == "progress":
                    progress(int(words[1]), int(words[2]), int(words[3]))
            status = proc.wait()
        message = err_path.read_text().strip()
        if status == 2:
            raise UsageError(message.splitlines()[-1] if message else "the native harness refused its input")
        if status:
            raise RuntimeError(f"the native motion_top harness failed (status {status}): {message[-2000:]}")
        return json.loads(result_path.read_text())


def run_cocotb_job(commands, sim: str, timing, steps_path, max_cycles: int, vcd=None,
                   parameters: dict | None = None, progress=None, settings: Mapping | None = None,
                   controls=None, push_interval: int = 1) -> dict:
    """The same job under cocotb (Icarus or Verilator): same files, same result dict.

    `commands`: a command file path, or rows of 16 integers (or objects with ports())."""
    from .cocotb_job import run

    if isinstance(commands, (str, Path)):
        rows = read_commands(commands)
    else:
        rows = [command_row(c) for c in commands]
    return run(rows, sim, timing_values(timing), steps_path or os.devnull, max_cycles, vcd,
               full_parameters(parameters if parameters is not None else CLI_PARAMETERS), progress,
               dict(zip(SETTINGS, settings_values(settings))), control_rows(controls), int(push_interval))
