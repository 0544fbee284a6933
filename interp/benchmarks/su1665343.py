# SPDX-License-Identifier: Apache-2.0
"""SU 1665343 figures: cycles per step, steps per quadrant, radial error, simulation speed."""
from __future__ import annotations

import tempfile
from pathlib import Path

from ..models.su1665343 import (CORRECTION_CYCLES, STEP_CYCLES, move_cycles, path_string,
                                radial_error, setup_cycles, steps)
from ..simulation.speed import run_harness

WIDTH = 12          # the sweep harness's counters: R <= 2046


def tables(quick: bool):
    top = 200 if quick else 2000
    rows_quadrant = []
    for r in (1, 12, 100, 1000, 2000):
        path = steps(r)
        s = path_string(path)
        cycles = move_cycles(path, WIDTH)
        rows_quadrant.append([r, len(path), s.count("Y"), s.count("D"), s.count("X"),
                              f"{len(path) / r:.4f}", cycles, f"{cycles / len(path):.3f}",
                              next(p.switch for p in path if p.switch)])
    worst, where, over = 0.0, 0, 0
    for r in range(1, top + 1):
        e = radial_error(r, steps(r))
        over += e >= 0.5
        if e > worst:
            worst, where = e, r
    rows_speed = []
    for sim, rhi in (("icarus", 100 if quick else 300), ("verilator", top)):
        with tempfile.TemporaryDirectory() as tmp:
            got, seconds = run_harness("sweep_su1665343", sim, {"SWEEP_WIDTH": WIDTH},
                                       ["+rlo=1", f"+rhi={rhi}", f"+out={Path(tmp) / 'paths.txt'}"])
            lines = (Path(tmp) / "paths.txt").read_text().split("\n")[:-1]
        same = all(line.split(" ")[1] == path_string(steps(int(line.split(" ")[0]))) for line in lines)
        rows_speed.append([sim, f"1 .. {rhi}", f"{got['steps']:,}", f"{got['cycles']:,}",
                           f"{seconds:.2f}", f"{got['cycles'] / seconds:,.0f}",
                           "yes" if same else "NO"])
    return [
        ("SU 1665343 circular: cycles per step (tick high)",
         ["step", "cycles"],
         [["Y, X or diagonal step (pulse, check, transfer)", STEP_CYCLES],
          ["step with the sector switch (expander 25)", STEP_CYCLES + CORRECTION_CYCLES - 1],
          [f"start -> first step pulse (load former's set-up, 3 WIDTH + 8 at WIDTH {WIDTH}, + 1)",
           setup_cycles(WIDTH) + 1]]),
        (f"SU 1665343 circular: one quadrant from (R, 0) to (0, R), WIDTH {WIDTH}",
         ["R", "steps", "Y", "diagonal", "X", "steps / R", "cycles (start to done)", "cycles / step",
          "switch case"],
         rows_quadrant),
        (f"SU 1665343 circular: radial error, every R = 1 .. {top}",
         ["max radial error (steps)", "at R", "radii with an error >= 0.5"],
         [[f"{worst:.4f}", where, over]]),
        ("SU 1665343 circular: simulation speed (sim/sweep_su1665343.v, every R, no cocotb)",
         ["simulator", "R", "steps", "cycles", "seconds", "cycles/s", "paths = model"], rows_speed),
    ]
