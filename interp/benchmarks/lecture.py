# SPDX-License-Identifier: Apache-2.0
"""Side by side: the lecture's standard and accelerated cores, the production arc,
and the patents (SU 1571551 linear, SU 1665343 circular).

Per core: steps taken, cycles per step (start to `done`, `tick` high, from the
cycle models, which the benches prove equal to the RTL cycle by cycle), and the
maximum deviation from the ideal curve (distance to the line; |r - R| for arcs)
over an exhaustive small range and a random large one (seed fixed: 4).
"""
from __future__ import annotations

import itertools
import math
import random

from ..models import su1571551 as su_lin
from ..models.arc import CircArc, arc_steps
from ..models.base import drive, move, steps_of
from ..models.lecture import (CircQuadrant, LinAccel, LinStd, circ_steps, lin_accel_steps,
                              lin_std_steps, line_deviation, quadrant_error, radial_deviation)

try:                                    # the circular patent core (another engineer's model)
    from ..models import su1665343 as su_circ
except ImportError:                     # pragma: no cover
    su_circ = None

SEED = 4
# The step counts and errors come from the step-level models; "radial error" is
# |r - R| with R = |start - centre|, "distance to the line" is perpendicular.


def _dev(value: float) -> str:
    """Truncated (not rounded) to 4 decimals, so 0.49999 does not print as 0.5000."""
    return f"{math.floor(value * 1e4) / 1e4:.4f}"


def _cycles(model, load) -> tuple[int, int]:
    """(steps, cycles from start to done) of one command through a cycle model."""
    samples = drive(model, move(load, idle_after=0))
    return len(steps_of(samples)), len(samples) - 1


def _linear_rows(quick: bool):
    small = 10 if quick else 30
    big, count = (2_000, 10) if quick else (20_000, 40)
    rng = random.Random(SEED)
    randoms = [(rng.randint(-big, big), rng.randint(-big, big)) for _ in range(count)]
    grid = list(itertools.product(range(-small, small + 1), repeat=2))
    cores = [
        ("lin-std (lecture, standard)", lin_std_steps, LinStd),
        ("lin-accel (lecture, accelerated)", lin_accel_steps, LinAccel),
        ("su1571551 exact (expression (1))", lambda x, y: su_lin.steps(x, y, "exact"),
         lambda w: su_lin.Su1571551(w, True)),
        ("su1571551 faithful (expression (5))", lambda x, y: su_lin.steps(x, y, "faithful"),
         lambda w: su_lin.Su1571551(w, False)),
    ]
    rows = []
    for name, path_of, make in cores:
        steps = cycles = 0
        for x, y in grid:
            s, c = _cycles(make(16), {"x": x, "y": y})
            steps, cycles = steps + s, cycles + c
        long_axis = sum(max(abs(x), abs(y)) for x, y in grid)
        dev_small = max(line_deviation(x, y, path_of(x, y)) for x, y in grid)
        dev_big = max(line_deviation(x, y, path_of(x, y)) for x, y in randoms)
        rows.append([name, f"{steps / len(grid):.2f}", f"{steps / long_axis:.3f}", f"{cycles / steps:.3f}",
                     _dev(dev_small), _dev(dev_big)])
    header = ["core", f"steps per move (mean, every x, y in -{small} .. {small})", "steps / long axis",
              "cycles / step (start to done)", f"max distance to the line, every x, y in -{small} .. {small}",
              f"max distance to the line, {count} random x, y in -{big:,} .. {big:,}"]
    return header, rows


def _quarter(r: int, ccw: bool = True):
    return (r, 0, 0, r) if ccw else (0, r, r, 0)


def _circular_rows(quick: bool):
    small = 8 if quick else 12
    top = 200 if quick else 1000
    rng = random.Random(SEED)
    radii = sorted(rng.randint(top // 2, top * 10) for _ in range(5 if quick else 20))
    # Exhaustive small: every valid first-quadrant command with coordinates 0 .. small.
    quadrant_cmds = [(x0, y0, x1, y1, ccw) for x0, y0, x1, y1 in itertools.product(range(small + 1), repeat=4)
                     for ccw in (True, False) if quadrant_error(x0, y0, x1, y1, ccw) is None]
    rows = []
    for name, accel in (("circ-std (lecture, standard)", False), ("circ-accel (lecture, accelerated)", True)):
        dev_small = max(radial_deviation(c[0], c[1], circ_steps(*c, accel)) for c in quadrant_cmds)
        dev_q = max(radial_deviation(r, 0, circ_steps(*_quarter(r), True, accel)) for r in range(1, top + 1))
        dev_big = max(radial_deviation(r, 0, circ_steps(*_quarter(r), True, accel)) for r in radii)
        steps = sum(len(circ_steps(*_quarter(r), True, accel)) for r in range(1, top + 1))
        s, c = _cycles(CircQuadrant(16, accel), dict(zip(("x0", "y0", "x1", "y1"), _quarter(100)), ccw=1))
        rows.append([name, "first quadrant", f"{steps / sum(range(1, top + 1)):.3f}", f"{c / s:.3f}",
                     _dev(dev_small), _dev(dev_q), _dev(dev_big)])
    # The production arc: every start |u|, |v| <= small, full circles both ways.
    starts = [(u, v) for u, v in itertools.product(range(-small, small + 1), repeat=2) if (u, v) != (0, 0)]
    dev_small = max(radial_deviation(u, v, arc_steps(0, 0, u, v, u, v, ccw, True))
                    for (u, v), ccw in itertools.product(starts, (True, False)))
    dev_q = max(radial_deviation(r, 0, arc_steps(0, 0, *_quarter(r), True)) for r in range(1, top + 1))
    dev_big = max(radial_deviation(r, 0, arc_steps(0, 0, r, 0, r, 0, True, True)) for r in radii)
    steps = sum(len(arc_steps(0, 0, *_quarter(r), True)) for r in range(1, top + 1))
    s, c = _cycles(CircArc(32), {"cx": 0, "cy": 0, "x0": 100, "y0": 0, "x1": 0, "y1": 100, "ccw": 1, "full": 0})
    rows.append(["circ-arc (production, midpoint, all octants)", "any arc, full circle",
                 f"{steps / sum(range(1, top + 1)):.3f}", f"{c / s:.3f}",
                 _dev(dev_small), _dev(dev_q), _dev(dev_big) + " (full circles)"])
    if su_circ is not None:
        dev_q = max(su_circ.radial_error(r, su_circ.steps(r)) for r in range(1, top + 1))
        dev_big = max(su_circ.radial_error(r, su_circ.steps(r)) for r in radii)
        steps = sum(len(su_circ.steps(r)) for r in range(1, top + 1))
        path = su_circ.steps(100)
        rows.append(["su1665343 (patent, two sectors)", "quadrant from (R, 0)",
                     f"{steps / sum(range(1, top + 1)):.3f}", f"{su_circ.move_cycles(path) / len(path):.3f}",
                     "-", _dev(dev_q), _dev(dev_big)])
    header = ["core", "arcs", "steps / R (quarter circle)", "cycles / step (R = 100 quarter, start to done)",
              f"max radial error, every command with coordinates 0 .. {small} (circ-arc: every start "
              f"with u, v in -{small} .. {small}, full circles)",
              f"max radial error, quarter circles R = 1 .. {top}",
              f"max radial error, {len(radii)} random R in {top // 2:,} .. {top * 10:,}"]
    return header, rows


def tables(quick: bool):
    lin_header, lin_rows = _linear_rows(quick)
    circ_header, circ_rows = _circular_rows(quick)
    return [("Lecture vs patents: linear interpolators", lin_header, lin_rows),
            ("Lecture vs patents: circular interpolators", circ_header, circ_rows)]
