# SPDX-License-Identifier: Apache-2.0
"""Motion subsystem figures, measured on rtl/motion_top.v with Icarus (the benches' build,
W = 16, FRAC = 16, speed quantum A = 64 path units per clock = 1/1024 step per clock).

  * cruise path speed vs programmed feed for axial, diagonal, 3-axis and mixed lines
    (the middle third of a long line, after the acceleration);
  * the trapezoid: the time of a line vs the ideal v_c^2 / a + L / v_c, S-curve too;
  * feed hold: the steps after the hold until `stopped` vs the ideal v^2 / (2 a);
  * maximum step rate of the output stage (steps per clock) at several timings.
"""
from __future__ import annotations

import math

from ..models.motion import DWELL, LINE, Command, queue_steps
from ..models.profile import profile_for
from ..models.speed_ramp import BLOCK_SHIFT_MIN
from ..simulation.motion_build import FEED_MAX, FRAC, PF, QUANTUM, simulate

MOVES = [("axial", (120, 0, 0)), ("diagonal", (120, 120, 0)), ("3-axis", (120, 120, 120)),
         ("mixed 2-axis", (120, 50, 0)), ("mixed 3-axis", (120, -70, 30))]
FAST = {"pulse_width": 1, "setup": 0, "hold_time": 0}
ONE = 1 << FRAC


def settings(block_shift: int = BLOCK_SHIFT_MIN, jerk_shift: int = 0) -> dict:
    return {"speed_quantum": QUANTUM, "block_shift": block_shift, "jerk_shift": jerk_shift, "override": 100}


def profiled(cmds, accel: float = QUANTUM, block_shift: int = BLOCK_SHIFT_MIN):
    return profile_for(cmds, quantum=QUANTUM, accel=accel, frac=FRAC, pf=PF, block_shift=block_shift,
                       feed_w=16, feed_max=FEED_MAX)


def segments(result, counts):
    """Split the drive's pulses into the commands' steps (counts = steps per command)."""
    pulses, out = result["pulses"], []
    for n in counts:
        out.append(pulses[:n])
        pulses = pulses[n:]
    return out


def speed_table(quick: bool):
    feeds = [ONE >> 2, ONE // 10] if quick else [ONE >> 2, ONE // 10, ONE // 37]
    cmds, rows_meta = [], []
    for feed in feeds:
        for name, move in MOVES:
            cmds += [Command(LINE, feed, *move), Command(DWELL, 0, 5)]
            rows_meta.append((name, move, feed))
    cmds = profiled(cmds)
    result = simulate(cmds, "icarus", FAST, settings=settings())
    counts = [len(queue_steps([c])[0]) for c in cmds]
    rows = []
    for (name, move, feed), pulses in zip(rows_meta, segments(result, counts)[::2]):
        steps = queue_steps([Command(LINE, feed, *move)])[0]
        lo, hi = len(steps) // 3, 2 * len(steps) // 3
        cycles = pulses[hi][0] - pulses[lo][0]
        step_path = sum(math.sqrt(sum(map(abs, s))) for s in steps[lo:hi])     # intervals measured
        line = math.sqrt(sum(c * c for c in move)) * (hi - lo) / len(steps)
        want = feed / ONE
        got = step_path / cycles
        rows.append([name, str(move), f"{want:.5f}", f"{got:.5f}", f"{100 * (got / want - 1):+.3f}",
                     f"{100 * (line / cycles / want - 1):+.2f}"])
    return ("Cruise path speed vs programmed feed (motion_top, Icarus; middle third of each line)",
            ["move", "(dx, dy, dz)", "feed, steps/clock", "measured along the steps", "error %",
             "along the straight line, error %"], rows)


def profile_table(quick: bool):
    """A 300-step axial line from rest to rest: cycles vs the ideal profile (a triangle here:
    the line is shorter than v^2 / a), and S-curves."""
    n, feed = 300, ONE >> 2
    cases = [(0, 0), (0, 3), (1, 0), (2, 4)] if quick else [(0, 0), (0, 2), (0, 4), (1, 0), (1, 3), (2, 4), (0, 6)]
    rows = []
    for block_shift, jerk_shift in cases:
        accel = QUANTUM / 8
        cmd = profiled([Command(LINE, feed, n, 0, 0)], accel=accel, block_shift=block_shift)[0]
        a = cmd.rate / (1 << PF) * QUANTUM / (1 << block_shift) / ONE        # steps per clock^2
        v = min(feed, (cmd.limit // QUANTUM) * QUANTUM) / ONE
        ideal = v / a + n / v if n >= v * v / a else 2 * math.sqrt(n / a)     # trapezoid, or triangle
        result = simulate([cmd], "icarus", FAST, settings=settings(block_shift, jerk_shift))
        first, last = result["pulses"][0][0], result["pulses"][-1][0]
        jerk_time = (1 << jerk_shift) * (1 << block_shift)
        rows.append([block_shift, jerk_shift, f"{a:.3g}", f"{v:.4f}", f"{ideal:.0f}", f"{ideal + jerk_time:.0f}",
                     result["cycles"], last - first, f"{100 * (result['cycles'] / (ideal + jerk_time) - 1):+.2f}"])
    return ("Trapezoid and S-curve: a 300-step line at feed 0.25 step/clock from rest to rest",
            ["block_shift", "jerk_shift", "a, steps/clock^2", "v_c, steps/clock", "ideal time, clocks",
             "+ the S-curve's 2^J blocks", "cycles (run)", "first to last step", "run vs ideal + 2^J, %"], rows)


def hold_table(quick: bool):
    """Feed hold at cruise: steps from the hold to `stopped` vs v^2 / (2 a) (+ the steps in flight)."""
    rows = []
    feeds = [ONE >> 2, ONE >> 3] if quick else [ONE >> 2, ONE >> 3, ONE >> 4]
    for feed in feeds:
        for accel in (QUANTUM / 4, QUANTUM / 16):
            cmd = profiled([Command(LINE, feed, 2000, 0, 0)], accel=accel)[0]
            a = cmd.rate / (1 << PF) * QUANTUM / ONE
            v = feed / ONE
            when = int(v / a) + 400                              # at cruise
            result = simulate([cmd], "icarus", FAST, settings=settings(),
                              controls=[(when, "hold", 0), (when + 3 * int(v / a) + 200, "resume", 0)])
            hold, stopped, steps = result["hold_stops"][0]
            ideal = v * v / (2 * a)
            rows.append([f"{v:.4f}", f"{a:.3g}", stopped - hold, f"{v / a:.0f}", steps, f"{ideal:.1f}",
                         len(result["pulses"]), result["position"][0]])
    return ("Feed hold at cruise on a 2000-step line: the stop (then resume; no step lost)",
            ["v, steps/clock", "a, steps/clock^2", "cycles to stopped", "ideal v/a", "steps after hold",
             "ideal v^2/(2a)", "pulses in all", "end position"], rows)


def rate_table(quick: bool):
    timings = [(1, 0, 0), (2, 1, 1), (4, 2, 3)] if quick else [(1, 0, 0), (2, 1, 1), (4, 2, 3), (10, 5, 5)]
    rows = []
    for pulse, setup, hold in timings:
        timing = {"pulse_width": pulse, "setup": setup, "hold_time": hold}
        n = 400
        cmds = profiled([Command(LINE, FEED_MAX, n, 0, 0), Command(DWELL, 0, 5),
                         Command(LINE, FEED_MAX, n, n, n), Command(DWELL, 0, 5)], accel=QUANTUM)
        result = simulate(cmds, "icarus", timing, settings=settings())
        axial, _, diag, _ = segments(result, [n, 0, n, 0])
        mid = [p[n // 3: 2 * n // 3] for p in (axial, diag)]
        rate = [(len(p) - 1) / (p[-1][0] - p[0][0]) for p in mid]
        rows.append([pulse, setup, hold, f"{rate[0]:.3f}", f"{rate[1]:.3f}", f"{1 / (pulse + 1):.3f}"])
    return ("Output stage: step rate at cruise, feed 1 step/clock (steps per clock, middle third)",
            ["pulse width", "setup", "hold", "long line, same direction", "3-axis line", "bound 1/(width+1)"], rows)


def tables(quick: bool):
    return [speed_table(quick), profile_table(quick), hold_table(quick), rate_table(quick)]
