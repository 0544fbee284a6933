# SPDX-License-Identifier: Apache-2.0
"""The public G-code corpus through `interp gcode`: one Markdown table row per program.

    python -m interp.benchmarks.gcode_corpus [--simulate] [--clock-hz HZ] [--only TEXT] ...

The corpus directory is INTERP_GCODE_CORPUS (the default is CORPUS below, beside the
repository checkout).  Each program runs `interp gcode FILE --check --json` with the default
machine file: lines, run or refused (the one-line reason), whether the end position agrees
with the tests' own reading of the program (interp.testing.gcode_reference, which shares no
code with interp.gcode), moves, arcs, machine time.  With --simulate each program that runs
is also simulated on the RTL (`--steps`, `--events`): clock cycles, wall time, cycles per
second and the motion monitor's verdict.  Every row also gives the program's step events
and the wall time of its --check (interpretation, compilation and the look-ahead plan).  The tests (tests/test_gcode_corpus*.py) use the helpers here.
"""
from __future__ import annotations

import argparse
import contextlib
import io
import json
import math
import os
import re
import sys
import tempfile
import time
import tomllib
from pathlib import Path

from ..testing.gcode_reference import Refused, Result, run

ROOT = Path(__file__).resolve().parents[2]
CORPUS = Path(os.environ.get("INTERP_GCODE_CORPUS", ROOT.parent / "shared" / "gcode"))
MACHINE = ROOT / "interp" / "gcode" / "default_machine.toml"
PROGRAM_SUFFIXES = {".gcode", ".nc", ".ngc", ".tap"}
# Programs that need the front end's two documented Fanuc habits that LinuxCNC refuses
# ("G0 ... G80" in one block; axis words after G80 move in the G0/G1 mode of before the cycle).
# The simulations' clock unless --clock-hz says otherwise: the corpus's machine times (up to
# 50 min) at the default machine's 50 MHz would be 1e11 cycles; steps and events do not
# depend on the clock, the harness's cycles/s hardly.
SIMULATION_HZ = 1e6
FANUC_HABITS = {"helman_simple_mill.gcode", "tap_HeatSunk_drill.tap"}


def corpus_files(corpus: Path = CORPUS) -> list[Path]:
    if not corpus.is_dir():
        return []
    return sorted(p for p in corpus.iterdir() if p.suffix.lower() in PROGRAM_SUFFIXES)


def machine_file(path: Path = MACHINE) -> dict:
    """What the reference needs of the machine file: steps/mm, G28/G30 positions, tools."""
    values = tomllib.loads(path.read_text())
    home = values.get("home", {})
    return {"steps_per_mm": [float(values["axis"][a]["steps_per_mm"]) for a in "xyz"],
            "g28": tuple(home.get("g28", (0, 0, 0))), "g30": tuple(home.get("g30", (0, 0, 0))),
            "tools": {int(n): dict(v) for n, v in values.get("tool", {}).items()}}


def interp_gcode(args: list[str]) -> tuple[int, str, str]:
    """`interp gcode ARGS` in this process: (exit status, stdout, stderr)."""
    from ..cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(["gcode", *args])
    return status, out.getvalue(), err.getvalue()


def reference(path: Path, machine: dict) -> Result:
    """The tests' own reading of the program (raises Refused)."""
    text = path.read_text(encoding="utf-8", errors="surrogateescape")
    return run(text, g28=machine["g28"], g30=machine["g30"], tools=machine["tools"],
               fanuc_g80=path.name in FANUC_HABITS)


def steps_match(steps: int, exact: float) -> bool:
    """`steps` is `exact` rounded (either neighbour when `exact` lies on a half step)."""
    if abs(abs(exact - math.floor(exact)) - 0.5) < 1e-6:
        return steps in (math.floor(exact), math.ceil(exact))
    return steps == round(exact)


def end_agrees(summary: dict, expected: Result, machine: dict) -> bool:
    exact = [mm * spm for mm, spm in zip(expected.machine, machine["steps_per_mm"])]
    return (all(abs(a - b) <= 1e-6 for a, b in zip(summary["end"], expected.work))
            and all(steps_match(s, e) for s, e in zip(summary["end_steps"], exact)))


def row(path: Path, machine: dict, options) -> list[str]:
    text = path.read_bytes()
    lines = text.count(b"\n") + (not text.endswith(b"\n"))
    extra = ["--clock-hz", str(options.clock_hz)] if options.clock_hz else []
    start = time.perf_counter()
    status, out, err = interp_gcode([str(path), "--check", "--json", *extra])
    check_wall = time.perf_counter() - start
    if status != 0:
        reason = (err.strip().splitlines() or [f"exit status {status}"])[-1]
        cells = [path.name, str(lines), f"refused: {reason.replace('|', '/')}", "", "", "", "", "", ""]
        return cells + (["", "", "", ""] if options.simulate else [])
    summary = json.loads(out)
    try:
        correct = "yes" if end_agrees(summary, reference(path, machine), machine) else "**NO**"
    except Refused as error:
        correct = f"reference refuses: {error}"
    cells = [path.name, str(lines), "run", correct, str(summary["moves"]), str(summary["arcs"]),
             str(summary["step_events"]), f"{summary['machine_time_s']:.3f}", f"{check_wall:.2f}"]
    if options.simulate:
        cells += simulate(path, summary, ["--clock-hz", str(options.clock_hz or SIMULATION_HZ)],
                          options)
    return cells


def simulate(path: Path, summary: dict, extra: list[str], options) -> list[str]:
    if summary["machine_time_s"] > options.max_machine_seconds:
        return ["skipped (longer than --max-machine-seconds)", "", "", ""]
    with tempfile.TemporaryDirectory(prefix="gcode_corpus_") as tmp:
        start = time.perf_counter()
        status, out, err = interp_gcode([str(path), *extra, "--steps", f"{tmp}/steps.csv",
                                         "--events", f"{tmp}/events.csv"])
        wall = time.perf_counter() - start
    match = re.search(r"(\d+) clock cycles", out)
    verdict = next((line for line in out.splitlines() if line.startswith("monitor: ")), "monitor: none")
    verdict = "ok" if verdict.startswith("monitor: ok") else verdict.removeprefix("monitor: ").replace("|", "/")
    if status != 0 or not match:
        reason = (err.strip().splitlines() or [f"exit status {status}"])[-1]
        return [f"failed: {reason.replace('|', '/')}", f"{wall:.2f}", "", verdict]
    cycles = int(match.group(1))
    return [str(cycles), f"{wall:.2f}", f"{cycles / wall:.3g}", verdict]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m interp.benchmarks.gcode_corpus",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--simulate", action="store_true", help="also run each program on the RTL")
    parser.add_argument("--clock-hz", type=float,
                        help="controller clock (default: the machine file's; with --simulate, "
                             f"{SIMULATION_HZ:g} Hz for the simulations)")
    parser.add_argument("--only", action="append", default=[], metavar="TEXT",
                        help="only programs whose name contains TEXT (repeatable)")
    parser.add_argument("--max-machine-seconds", type=float, default=300.0, metavar="S",
                        help="with --simulate: skip programs whose machine time exceeds S "
                             "(default 300)")
    options = parser.parse_args(argv)
    files = [p for p in corpus_files()
             if not options.only or any(text in p.name for text in options.only)]
    if not files:
        print(f"gcode_corpus: no programs in {CORPUS} (set INTERP_GCODE_CORPUS)", file=sys.stderr)
        return 2
    machine = machine_file()
    head = ["program", "lines", "result", "end correct", "moves", "arcs", "step events", "machine time (s)",
            "--check wall (s)"]
    if options.simulate:
        head += ["clock cycles", "wall (s)", "cycles/s", "monitor"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for path in files:
        print("| " + " | ".join(row(path, machine, options)) + " |", flush=True)
    if options.simulate:
        print(f"\nSimulated at {options.clock_hz or SIMULATION_HZ:g} Hz (the native harness), "
              f"programs of at most {options.max_machine_seconds:g} s machine time.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
