# SPDX-License-Identifier: Apache-2.0
"""Feed precision of `interp gcode`: the path speed motion_top's feed word gives.

For F = 1 .. 6000 mm/min (the default machine's axis maximum) at 1, 50 and 200 MHz
with 100 steps/mm, a line is compiled as the command line compiles it and the
speed its feed word stands for (word / 2^48 steps per clock) is compared with F.
The rule the compiler warns by is 0.01 %.

  python -m interp.benchmarks.feed_accuracy      (also a table of `interp bench`)
"""
from __future__ import annotations

from ..gcode.compile import FRAC, compile_program
from ..gcode.machine import load_machine
from ..gcode.moves import Line, Program

CLOCKS_HZ = (1e6, 50e6, 200e6)
FEEDS = (1, 10, 100, 1000, 6000)


def achieved(feed: float, clock_hz: float, steps_per_mm: float = 100) -> tuple[int, float]:
    """(feed word, the path speed in mm/min it gives) for a line along X at F = feed."""
    machine = load_machine(sets=[f"axis.x.steps_per_mm={steps_per_mm}"], clock_hz=clock_hz)
    compiled = compile_program(Program([Line((0, 0, 0), (10, 0, 0), feed, 1)]), machine)
    word = compiled.commands[0].feed
    return word, word / (1 << FRAC) * clock_hz * 60 / steps_per_mm


def rows():
    out = []
    for clock in CLOCKS_HZ:
        for feed in FEEDS:
            word, speed = achieved(feed, clock)
            out.append([f"{clock / 1e6:g}", feed, word, f"{speed:.9g}", f"{(speed - feed) / feed * 100:.2e}"])
    return out


def tables(quick: bool):
    return [("feed word precision (100 steps/mm, FRAC = 48)",
             ["clock MHz", "F mm/min", "feed word", "achieved mm/min", "error %"], rows())]


if __name__ == "__main__":
    for title, header, body in tables(False):
        print(title)
        print("  ".join(f"{h:>16}" for h in header))
        for row in body:
            print("  ".join(f"{str(c):>16}" for c in row))
