# SPDX-License-Identifier: Apache-2.0
"""Simulation speed of whole motion_top jobs: native Verilator harness vs cocotb.

motion_top at the CLI build (W = 32, FRAC = 32), a 50 MHz clock in mind:
  * "F600 contour": a 40 x 20 mm rectangle with 5 mm corner arcs at F600 mm/min,
    100 steps/mm (1 step per 50,000 cycles), 2 us pulses;
  * "rapid 100 kHz": the same at 1 step per 500 cycles;
  * "dense": short lines and arcs at about a step per 2 cycles (no quiet stretches);
  * "dwells": short moves with 0.1 s dwells between them (quiet stretches).
Every job gets bench profiles (interp.models.profile.profile_for): 500 mm/s^2 at
100 steps/mm, the speed quantum 1/64 of the feed.  The native harness runs each
job to the end, skipping the stretches at rest (dwells; the default) and also
cycle by cycle (--exact, capped); the cocotb paths (Python
every cycle) run the first cycles only (stopped at max_cycles).  Wall time
excludes the one-off builds.
"""
from __future__ import annotations

import tempfile
import time
from pathlib import Path

from ..models.motion import Command
from ..models.profile import profile_for
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


def dwells(n: int) -> list[tuple[int, ...]]:
    feed = ONE // 500
    return [row for k in range(n) for row in ((0, 0, feed, 50, k % 7, 0, 0, 0, 0, 0), (4, 0, 0, 5_000_000, 0, 0, 0, 0, 0, 0))]


ACCEL = 500 * 100 / 50e6 ** 2 * ONE     # 500 mm/s^2 at 100 steps/mm and 50 MHz, path units per clock^2


def profiled(rows: list[tuple[int, ...]]) -> tuple[list[tuple[int, ...]], dict]:
    """The rows with bench profiles, and the settings (the quantum 1/64 of the lowest feed)."""
    feeds = [r[2] for r in rows if r[0] < 4 and r[2]]
    quantum = max(1, min(feeds) // 64)
    cmds = profile_for([Command(r[0], r[2], *r[3:10], plane=r[1]) for r in rows], quantum=quantum,
                       accel=max(ACCEL, quantum / (1 << CLI_PARAMETERS["PF"])), frac=CLI_PARAMETERS["FRAC"],
                       pf=CLI_PARAMETERS["PF"], width=CLI_PARAMETERS["W"], feed_w=CLI_PARAMETERS["FEED_W"],
                       feed_max=(1 << CLI_PARAMETERS["FEED_W"]) - 1)
    return [c.row() for c in cmds], {"speed_quantum": quantum}


def jobs(quick: bool):
    return [("F600 contour", contour(ONE // 50_000), SLOW_TIMING),
            ("rapid 100 kHz", contour(ONE // 500) * (1 if quick else 4), SLOW_TIMING),
            ("dense", dense(40 if quick else 400), FAST_TIMING),
            ("dwells", dwells(4 if quick else 20), SLOW_TIMING)]


def _row(sim, name, result, seconds):
    return [name, sim, result["cycles"], result["steps"], "yes" if result["stopped"] else "",
            round(seconds, 2), f"{result['cycles'] / seconds:.3g}", result.get("skipped", 0)]


def speed_table(quick: bool):
    executable(CLI_PARAMETERS)              # the one-off build, outside the timing
    caps = {"exact": 2_000_000 if quick else 20_000_000, "icarus": 20_000 if quick else 100_000,
            "verilator": 50_000 if quick else 400_000}
    sims = [s for s in ("icarus", "verilator") if have_simulator(s)]
    if "FRAC > 28" in (RTL / "motion_top.v").read_text():
        return ("Simulation speed of motion_top jobs", ["note"],
                [[f"motion_top does not take FRAC = {CLI_PARAMETERS['FRAC']} yet (the CLI build)"]])
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for name, commands, timing in jobs(quick):
            path = tmp / "job.txt"
            commands, settings = profiled(commands)
            write_commands(path, commands)
            for label, kwargs in (("native", {}), ("native --exact", {"exact": True})):
                cap = caps["exact"] if kwargs else 10**12
                start = time.perf_counter()
                result = run_native(path, steps_path=tmp / "steps.csv", timing=timing, max_cycles=cap,
                                    settings=settings, **kwargs)
                rows.append(_row(label, name, result, time.perf_counter() - start))
            for sim in sims:
                if sim == "verilator":              # the one-off cocotb build, outside the timing
                    run_cocotb_job([], sim, timing, tmp / "steps.csv", 10)
                start = time.perf_counter()
                result = run_cocotb_job(path, sim, timing, tmp / "steps.csv", caps[sim], settings=settings)
                rows.append(_row(f"{sim} cocotb", name, result, time.perf_counter() - start))
    return (f"Simulation speed of motion_top jobs (CLI build, W = 32, FRAC = {CLI_PARAMETERS['FRAC']})",
            ["job", "simulation", "cycles", "steps", "stopped at max_cycles", "wall s", "cycles/s", "skipped"], rows)


def tables(quick: bool):
    return [speed_table(quick)]
