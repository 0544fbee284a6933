# SPDX-License-Identifier: Apache-2.0
"""Properties of the SU 1571551 golden models (pure Python, hypothesis)."""
from hypothesis import given, settings
from hypothesis import strategies as st

from interp.models.base import drive, move, steps_of
from interp.models.su1571551 import Su1571551, max_deviation, steps

coord = st.integers(min_value=-3000, max_value=3000)


@settings(max_examples=300, deadline=None)
@given(coord, coord, st.sampled_from(["faithful", "exact"]))
def test_ends_at_the_point_with_l_minus_s_axial_and_s_diagonal(x, y, mode):
    path = steps(x, y, mode)
    assert (sum(s.dx for s in path), sum(s.dy for s in path)) == (x, y)
    small = min(abs(x), abs(y))
    assert sum(s.kind == "diagonal" for s in path) == small
    assert len(path) == max(abs(x), abs(y))


@settings(max_examples=300, deadline=None)
@given(coord, coord)
def test_exact_mode_is_within_half_a_step(x, y):
    assert max_deviation(x, y, steps(x, y, "exact")) <= 0.5 + 1e-12


@settings(max_examples=100, deadline=None)
@given(st.integers(-200, 200), st.integers(-200, 200), st.booleans())
def test_cycle_model_steps_equal_the_equations(x, y, exact):
    mode = "exact" if exact else "faithful"
    samples = drive(Su1571551(16, exact), move({"x": x, "y": y}))
    got = [(dx, dy) for _, dx, dy in steps_of(samples)]
    assert got == [(s.dx, s.dy) for s in steps(x, y, mode)]


def test_faithful_mode_breaks_the_half_step_claim():
    """The patent's live-counter circuit is not expression (1): a witness."""
    path = steps(31, 2, "faithful")
    assert path != steps(31, 2, "exact")
    assert max_deviation(31, 2, path) > 0.9
