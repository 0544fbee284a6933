# SPDX-License-Identifier: Apache-2.0
"""The arc algorithm's two promises, on the step-level model (no simulator):
every visited point within half a step of the circle, and the move ends exactly
at the end point with a single last step.  (The RTL equals the model: test_circ_arc.)"""
import itertools

import pytest

from interp.models.arc import arc_steps
from interp.models.lecture import radial_deviation, within_half_step

SPAN = 9


@pytest.mark.parametrize("ccw", [True, False])
def test_every_arc_small(ccw):
    """Every start with |u|, |v| <= 9 to every end point within half a step (full circle at end = start)."""
    ends = list(itertools.product(range(-SPAN - 1, SPAN + 2), repeat=2))
    for u0, v0 in itertools.product(range(-SPAN, SPAN + 1), repeat=2):
        if u0 == v0 == 0:
            continue
        r2 = u0 * u0 + v0 * v0
        for u1, v1 in ends:
            if not within_half_step(r2, u1 * u1 + v1 * v1):
                continue
            path = arc_steps(0, 0, u0, v0, u1, v1, ccw, True)   # raises if the last step is not single
            assert (u0 + sum(s.dx for s in path), v0 + sum(s.dy for s in path)) == (u1, v1)
            assert radial_deviation(u0, v0, path) < 0.5, (u0, v0, u1, v1, ccw)


@pytest.mark.parametrize("r", [100, 1000, 12345])
def test_full_circles_large(r):
    """Full circles from (R, 0) and from a point near 30 degrees, both ways."""
    for (u0, v0), ccw in itertools.product([(r, 0), (round(r * 0.866), r // 2)], (True, False)):
        path = arc_steps(0, 0, u0, v0, u0, v0, ccw, True)
        assert (sum(s.dx for s in path), sum(s.dy for s in path)) == (0, 0)
        assert radial_deviation(u0, v0, path) < 0.5
