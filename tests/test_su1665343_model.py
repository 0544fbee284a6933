# SPDX-License-Identifier: Apache-2.0
"""SU 1665343 models: the cycle model (circuit order) agrees with the step-level equations."""
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from interp.models.base import drive, move
from interp.models.su1665343 import (Su1665343, expected_per_step, move_cycles, path_string,
                                     per_step, preload, start_error, steps, trace)


def run_cycle_model(r, x0, y0, width=12):
    samples = drive(Su1665343(width), move({"r": r, "x0": x0, "y0": y0}))
    return samples, trace(samples, width)


@pytest.mark.parametrize("rs", [range(1, 120), range(1990, 2000)])
def test_cycle_model_equals_equations(rs):
    for r in rs:
        samples, rows = run_cycle_model(r, r, 0)
        path = steps(r)
        assert per_step(rows) == expected_per_step(path), r
        assert [i for i, s in enumerate(samples) if s["done"]] == [move_cycles(path, 12)], r


def valid_starts(r):
    """Every start point the core accepts for R: within one step of the circle."""
    return [(x, y) for x in range(r + 2) for y in range(r + 2) if start_error(r, x, y, 30) is None]


def test_every_start_point_at_width_5():
    """WIDTH = 5 (Table 2's codes): every R and every accepted start point; F never
    overflows its WIDTH + 5 bits (the models would disagree)."""
    for r in range(1, 15):
        for x0, y0 in valid_starts(r):
            _, rows = run_cycle_model(r, x0, y0, width=5)
            assert per_step(rows) == expected_per_step(steps(r, x0, y0)), (r, x0, y0)


def test_start_points_on_both_sides_of_45():
    for r in (7, 12, 50):
        for p in steps(r)[:-1]:
            _, rows = run_cycle_model(r, p.x, p.y)
            tail = steps(r, p.x, p.y)
            assert per_step(rows) == expected_per_step(tail), (r, p)
            assert (tail[-1].x, tail[-1].y) == (0, r)


def test_equations_reproduce_formulas_3_4_and_symmetry():
    """F0 = R - 1.25 at (R, 0); F1 and F2 agree with (3)/(4) after every step; the
    path is symmetric about X = Y and ends at (0, R)."""
    for r in range(1, 400):
        assert preload(r, r, 0)[0] == 4 * r - 5
        path = steps(r)
        for s in path:
            if s is not path[-1] or s.switch:
                assert s.f4 == preload(r, s.x, s.y)[0] or s.x == 0, (r, s)
        text = path_string(path)
        assert text == text[::-1].translate(str.maketrans("XY", "YX")), r
        assert (path[-1].x, path[-1].y) == (0, r)


@settings(max_examples=60, deadline=None)
@given(st.data())
def test_any_start_within_one_step(data):
    """Any start point within one step of the circle: the models agree and the arc ends at X = 0."""
    r = data.draw(st.integers(1, 300), label="r")
    x0 = data.draw(st.integers(0, r + 1), label="x0")
    lo = math.isqrt(max(0, (r - 1) ** 2 - x0 * x0 - 1)) + 1 if (r - 1) ** 2 > x0 * x0 else 0
    hi = math.isqrt((r + 1) ** 2 - x0 * x0)
    y0 = data.draw(st.integers(lo, hi), label="y0")
    assert start_error(r, x0, y0, 12) is None
    samples, rows = run_cycle_model(r, x0, y0)
    path = steps(r, x0, y0)
    assert per_step(rows) == expected_per_step(path)
    assert not path or path[-1].x == 0
    assert not any(s["error"] for s in samples)
