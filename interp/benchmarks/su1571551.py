# SPDX-License-Identifier: Apache-2.0
"""SU 1571551 figures: cycles per step, deviation from the line, simulation speed."""
from __future__ import annotations

import random

from ..models.su1571551 import MODES, max_deviation, steps
from ..simulation.speed import run_harness

EXHAUSTIVE = 32          # every X, Y in -32 .. 32
SAMPLE_SEED = 1571551


def deviation(mode: str, moves) -> tuple[float, tuple[int, int], int]:
    worst, where, over_half = 0.0, (0, 0), 0
    for x, y in moves:
        d = max_deviation(x, y, steps(x, y, mode))
        over_half += d > 0.5 + 1e-12
        if d > worst:
            worst, where = d, (x, y)
    return worst, where, over_half


def tables(quick: bool):
    r = range(-EXHAUSTIVE, EXHAUSTIVE + 1)
    exhaustive = [(x, y) for x in r for y in r]
    rng = random.Random(SAMPLE_SEED)
    big = 2_000 if quick else 20_000
    sample = [(rng.randint(-big, big), rng.randint(-big, big)) for _ in range(100 if quick else 400)]
    length = 100_000 if quick else 1_000_000
    rows_acc, rows_speed = [], []
    for mode in MODES:
        exact = int(mode == "exact")
        worst, where, over = deviation(mode, exhaustive)
        worst_s, where_s, over_s = deviation(mode, sample)
        differ = sum(steps(x, y, mode) != steps(x, y, "exact") for x, y in exhaustive
                     if x >= 0 and y >= 0) if mode == "faithful" else 0
        # the exact mode also as the production core lin_exact (same cycles, other RTL)
        cores = [(f"su1571551 {mode}", {"BENCH_EXACT": exact})]
        if exact:
            cores.append(("lin_exact", {"BENCH_EXACT": 1, "BENCH_LIN_EXACT": 1}))
        for core, defines in cores:
            for sim in ("icarus", "verilator"):
                got, seconds = run_harness("bench_su1571551", sim, defines,
                                           [f"+x={length}", f"+y={length * 3 // 8}"])
                assert got["steps_x"] == length and got["steps_y"] == length * 3 // 8, got
                rows_speed.append([core, sim, f"{length:,}", f"{got['cycles']:,}", f"{seconds:.2f}",
                                   f"{got['cycles'] / seconds:,.0f}"])
        rows_acc.append([mode, f"{got['cycles'] / length:.6f}", 3,
                         f"{worst:.4f} at {where}", over, f"{worst_s:.4f} at {where_s}", over_s,
                         differ if mode == "faithful" else "-"])
    return [
        ("SU 1571551 linear: speed and accuracy",
         ["mode", "cycles/step (10^6-step line, incl. start)", "start -> first step (cycles)",
          f"max deviation, X, Y in ±{EXHAUSTIVE} (steps)", "moves over 0.5",
          f"max deviation, {len(sample)} random moves up to {big}", "moves over 0.5",
          "first-quadrant moves whose steps differ from (1)"],
         rows_acc),
        ("SU 1571551 linear: simulation speed (sim/bench_su1571551.v, no cocotb)",
         ["core", "simulator", "steps", "cycles", "seconds", "cycles/s"], rows_speed),
    ]
