# SPDX-License-Identifier: Apache-2.0
"""Motion subsystem figures, measured on rtl/motion_top.v with Icarus.

  * path speed vs programmed feed for axial, diagonal, 3-axis and mixed lines;
  * maximum step rate of the output stage (steps per clock) at several timings.
"""
from __future__ import annotations

import math

from ..simulation.motion_build import FEED_MAX, FRAC, simulate
from ..models.motion import DWELL, LINE, Command, queue_steps

MOVES = [("axial", (120, 0, 0)), ("diagonal", (120, 120, 0)), ("3-axis", (120, 120, 120)),
         ("mixed 2-axis", (120, 50, 0)), ("mixed 3-axis", (120, -70, 30))]
FAST = {"pulse_width": 1, "setup": 0, "hold_time": 0}


def segments(result, counts):
    """Split the drive's pulses into the commands' steps (counts = steps per command)."""
    pulses, out = result["pulses"], []
    for n in counts:
        out.append(pulses[:n])
        pulses = pulses[n:]
    return out


def speed_table(quick: bool):
    feeds = [1 << FRAC >> 2, (1 << FRAC) // 10] if quick else [1 << FRAC >> 2, (1 << FRAC) // 10, (1 << FRAC) // 37]
    cmds, rows_meta = [], []
    for feed in feeds:
        for name, move in MOVES:
            cmds += [Command(LINE, feed, *move), Command(DWELL, 0, 5)]
            rows_meta.append((name, move, feed))
    result = simulate(cmds, "icarus", FAST)
    counts = [len(queue_steps([c])[0]) for c in cmds]
    rows = []
    for (name, move, feed), pulses in zip(rows_meta, segments(result, counts)[::2]):
        steps = queue_steps([Command(LINE, feed, *move)])[0]
        cycles = pulses[-1][0] - pulses[0][0]
        step_path = sum(math.sqrt(sum(map(abs, s))) for s in steps[:-1])    # intervals measured
        line = math.sqrt(sum(c * c for c in move)) * (len(steps) - 1) / len(steps)
        want = feed / (1 << FRAC)
        got = step_path / cycles
        rows.append([name, str(move), f"{want:.5f}", f"{got:.5f}", f"{100 * (got / want - 1):+.3f}",
                     f"{100 * (line / cycles / want - 1):+.2f}"])
    return ("Path speed vs programmed feed (motion_top, Icarus)",
            ["move", "(dx, dy, dz)", "feed, steps/clock", "measured along the steps", "error %",
             "along the straight line, error %"], rows)


def rate_table(quick: bool):
    timings = [(1, 0, 0), (2, 1, 1), (4, 2, 3)] if quick else [(1, 0, 0), (2, 1, 1), (4, 2, 3), (10, 5, 5)]
    rows = []
    for pulse, setup, hold in timings:
        timing = {"pulse_width": pulse, "setup": setup, "hold_time": hold}
        n = 200
        zigzag = [Command(LINE, FEED_MAX, 1 - 2 * (k % 2), 0, 0) for k in range(40)]
        cmds = [Command(LINE, FEED_MAX, n, 0, 0), Command(DWELL, 0, 5),
                Command(LINE, FEED_MAX, n, n, n), Command(DWELL, 0, 5)] + zigzag
        result = simulate(cmds, "icarus", timing)
        axial, _, diag, _, *zz = segments(result, [n, 0, n, 0] + [1] * 40)
        rate = [(len(p) - 1) / (p[-1][0] - p[0][0]) for p in (axial, diag)]
        rises = [p[0][0] for p in zz]
        reverse = (len(rises) - 1) / (rises[-1] - rises[0])
        rows.append([pulse, setup, hold, f"{rate[0]:.3f}", f"{rate[1]:.3f}", f"{reverse:.3f}",
                     f"{1 / (pulse + 1):.3f}"])
    return ("Output stage: maximum step rate at feed 1 step/clock (steps per clock)",
            ["pulse width", "setup", "hold", "long line, same direction", "3-axis line",
             "1-step moves, reversing", "bound 1/(width+1)"], rows)


def tables(quick: bool):
    return [speed_table(quick), rate_table(quick)]
