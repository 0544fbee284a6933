# SPDX-License-Identifier: Apache-2.0
"""Feed precision of `interp gcode`: the path speed at cruise against the programmed F.

Table 1, the cost modes.  At cruise the speed generator's virtual distance grows by
cmd_feed path units a clock and the pacer releases a step event each time it has
covered the event's cost, so a command of N events takes length / feed clocks
(length = the sum of its costs): the mean path speed along the programmed path is

    true length x 2^FRAC / length  x  feed  (path units / clock),

compared with F for moves of every kind, in the compiler's three modes: "true" (the
default: a line's or a helix's events cost its true length / N each; a flat arc's
the lecture's 1, sqrt 2 per 1-, 2-axis step, its speed words scaled by its stepped
length over its true length), "even" (every move's events cost true length / N)
and "lecture" (the lecture's costs everywhere, unscaled: the cruise word is F along the
true path).  The lecture's rule over-charges the mixed steps of a line whose minor axes
move on different steps, so such a line runs slow (-10.5 % for the 3-axis 10:7:3 line).

Table 2, the local speed: the true distance covered by 32 consecutive events over the
distance they are charged, against the move's mean (the models' steps, no simulation).
Evenly charged events run an arc's octant diagonals (diagonal steps) fast and its axis
directions slow, -10 % .. +27 % on a quarter arc; the lecture's costs follow the
stepped path, within cos(pi / 8) .. 1 of its speed, so the scaled default stays within
-3 % .. +6 % on a quarter arc (the planner bounds the axes with that pacing).

Table 3, measured on the RTL (the native Verilator harness, when it is built): the same
moves at 50 kHz (the steps as at 50 MHz in a thousandth of the cycles), the path speed
over the middle half of the run's step events = (the distance along the programmed line or
arc between the step positions there) / (their time).  At 50 kHz the speed quantum A is
large (v = n A with n ~ 1700 quanta at F1000): the cruise is a whole number of quanta,
below F by up to 1 / n (0.04 %); at 50 MHz n is 1000 times larger.  On an arc the true
"even" cost is the AVERAGE path length of its events, so the middle half of a quarter
arc runs +7.9 % fast; the default's is the mean of the stepped path's; the lecture's
costs, unscaled, lose the stepped path's excess length over the arc (-5 %).  Skipped
where the harness is missing.

Table 4, the clock: the cruise word is F in path units per clock rounded to an
integer; its error for F = 1 .. 6000 mm/min at 1, 50, 200 MHz (100 steps/mm).

  python -m interp.benchmarks.feed_accuracy      (also a table of `interp bench`)
"""
from __future__ import annotations

import math

from ..gcode.compile import FRAC, compile_program
from ..gcode.machine import load_machine
from ..gcode.moves import Arc, Line, Program

CLOCKS_HZ = (1e6, 50e6, 200e6)
FEEDS = (1, 10, 100, 1000, 6000)
FEED = 1000.0               # mm/min, for the cost modes
MOVES = {                   # name: (moves in mm; the first starts at the origin)
    "line along X": [Line((0, 0, 0), (50, 0, 0), FEED, 1)],
    "line 2:1 (XY)": [Line((0, 0, 0), (40, 20, 0), FEED, 1)],
    "line 45 deg (XY)": [Line((0, 0, 0), (30, 30, 0), FEED, 1)],
    "3-axis line 10:7:3": [Line((0, 0, 0), (30, 21, 9), FEED, 1)],
    "3-axis line 1:1:1": [Line((0, 0, 0), (20, 20, 20), FEED, 1)],
    "arc r 20, quarter": [Line((0, 0, 0), (20, 0, 0), None, 1),
                          Arc((20, 0, 0), (0, 20, 0), (0, 0, 0), "XY", True, 1, FEED, 2)],
    "helix r 20, 10 mm": [Line((0, 0, 0), (20, 0, 0), None, 1),
                          Arc((20, 0, 0), (0, 20, 10), (0, 0, 0), "XY", True, 1, FEED, 2)],
}


def cruise_speed(moves, costs: str, clock_hz: float = 50e6) -> float:
    """The path speed (mm/min) at cruise along the last command of the program."""
    machine = load_machine(clock_hz=clock_hz)
    out = compile_program(Program(moves), machine, costs=costs)
    c = out.commands[-1]
    true = c.motion.steps * (1 << FRAC)             # path units along the programmed path
    units_per_clock = c.feed * true / c.length
    return units_per_clock / (1 << FRAC) * clock_hz / c.motion.spm * 60


def cost_rows():
    out = []
    for name, moves in MOVES.items():
        true, even, lecture = (cruise_speed(moves, mode) for mode in ("true", "even", "lecture"))
        out.append([name, f"{FEED:g}", f"{true:.6g}", f"{(true - FEED) / FEED * 100:+.2e}",
                    f"{(even - FEED) / FEED * 100:+.2e}", f"{lecture:.6g}", f"{(lecture - FEED) / FEED * 100:+.2f}"])
    return out


WINDOW = 32                 # events of a local speed


def local_range(moves, costs: str) -> tuple[float, float]:
    """(least, largest) local path speed over the mean along the last command: the true
    distance of WINDOW consecutive events (the chord between their step positions) over the
    distance they are charged, times the command's charged length over its true length."""
    import numpy as np

    from ..models.motion import command_steps
    from ..simulation.monitor import event_costs

    out = compile_program(Program(moves), load_machine(), costs=costs)
    c = out.commands[-1]
    steps, _ = command_steps(c, 32)
    position = np.cumsum(np.array(steps, dtype=float), axis=0)
    charged = np.cumsum(event_costs(c.cost, steps))
    local = np.linalg.norm(position[WINDOW:] - position[:-WINDOW], axis=1) / (charged[WINDOW:] - charged[:-WINDOW])
    local *= c.length / (1 << FRAC) / c.motion.steps
    return float(local.min()), float(local.max())


def local_rows():
    out = []
    for name, moves in MOVES.items():
        row = [name]
        for mode in ("true", "even", "lecture"):
            low, high = local_range(moves, mode)
            row.append(f"{(low - 1) * 100:+.1f} .. {(high - 1) * 100:+.1f}")
        out.append(row)
    return out


RTL_CLOCK_HZ = 50e3


def measured_speed(moves, costs: str) -> float | None:
    """The path speed (mm/min) over the middle half of the last command's events on the RTL."""
    try:
        from ..simulation import native
    except ImportError:
        return None
    import tempfile

    import numpy as np

    from ..gcode.compile import write_commands
    from ..simulation.monitor import read_rows

    machine = load_machine(clock_hz=RTL_CLOCK_HZ)
    out = compile_program(Program(moves), machine, costs=costs)
    with tempfile.TemporaryDirectory(prefix="feed_accuracy_") as tmp:
        write_commands(f"{tmp}/c.txt", out.commands)
        t = machine.timing()
        native.run_native(f"{tmp}/c.txt", steps_path=f"{tmp}/s.csv", timing=(t["pulse_width"], t["setup"], t["hold"]),
                          max_cycles=int(100 * out.machine_time_s * RTL_CLOCK_HZ) + 10**6, settings=out.settings,
                          controls=[])
        rows = read_rows(f"{tmp}/s.csv")
    n = out.commands[-1].motion.events
    position = np.cumsum(rows[:, 1:4], axis=0)[-n:] / np.array(machine.steps_per_mm)     # mm
    cycles = rows[-n:, 0].astype(float)
    a, b = n // 4, 3 * n // 4
    return abs(along(moves[-1], position[b]) - along(moves[-1], position[a])) / \
        ((cycles[b] - cycles[a]) / RTL_CLOCK_HZ) * 60


def along(move, point) -> float:
    """The distance (mm) along a line, or along an arc in its plane, of the point nearest `point`."""
    if isinstance(move, Line):
        d = [e - s for e, s in zip(move.end, move.start)]
        length = math.sqrt(sum(c * c for c in d))
        return sum((p - s) * c for p, s, c in zip(point, move.start, d)) / length
    r = math.hypot(move.start[0] - move.centre[0], move.start[1] - move.centre[1])
    return r * math.atan2(point[1] - move.centre[1], point[0] - move.centre[0])


def rtl_rows():
    out = []
    for name, moves in MOVES.items():
        if name.startswith("helix"):
            continue                # (the arcs' rows measure the plane's path already)
        true, even, lecture = (measured_speed(moves, mode) for mode in ("true", "even", "lecture"))
        if true is None:
            return []
        out.append([name, f"{FEED:g}", f"{true:.6g}", f"{(true - FEED) / FEED * 100:+.3f}",
                    f"{(even - FEED) / FEED * 100:+.3f}", f"{lecture:.6g}", f"{(lecture - FEED) / FEED * 100:+.2f}"])
    return out


def achieved(feed: float, clock_hz: float, steps_per_mm: float = 100) -> tuple[int, float]:
    """(cruise word, the path speed in mm/min it gives) for a long line along X at F = feed."""
    machine = load_machine(sets=[f"axis.x.steps_per_mm={steps_per_mm}"], clock_hz=clock_hz)
    compiled = compile_program(Program([Line((0, 0, 0), (500, 0, 0), feed, 1)]), machine)
    word = compiled.commands[0].feed
    return word, word / (1 << FRAC) * clock_hz * 60 / steps_per_mm


def clock_rows():
    out = []
    for clock in CLOCKS_HZ:
        for feed in FEEDS:
            word, speed = achieved(feed, clock)
            out.append([f"{clock / 1e6:g}", feed, word, f"{speed:.9g}", f"{(speed - feed) / feed * 100:.2e}"])
    return out


def tables(quick: bool):
    return [(f"mean path speed at cruise, F{FEED:g} mm/min, 50 MHz, 100 steps/mm, by the cost modes",
             ["move", "F mm/min", "true: mm/min", "true: error %", "even: error %", "lecture: mm/min",
              "lecture: error %"], cost_rows()),
            (f"local path speed over the mean, {WINDOW}-event windows, %",
             ["move", "true", "even", "lecture"], local_rows()),
            (f"the same measured on the RTL (native Verilator harness, {RTL_CLOCK_HZ / 1e3:g} kHz, middle half "
             f"of the events)", ["move", "F mm/min", "true: mm/min", "true: error %", "even: error %",
                                 "lecture: mm/min", "lecture: error %"], rtl_rows()),
            (f"cruise word precision (100 steps/mm, FRAC = {FRAC})",
             ["clock MHz", "F mm/min", "cruise word", "achieved mm/min", "error %"], clock_rows())]


if __name__ == "__main__":
    for title, header, body in tables(False):
        print(title)
        print("  ".join(f"{h:>18}" for h in header))
        for row in body:
            print("  ".join(f"{str(c):>18}" for c in row))
        print()
