# SPDX-License-Identifier: Apache-2.0
"""Native Verilator harness for rtl/motion_top.v: whole G-code jobs without cocotb.

  run_native(commands_path, *, steps_path (None: no file), timing, max_cycles, progress=None, vcd=None)
      -> {"cycles", "position": [x, y, z], "errors": [[cycle, code]],
          "events": [[cycle, code, value]], "steps": rows, "stopped", "pushed",
          "dispatched", "commands", "skipped"}

The command file has one command per line, 10 decimal integers
"kind plane feed x y z i j k l" (write_commands writes one).  The harness
(motion_main.cpp, built once per parameter set by build.py) pushes the
commands whenever cmd_full is low, counts cycles as the cocotb driver
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
from ..runner import RTL
from .build import CLI_PARAMETERS, executable, full_parameters

__all__ = ["CLI_PARAMETERS", "run_native", "run_cocotb_job", "write_commands", "read_commands",
           "timing_values", "executable"]

PROGRESS_LOG2 = 22          # a progress line every 2^22 cycles


def timing_values(timing) -> tuple[int, int, int]:
    """(pulse_width, setup, hold) from a tuple or a dict (hold or hold_time)."""
    if isinstance(timing, Mapping):
        hold = timing["hold"] if "hold" in timing else timing["hold_time"]
        return int(timing["pulse_width"]), int(timing["setup"]), int(hold)
    pulse_width, setup, hold = timing
    return int(pulse_width), int(setup), int(hold)


def command_row(command) -> tuple[int, ...]:
    """The 10 fields of a command: a sequence of 10 integers, or an object with ports()."""
    if hasattr(command, "ports"):
        p = command.ports()
        return (p["cmd_kind"], p.get("cmd_plane", getattr(command, "plane", 0)), p["cmd_feed"],
                *(p[f"cmd_{f}"] for f in "xyzijkl"))
    row = tuple(int(v) for v in command)
    if len(row) != 10:
        raise ValueError(f"a command has 10 fields (kind plane feed x y z i j k l), got {len(row)}")
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
        if len(row) != 10:
            raise UsageError(f"{path} line {number}: want 10 integers \"kind plane feed x y z i j k l\", "
                             f"got \"{line.strip()[:60]}\"")
        rows.append(row)
    return rows


def run_native(commands_path, *, steps_path, timing, max_cycles: int,
               progress: Callable[[int, int, int], None] | None = None, vcd=None,
               parameters: dict | None = None, rtl: Path = RTL, exact: bool = False) -> dict:
    """Run a command file through the native model of motion_top (see the module text).

    `timing`: (pulse_width, setup, hold) cycles, or a dict with those keys (hold or hold_time);
    `progress(cycle, steps, dispatched)` is called every 2^22 cycles while it runs;
    `vcd`: a waveform file (a separate build with tracing); `parameters`: motion_top's
    (default the CLI build's); `exact`: simulate every cycle (no quiet-stretch skipping;
    same results, for cross-checks)."""
    pulse_width, setup, hold = timing_values(timing)
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
               "--exact", "1" if exact else "0"]
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
                   parameters: dict | None = None, progress=None) -> dict:
    """The same job under cocotb (Icarus or Verilator): same files, same result dict.

    `commands`: a command file path, or rows of 10 integers (or objects with ports())."""
    from .cocotb_job import run

    if isinstance(commands, (str, Path)):
        rows = read_commands(commands)
    else:
        rows = [command_row(c) for c in commands]
    return run(rows, sim, timing_values(timing), steps_path or os.devnull, max_cycles, vcd,
               full_parameters(parameters if parameters is not None else CLI_PARAMETERS), progress)
