# SPDX-License-Identifier: Apache-2.0
"""The path-speed profile generator (rtl/speed_ramp.v) through its cycle model.

Rest-to-rest moves at the bench widths (FEED_W 16, NW 16, PF 12): the clocks the
generator takes against the ideal continuous trapezoid (or triangle) with the same
acceleration p A / 2^bs and cruise speed, the crawl at one quantum before the stop
against its bound 2/p + 2 blocks; feed-hold stop distances against v^2 / (2 a);
the look-ahead's set-up latency.

  python -m interp.benchmarks.speed_ramp
"""
from __future__ import annotations

import math

from ..gcode import compile as cli
from ..models.speed_ramp import BLOCK_SHIFT_MIN, Segment, SpeedRamp, run_profile, segment_budget

BENCH = {"feed_w": 16, "nw": 16, "pf": 12, "len_w": 34, "zw": 48}
PF = BENCH["pf"]
CASES = [  # quantum A, block_shift, rate p * 2^PF, cruise quanta, length in clocks at cruise
    (16, 2, 1 << PF, 60, 1600), (16, 2, 1 << PF, 60, 160), (3, 3, 3000, 100, 3200),
    (1, 4, 1 << PF - 3, 40, 8000), (50, 2, 777, 120, 12000)]


def ideal_clocks(length: float, v: float, a: float) -> float:
    """Rest to rest along `length` with speed cap v and acceleration a (continuous)."""
    if v * v / a >= length:                       # a triangle
        return 2 * math.sqrt(length / a)
    return length / v + v / a


def move_rows():
    rows = []
    for quantum, shift, rate, quanta, clocks in CASES:
        feed = quanta * quantum
        length = feed * clocks
        seg = Segment(feed, feed, 0, rate, length, segment_budget(rate, length, quantum, shift))
        samples = run_profile([seg], widths=BENCH, quantum=quantum, block_shift=shift)
        moving = [s for s in samples if s["speed"]]
        ns = [s["n"] for s in samples]
        top = max((i for i, n in enumerate(ns) if n >= 2), default=0)
        crawl = sum(1 for n in ns[top:] if n == 1)
        p = rate / (1 << PF)
        a = p * quantum / (1 << shift)
        ideal = ideal_clocks(length, feed, a)
        rows.append([quantum, shift, f"{p:.3f}", feed, length, len(moving), f"{ideal:.0f}",
                     f"{(len(moving) - ideal) / ideal * 100:+.2f}", max(ns), crawl,
                     f"{(2 / p + 2) * (1 << shift):.0f}"])
    return rows


def hold_rows():
    rows = []
    for quantum, shift, rate, quanta in [(16, 2, 1 << PF, 60), (3, 3, 3000, 100), (50, 2, 777, 120)]:
        feed = quanta * quantum
        length = feed * 20000
        seg = Segment(feed, feed, 0, rate, length, segment_budget(rate, length, quantum, shift))
        at = 8000
        samples = run_profile([seg], widths=BENCH, quantum=quantum, block_shift=shift,
                              controls=[(at, "hold", 1), (at + 6000, "resume", 0)])
        v0 = samples[at]["speed"]                  # the first clock with hold high
        stop = next(i for i in range(at, len(samples)) if samples[i]["stopped"])
        travel = sum(s["speed"] for s in samples[at:stop])
        p = rate / (1 << PF)
        a = p * quantum / (1 << shift)
        rows.append([quantum, shift, f"{p:.3f}", v0, travel, f"{v0 * v0 / (2 * a):.0f}",
                     f"{travel / (v0 * v0 / (2 * a)):.3f}", stop - at])
    return rows


def latency_rows():
    rows = []
    for name, widths in (("bench", BENCH), ("cli", {"feed_w": cli.FEED_W, "nw": cli.NW, "pf": cli.PF,
                                                   "len_w": cli.LEN_W, "zw": cli.ZW})):
        model = SpeedRamp(**widths)
        seg = Segment(100, 100, 0, 1 << widths["pf"], 100 * 50, 0)
        inputs = {**seg.ports(), "speed_quantum": 1, "block_shift": BLOCK_SHIFT_MIN, "override": 100, "hold": 0}
        clocks = 0
        while not model.next_pop:
            model.clock(inputs)
            clocks += 1
        rows.append([name, widths["nw"], clocks, widths["nw"], 8 + 1])
    return rows


def tables(quick: bool = False):
    return [
        ("speed_ramp: rest-to-rest moves against the continuous trapezoid",
         ["A", "bs", "p", "v_c", "length", "clocks", "ideal", "over %", "n max", "crawl", "bound"],
         move_rows()),
        ("speed_ramp: feed hold at speed v0, travel to `stopped` against v0^2 / 2a",
         ["A", "bs", "p", "v0", "travel", "v0^2/2a", "ratio", "clocks"], hold_rows()),
        ("speed_ramp: a move at the head to its start (look-ahead set-up)",
         ["build", "NW", "clocks to load", "refinement clocks", "cap product clocks"],
         latency_rows()),
    ]


if __name__ == "__main__":
    for title, header, body in tables():
        print(title)
        print("  ".join(f"{h:>9}" for h in header))
        for row in body:
            print("  ".join(f"{str(c):>9}" for c in row))
        print()
