# SPDX-License-Identifier: Apache-2.0
"""Simulation speed of whole motion_top jobs: native Verilator harness vs cocotb.

motion_top at the CLI build (W = 32, FRAC = 48), a 50 MHz clock in mind:
  * "F600 contour": a 40 x 20 mm rectangle with 5 mm corner arcs at F600 mm/min,
    100 steps/mm (1 step per 50,000 cycles), 2 us pulses;
  * "rapid 100 kHz": the same at 1 step per 500 cycles;
  * "dense": short lines and arcs at about a step per 2 cycles (no quiet stretches).
The native harness runs each job to the end, skipping quiet stretches (the
default) and also cycle by cycle (--exact, capped); the cocotb paths (Python
every cycle) run the first cycles only (stopped at max_cycles).  Wall time
excludes the one-off builds.
"""
from __future__ import annotations

import tempfile
import time
from pathlib import Path

from ..simulation.native import CLI_PARAMETERS, executable, run_cocotb_job, run_native, write_commands
from ..simulation.runner import RTL, have_simulator

ONE = 1 << CLI_PARAMETERS["FRAC"]
SLOW_TIMING = (100, 50, 50)             # 2 us pulse, 1 us dir setup and hold at 50 MHz
FAST_TIMING = (1, 0, 0)


def contour(feed: int, mm: int = 100) -> list[tuple[int, ...]]:
    """40 x 20 mm rectangle, 5 mm corner radius, counter-clockwise (steps at `mm` per mm)."""
    r, w, h = 5 * mm, 30 * mm, 10 * mm
    return [(0, 0, feed, w, 0, 0, 0, 0, 0, 0), (2, 0, feed, r, r, 0, 0, r, 0, 0),
            (0, 0, feed, 0, h, 0, 0, 0, 0, 0), (2, 0, feed, -r, r, 0, -r, 0, 0, 0),
            (0, 0, feed, -w, 0, 0, 0, 0, 0, 0), (2, 0, feed, -r, -r, 0, 0, -r, 0, 0),
            (0, 0, feed, 0, -h, 0, 0, 0, 0, 0), (2, 0, feed, r, -r, 0, r, 0, 0, 0)]


def dense(n: int) -> list[tuple[int, ...]]:
    feed = ONE // 2
    rows = []
    for k in range(n):
        rows.append((0, 0, feed, 40 + k % 7, -(k % 5) * 9, k % 3, 0, 0, 0, 0))
        rows.append((2, 0, feed, 0, 0, 0, 12 + k % 4, 0, 0, 0))
    return rows


def jobs(quick: bool):
    return [("F600 contour", contour(ONE // 50_000), SLOW_TIMING),
            ("rapid 100 kHz", contour(ONE // 500) * (1 if quick else 4), SLOW_TIMING),
            ("dense", dense(40 if quick else 400), FAST_TIMING)]


def _row(sim, name, result, seconds):
    return [name, sim, result["cycles"], result["steps"], "yes" if result["stopped"] else "",
            round(seconds, 2), f"{result['cycles'] / seconds:.3g}"]


def speed_table(quick: bool):
    executable(CLI_PARAMETERS)              # the one-off build, outside the timing
    caps = {"exact": 2_000_000 if quick else 20_000_000, "icarus": 20_000 if quick else 100_000,
            "verilator": 50_000 if quick else 400_000}
    sims = [s for s in ("icarus", "verilator") if have_simulator(s)]
    if "FRAC > 28" in (RTL / "motion_top.v").read_text():
        return ("Simulation speed of motion_top jobs", ["note"],
                [["motion_top does not take FRAC = 48 yet (the CLI build)"]])
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for name, commands, timing in jobs(quick):
            path = tmp / "job.txt"
            write_commands(path, commands)
            for label, kwargs in (("native", {}), ("native --exact", {"exact": True})):
                cap = caps["exact"] if kwargs else 10**12
                start = time.perf_counter()
                result = run_native(path, steps_path=tmp / "steps.csv", timing=timing, max_cycles=cap, **kwargs)
                rows.append(_row(label, name, result, time.perf_counter() - start))
            for sim in sims:
                if sim == "verilator":              # the one-off cocotb build, outside the timing
                    run_cocotb_job([], sim, timing, tmp / "steps.csv", 10)
                start = time.perf_counter()
                result = run_cocotb_job(path, sim, timing, tmp / "steps.csv", caps[sim])
                rows.append(_row(f"{sim} cocotb", name, result, time.perf_counter() - start))
    return ("Simulation speed of motion_top jobs (CLI build, W = 32, FRAC = 48)",
            ["job", "simulation", "cycles", "steps", "stopped at max_cycles", "wall s", "cycles/s"], rows)


def tables(quick: bool):
    return [speed_table(quick)]
