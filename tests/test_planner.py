# SPDX-License-Identifier: Apache-2.0
"""The look-ahead planner (interp.gcode.planner): its rules as properties and known values."""
from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from interp.gcode.planner import (CENTRIPETAL_SHARE, PACING_SLOPE, Plan, Segment, _entry_caps, _junction_limits,
                                  junction_speed,
                                  largest_secant, limits, machine_time, plan, trapezoid_time)
from interp.testing.seeds import seeded_random

RATE = (100.0, 100.0, 50.0)
ACCEL = (500.0, 400.0, 200.0)
SLACK = 1e-7


def line(direction, length=10.0, feed=50.0, **kw) -> Segment:
    size = math.sqrt(sum(c * c for c in direction))
    unit = tuple(c / size for c in direction)
    return Segment(length, unit, unit, feed, kw.pop("rate", RATE), kw.pop("accel", ACCEL), **kw)


def arc_segment(radius, angle, pitch, plane, start_angle, feed, rate=RATE, accel=ACCEL, **kw):
    """An arc or helix of `angle` radians (negative: clockwise) turning in `plane` (p, q)
    from the angle `start_angle`, rising `pitch` mm along the normal axis per radian."""
    p, q = plane
    w = 3 - p - q
    arc = radius * abs(angle)
    rise = pitch * abs(angle)
    length = math.hypot(arc, rise)
    turn = 1.0 if angle > 0 else -1.0

    def tangent(theta):
        vector = [0.0, 0.0, 0.0]
        vector[p] = -math.sin(theta) * turn * arc / length
        vector[q] = math.cos(theta) * turn * arc / length
        vector[w] = math.copysign(rise / length, pitch) if rise else 0.0
        return tuple(vector)

    return Segment(length, tangent(start_angle), tangent(start_angle + angle), feed, rate, accel,
                   radius_mm=radius, plane_axes=plane, **kw)


directions = st.tuples(*[st.floats(-1, 1) for _ in range(3)]).filter(
    lambda d: sum(c * c for c in d) > 0.01)
planes = st.sampled_from([(0, 1), (2, 0), (1, 2)])
lines = st.builds(line, directions, length=st.floats(0.001, 50), feed=st.floats(0.5, 200),
                  stop_before=st.booleans() | st.just(False),
                  tolerance_mm=st.none() | st.floats(0, 0.1))
arcs = st.builds(arc_segment, radius=st.floats(0.05, 100), angle=st.floats(0.01, 12) | st.floats(-12, -0.01),
                 pitch=st.floats(-2, 2), plane=planes, start_angle=st.floats(-4, 4),
                 feed=st.floats(0.5, 200), stop_before=st.booleans() | st.just(False),
                 tolerance_mm=st.none() | st.floats(0, 0.1))
programs = st.lists(lines | arcs, min_size=1, max_size=40)
deviations = st.floats(0.0, 0.2)


def _assert_feasible(segments: list[Segment], plans: list[Plan], deviation: float) -> None:
    assert len(plans) == len(segments)
    assert plans[0].entry_mm_s == 0.0 and plans[-1].exit_mm_s == 0.0
    for index, (segment, p) in enumerate(zip(segments, plans)):
        cruise, accel = limits(segment)
        assert (p.cruise_mm_s, p.accel_mm_s2) == (cruise, accel)
        room = 2 * accel * segment.length_mm * (1 + SLACK) + 1e-12
        assert p.exit_mm_s ** 2 <= p.entry_mm_s ** 2 + room, "exit not reachable from the entry"
        assert p.entry_mm_s ** 2 <= p.exit_mm_s ** 2 + room, "cannot brake to the exit"
        assert max(p.entry_mm_s, p.exit_mm_s) <= cruise * (1 + SLACK)
        assert p.time_s == trapezoid_time(segment.length_mm, p.entry_mm_s, p.exit_mm_s, cruise, accel)
        if index + 1 < len(segments):
            assert p.exit_mm_s == plans[index + 1].entry_mm_s
        if index == 0 or segment.stop_before:
            assert p.entry_mm_s == 0.0
            continue
        before = segments[index - 1]
        used = deviation if segment.tolerance_mm is None else min(deviation, segment.tolerance_mm)
        if min(segment.length_mm, before.length_mm) > used:       # (short runs: their own tests)
            cap = junction_speed(before.end_unit, segment.start_unit, segment.axis_accel_mm_s2, used)
            assert p.entry_mm_s <= cap * (1 + SLACK) + 1e-12, "junction speed exceeded"
        assert p.entry_mm_s <= plans[index - 1].cruise_mm_s * (1 + SLACK)


@settings(max_examples=150, deadline=None)
@given(programs, deviations)
def test_whole_plan_is_feasible_both_ways(segments, deviation):
    _assert_feasible(segments, plan(segments, junction_deviation_mm=deviation), deviation)


@settings(max_examples=150, deadline=None)
@given(programs, deviations, st.integers(1, 45))
def test_window_plan_is_feasible_and_never_faster(segments, deviation, window):
    whole = plan(segments, junction_deviation_mm=deviation)
    streamed = plan(segments, junction_deviation_mm=deviation, window=window)
    _assert_feasible(segments, streamed, deviation)
    for w, s in zip(whole, streamed):
        assert s.entry_mm_s <= w.entry_mm_s and s.exit_mm_s <= w.exit_mm_s
    assert machine_time(streamed) >= machine_time(whole) * (1 - 1e-12)
    # a segment's exit is one the next `window` segments can brake from to a stop
    for index in range(len(segments) - 1):
        speed_sqr = 0.0
        for ahead in range(min(index + window, len(segments) - 1), index, -1):
            speed_sqr += 2 * streamed[ahead].accel_mm_s2 * segments[ahead].length_mm
        assert streamed[index].exit_mm_s ** 2 <= speed_sqr * (1 + SLACK) + 1e-12
    if window >= len(segments):
        assert streamed == whole


# dense programs: short collinear lines at high feeds (a few with a corner or a stop),
# where a short look-ahead limits the speed
dense_lines = st.builds(lambda corner, length, feed, stop: line((1, 0.3 + corner, 0), length, feed,
                                                                rate=(1000, 1000, 1000), stop_before=stop),
                        st.sampled_from([0.0] * 8 + [0.2]), st.floats(0.05, 2), st.floats(100, 300),
                        st.sampled_from([False] * 15 + [True]))
dense = st.lists(dense_lines, min_size=1, max_size=60)


@settings(max_examples=100, deadline=None)
@given(programs | dense, deviations, st.integers(1, 12))
def test_window_plan_is_the_streaming_hosts(segments, deviation, window):
    """The window plan against a host written out plainly: at each segment, the backward
    pass over the segments it knows (the next `window`) from a stop at the last of them,
    and the forward step from the speed it actually has."""
    bounds = [limits(s) for s in segments]
    reach = [2 * accel * s.length_mm for (_, accel), s in zip(bounds, segments)]
    caps = _entry_caps(_junction_limits(segments, deviation), [cruise for cruise, _ in bounds])
    streamed = plan(segments, junction_deviation_mm=deviation, window=window)
    speed = 0.0
    for index in range(len(segments)):
        exit_sqr = 0.0
        for ahead in range(min(index + window, len(segments) - 1), index, -1):
            exit_sqr = min(caps[ahead], math.sqrt(exit_sqr + reach[ahead])) ** 2
        exit_speed = min(math.sqrt(exit_sqr), math.sqrt(speed ** 2 + reach[index]))
        assert streamed[index].entry_mm_s == speed
        assert streamed[index].exit_mm_s == pytest.approx(exit_speed, rel=1e-12, abs=1e-12)
        speed = streamed[index].exit_mm_s


@settings(max_examples=100, deadline=None)
@given(programs, deviations, st.floats(1.0, 10.0))
def test_time_is_monotone_in_acceleration(segments, deviation, factor):
    faster = [Segment(s.length_mm, s.start_unit, s.end_unit, s.feed_mm_s, s.axis_rate_mm_s,
                      tuple(a * factor for a in s.axis_accel_mm_s2), s.radius_mm, s.plane_axes,
                      s.stop_before, s.tolerance_mm) for s in segments]
    slow = plan(segments, junction_deviation_mm=deviation)
    quick = plan(faster, junction_deviation_mm=deviation)
    for s, q in zip(slow, quick):
        assert q.entry_mm_s >= s.entry_mm_s * (1 - SLACK)
    assert machine_time(quick) <= machine_time(slow) * (1 + 1e-9)


arc_shapes = st.builds(dict, radius=st.floats(0.05, 100), angle=st.floats(0.01, 12) | st.floats(-12, -0.01),
                       pitch=st.floats(-2, 2), plane=planes, start_angle=st.floats(-4, 4), feed=st.floats(0.5, 400))
arc_accels = st.sampled_from([ACCEL, (500.0, 500.0, 500.0), (100.0, 900.0, 300.0)])


@settings(max_examples=300, deadline=None)
@given(arc_shapes, arc_accels,
       st.sampled_from([1.0, 1.0]) | st.floats(1.0, 1.1))
def test_arc_bounds_hold_along_the_arc(shape, accel, pacing):
    """Speed, and tangential (speeding up or braking) plus centripetal acceleration at the
    cruise speed, per axis, at every angle the arc passes (sampled finely).  With a pacing P
    > 1 (the lecture's step costs) at the local speed P x cruise, the tangential P x a_t +
    PACING_SLOPE x the centripetal."""
    segment = arc_segment(**shape, accel=accel, pacing=pacing)
    cruise, tangential = limits(segment)
    p, q = segment.plane_axes
    w = 3 - p - q
    sin_a = abs(segment.start_unit[w])
    cos_a = math.sqrt(1 - sin_a ** 2)
    assert cruise <= segment.feed_mm_s and tangential > 0
    local = cruise * pacing
    centripetal = (local * cos_a) ** 2 / segment.radius_mm
    paced = tangential * pacing + (PACING_SLOPE * centripetal / cos_a if pacing > 1 else 0.0)
    samples = 2000
    for step in range(samples + 1):
        theta = shape["start_angle"] + shape["angle"] * step / samples      # position angle
        velocity = {p: -math.sin(theta) * local * cos_a, q: math.cos(theta) * local * cos_a,
                    w: local * sin_a}
        for sign in (1, -1):
            along = sign * paced
            acceleration = {p: -math.sin(theta) * along * cos_a - math.cos(theta) * centripetal,
                            q: math.cos(theta) * along * cos_a - math.sin(theta) * centripetal,
                            w: along * sin_a}
            for axis in range(3):
                assert abs(velocity[axis]) <= RATE[axis] * (1 + SLACK)
                assert abs(acceleration[axis]) <= accel[axis] * (1 + SLACK)


@settings(max_examples=300, deadline=None)
@given(arc_shapes, arc_accels,
       st.sampled_from([1.0, 1.26]) | st.floats(1.0, 1.6))
def test_evenly_charged_helix_bounds_hold_along_the_arc(shape, accel, pacing):
    """A helix charged evenly (its events take equal times, each covers sec(theta) of the
    plane, theta the tangent's angle from its octant's axis): the plane's local speed
    u = v cos(alpha) P sec(theta) / (its largest over the arc) changes by u^2 tan(theta) / R
    along the tangent, w runs at v sin(alpha).  Speed and acceleration per axis, both
    signs of the tangential acceleration, at every angle the arc passes (sampled finely)."""
    segment = arc_segment(**shape, accel=accel, pacing=pacing, even_costs=True)
    cruise, tangential = limits(segment)
    p, q = segment.plane_axes
    w = 3 - p - q
    sin_a = abs(segment.start_unit[w])
    cos_a = math.sqrt(1 - sin_a ** 2)
    peak = largest_secant(segment)
    turn = 1.0 if shape["angle"] > 0 else -1.0
    samples = 2000
    for step in range(samples + 1):
        theta = shape["start_angle"] + shape["angle"] * step / samples      # position angle
        tx, ty = -math.sin(theta) * turn, math.cos(theta) * turn              # tangent in the plane
        major, minor = max(abs(tx), abs(ty)), min(abs(tx), abs(ty))
        local = cruise * cos_a * pacing / major / peak
        assert local <= cruise * cos_a * pacing * (1 + SLACK)
        centripetal = local ** 2 / segment.radius_mm
        velocity = {p: tx * local, q: ty * local, w: cruise * sin_a}
        for sign in (1, -1):
            for pace_sign in (1, -1):
                along = sign * tangential * cos_a * pacing / major / peak + pace_sign * centripetal * minor / major
                acceleration = {p: tx * along + math.cos(theta) * -centripetal,
                                q: ty * along - math.sin(theta) * centripetal,
                                w: sign * tangential * sin_a}
                for axis in range(3):
                    assert abs(velocity[axis]) <= RATE[axis] * (1 + SLACK)
                    assert abs(acceleration[axis]) <= accel[axis] * (1 + SLACK)


def test_largest_secant():
    """sqrt 2 where an arc passes a diagonal, else at the end nearer one."""
    assert largest_secant(arc_segment(1.0, 0.1, 0.0, (0, 1), math.pi / 4 - 0.05, feed=10)) == math.sqrt(2)
    short = arc_segment(1.0, 0.1, 0.0, (0, 1), 0.0, feed=10)          # tangent from 90 to 95.7 degrees
    assert largest_secant(short) == pytest.approx(1 / math.cos(0.1), rel=1e-3)
    helix = arc_segment(1.0, 2 * math.pi, 0.3, (0, 1), 0.0, feed=10)
    assert largest_secant(helix) == math.sqrt(2)


def test_full_circle_bound_is_the_euclidean_one():
    """A whole turn meets every direction: the worst axis sees sqrt(a_t^2 + c^2)."""
    cruise, accel = limits(arc_segment(1.0, 2 * math.pi, 0.0, (0, 1), 0.3, feed=100))
    assert cruise == pytest.approx(math.sqrt(CENTRIPETAL_SHARE * 400))
    assert accel == pytest.approx(math.sqrt(400 ** 2 - (CENTRIPETAL_SHARE * 400) ** 2))


def test_short_arc_bound_is_wider_than_the_circle():
    """A 10-degree arc moving along y: x sees mostly the centripetal, y the tangential."""
    short = arc_segment(1.0, math.radians(10), 0.0, (0, 1), -math.radians(5), feed=100)
    full = arc_segment(1.0, 2 * math.pi, 0.0, (0, 1), 0.0, feed=100)
    assert limits(short)[0] > limits(full)[0] and limits(short)[1] > limits(full)[1]


def test_line_limits_are_grbl_rules():
    assert limits(line((1, 0, 0), feed=500)) == (100.0, 500.0)
    cruise, accel = limits(line((1, 1, 0), feed=500))
    assert cruise == pytest.approx(100 * math.sqrt(2))
    assert accel == pytest.approx(400 * math.sqrt(2))          # y's 400 over |u_y| = 1/sqrt(2)
    assert limits(line((0, 0, 1), feed=20)) == (20.0, 200.0)


def test_arc_limits_known_values():
    # a half circle of radius 1 mm in XY (meets every direction): v^2 <= share * 400 * 1,
    # a_t = sqrt(1 - share^2) * 400
    cruise, accel = limits(arc_segment(1.0, math.pi, 0.0, (0, 1), 0.0, feed=100))
    assert cruise == pytest.approx(math.sqrt(CENTRIPETAL_SHARE * 400))
    assert accel == pytest.approx(math.sqrt(1 - CENTRIPETAL_SHARE ** 2) * 400)
    # a large arc: the feed binds, the centripetal share is tiny
    cruise, accel = limits(arc_segment(1000.0, 0.1, 0.0, (0, 1), 0.0, feed=50))
    assert cruise == 50
    assert accel == pytest.approx(math.sqrt(400 ** 2 - (2500 / 1000) ** 2))


def test_grbl_junction_formula_known_values():
    a = (500.0, 500.0, 500.0)
    # 90 degrees: a_j = 500 sqrt(2), sin(theta/2) = 1/sqrt(2)
    expected = math.sqrt(500 * math.sqrt(2) * 0.01 * math.sqrt(0.5) / (1 - math.sqrt(0.5)))
    assert junction_speed((1, 0, 0), (0, 1, 0), a, 0.01) == pytest.approx(expected)
    assert junction_speed((1, 0, 0), (0, 1, 0), a, 0.01) == pytest.approx(4.1317148754)
    assert junction_speed((1, 0, 0), (1, 0, 0), a, 0.01) == math.inf          # straight on
    assert junction_speed((1, 0, 0), (-1, 0, 0), a, 0.01) == 0.0              # reversal
    # 45-degree turn: theta = 135 degrees between the paths
    turn = (math.cos(math.pi / 4), math.sin(math.pi / 4), 0.0)
    sin_half = math.sin(3 * math.pi / 8)
    change = (turn[0] - 1, turn[1], 0.0)
    size = math.hypot(*change)
    a_j = min(500 / abs(c / size) for c in change[:2])
    assert junction_speed((1, 0, 0), turn, a, 0.05) == pytest.approx(
        math.sqrt(a_j * 0.05 * sin_half / (1 - sin_half)))


def test_junction_of_velocities_of_different_lengths():
    """Given the machine's velocities per unit of planned speed: the corner whose velocity
    change is the same share of the larger velocity, at the speed over that length, and
    neither side faster than Grbl's rule for their directions.  A step of the speed alone is
    a junction; a reversal stops whatever the lengths; scaling both velocities scales the
    speed inversely; the change of velocity never exceeds sqrt(8 a_j delta), Grbl's bound
    over every angle."""
    a = (500.0, 500.0, 500.0)
    # a speed step of 20 % along x is the corner whose chord is 0.2: the change along y
    half = math.asin(0.1)
    corner = junction_speed((math.cos(half), -math.sin(half), 0.0), (math.cos(half), math.sin(half), 0.0), a, 0.01)
    assert junction_speed((1.0, 0, 0), (0.8, 0, 0), a, 0.01) == pytest.approx(corner)
    assert junction_speed((1.25, 0, 0), (1.0, 0, 0), a, 0.01) == pytest.approx(corner / 1.25)
    assert junction_speed((0.5, 0, 0), (0.5, 0, 0), a, 0.01) == math.inf
    assert junction_speed((0.5, 0, 0), (-0.5, 0, 0), a, 0.01) == 0.0
    assert junction_speed((1.0, 0, 0), (-math.cos(math.pi / 8), 0, 0), a, 0.01) == 0.0
    rng, seed = seeded_random()
    for _ in range(200):
        before = [rng.uniform(-1.3, 1.3) for _ in range(3)]
        after = [rng.uniform(-1.3, 1.3) for _ in range(3)]
        accel = tuple(rng.uniform(100, 1000) for _ in range(3))
        speed = junction_speed(before, after, accel, 0.02)
        change = [speed * (y - x) for x, y in zip(before, after)]
        jump = math.hypot(*change)
        if 0 < speed < math.inf:
            a_j = min(accel[i] / abs(c) * jump for i, c in enumerate(change) if abs(c) > 1e-12)
            assert jump <= math.sqrt(8 * a_j * 0.02) * (1 + 1e-9), seed
            sides = max(math.hypot(*before), math.hypot(*after)) * speed
            directions = [[u / math.hypot(*v) for u in v] for v in (before, after)]
            assert sides <= junction_speed(*directions, accel, 0.02) * (1 + 1e-9), seed
            assert junction_speed([2 * x for x in before], [2 * y for y in after], accel, 0.02) == \
                pytest.approx(speed / 2), seed


def test_trapezoid_and_triangle_times():
    assert trapezoid_time(10, 0, 0, 50, 500) == pytest.approx(0.3)    # 2.5 mm ramps, 5 mm cruise
    assert trapezoid_time(1, 0, 0, 50, 500) == pytest.approx(2 * math.sqrt(1 / 500))   # triangle
    assert trapezoid_time(10, 50, 50, 50, 500) == pytest.approx(0.2)
    assert trapezoid_time(2.5, 0, 50, 50, 500) == pytest.approx(0.1)  # all acceleration
    with pytest.raises(ValueError):
        trapezoid_time(1, 0, 50, 50, 500)                              # 50 mm/s needs 2.5 mm


def test_plan_time_is_the_analytic_sum():
    segments = [line((1, 0, 0), 10), line((1, 0, 0), 10), line((0, 1, 0), 10, stop_before=True)]
    plans = plan(segments, junction_deviation_mm=0.01)
    assert [p.entry_mm_s for p in plans] == [0.0, 50.0, 0.0]
    assert [p.exit_mm_s for p in plans] == [50.0, 0.0, 0.0]
    # x: 2.5 mm up in 0.1 s, 7.5 mm at 50 in 0.15 s; then 7.5 mm at 50 and down in 0.1 s;
    # y at 400 mm/s^2: 3.125 mm ramps of 0.125 s and 3.75 mm at 50
    assert plans[0].time_s == pytest.approx(0.25)
    assert plans[1].time_s == pytest.approx(0.25)
    assert plans[2].time_s == pytest.approx(0.25 + 3.75 / 50)
    assert machine_time(plans) == pytest.approx(0.75 + 0.075)


def test_corner_and_tolerance():
    corner = [line((1, 0, 0)), line((0, 1, 0))]
    wide = plan(corner, junction_deviation_mm=0.05)[0].exit_mm_s
    narrow = plan(corner, junction_deviation_mm=0.01)[0].exit_mm_s
    assert 0 < narrow < wide
    assert narrow == pytest.approx(junction_speed((1, 0, 0), (0, 1, 0), ACCEL, 0.01))
    corner[1].tolerance_mm = 0.01          # G64 P0.01 lowers the junction deviation there
    assert plan(corner, junction_deviation_mm=0.05)[0].exit_mm_s == pytest.approx(narrow)
    corner[1].tolerance_mm = 1.0           # ... but never raises it
    assert plan(corner, junction_deviation_mm=0.05)[0].exit_mm_s == pytest.approx(wide)
    corner[1].stop_before = True
    assert plan(corner, junction_deviation_mm=0.05)[0].exit_mm_s == 0.0


def test_a_short_run_is_one_corner():
    """An arc, a one-step correction line (0.01 mm) across it, and an arc continuing the
    first tangentially: the run is shorter than the junction deviation, so the junctions
    are judged across it (straight on) and the speed stays at the cruise."""
    first = arc_segment(20.0, math.pi / 2, 0.0, (0, 1), 0.0, feed=30)
    jog = line((0, 1, 0), length=0.01, feed=30)
    second = arc_segment(20.0, math.pi / 2, 0.0, (0, 1), math.pi / 2, feed=30)
    plans = plan([first, jog, second], junction_deviation_mm=0.01)
    assert plans[0].exit_mm_s == plans[1].exit_mm_s == pytest.approx(30.0)
    # a longer jog is a corner of its own; so is the short one under G64 P0.005
    assert plan([first, line((0, 1, 0), length=0.02, feed=30), second],
                junction_deviation_mm=0.01)[0].exit_mm_s < 5
    jog.tolerance_mm = 0.005
    assert plan([first, jog, second], junction_deviation_mm=0.01)[0].exit_mm_s < 5


def test_a_short_run_is_never_slower_nor_a_reversal():
    """Across the run the corner may be sharper than its own junctions: each junction keeps
    the faster of the two rules.  A run in which a moving axis turns back is not bridged."""
    corner = junction_speed((1, 0, 0), (0, 1, 0), ACCEL, 0.01)
    segments = [line((1, 0, 0)), line((0, 1, 0), length=0.005), line((-1, 0, 0))]
    assert [p.entry_mm_s for p in plan(segments, junction_deviation_mm=0.01)[1:]] == \
        pytest.approx([corner, corner])                           # not the reversal's 0
    segments = [line((1, 0, 0)), line((0, 1, 0), length=0.005), line((1, 0, 0))]
    assert plan(segments, junction_deviation_mm=0.01)[0].exit_mm_s == pytest.approx(50.0)
    for jog in ((-1, 0, 0), (-1, 1, 0)):                          # x turns back: two corners
        segments = [line((1, 0, 0)), line(jog, length=0.005), line((1, 0, 0))]
        entries = [p.entry_mm_s for p in plan(segments, junction_deviation_mm=0.01)[1:]]
        unit = segments[1].start_unit
        assert entries == pytest.approx([junction_speed((1, 0, 0), unit, ACCEL, 0.01),
                                         junction_speed(unit, (1, 0, 0), ACCEL, 0.01)])


def test_tangent_arc_keeps_speed():
    # a line into a tangent quarter circle of radius 100: no junction limit, only the cruises
    segments = [line((0, 1, 0), 20), arc_segment(100.0, math.pi / 2, 0.0, (0, 1), 0.0, feed=50)]
    plans = plan(segments, junction_deviation_mm=0.0)
    assert plans[0].exit_mm_s == pytest.approx(50.0)


def test_short_window_limits_speed():
    chain = [line((1, 0, 0), 1.0, feed=200, rate=(1000, 1000, 1000)) for _ in range(100)]
    whole = plan(chain, junction_deviation_mm=0.01)
    one = plan(chain, junction_deviation_mm=0.01, window=1)
    # with one segment known ahead, the exit speed is what 1 mm of braking allows
    assert max(p.exit_mm_s for p in one) == pytest.approx(math.sqrt(2 * 500 * 1.0))
    assert max(p.exit_mm_s for p in whole) == pytest.approx(200.0)
    assert machine_time(one) > machine_time(plan(chain, junction_deviation_mm=0.01, window=32)) \
        >= machine_time(whole)


@pytest.mark.parametrize("bad", [
    dict(window=0), dict(window=-3), dict(window=2.5), dict(junction_deviation_mm=-1)])
def test_bad_arguments(bad):
    arguments = dict(junction_deviation_mm=0.01) | bad
    with pytest.raises(ValueError):
        plan([line((1, 0, 0))], **arguments)


def test_bad_segments():
    with pytest.raises(ValueError):
        limits(line((1, 0, 0), length=0.0))
    with pytest.raises(ValueError):
        limits(Segment(1.0, (1, 0, 0), (0, 1, 0), 10, RATE, ACCEL, radius_mm=1.0, plane_axes=(0, 0)))
    assert plan([], junction_deviation_mm=0.01) == []


def test_scurve_smoothing_lowers_each_junction_by_a_w_over_2():
    segments = [line((1, 0, 0), 20.0), line((0, 1, 0), 20.0), line((-1, 0, 0), 20.0)]
    plain = plan(segments, junction_deviation_mm=0.05)
    window = 0.004
    smooth = plan(segments, junction_deviation_mm=0.05, smoothing_s=window)
    for k in range(len(segments) - 1):
        a = max(plain[k].accel_mm_s2, plain[k + 1].accel_mm_s2)
        assert plain[k].exit_mm_s > a * window / 2
        assert smooth[k].exit_mm_s == pytest.approx(plain[k].exit_mm_s - a * window / 2)
        assert smooth[k + 1].entry_mm_s == smooth[k].exit_mm_s
    # a junction slower than a W / 2 becomes a stop, never negative
    assert plan(segments, junction_deviation_mm=0.05, smoothing_s=10.0)[0].exit_mm_s == 0.0
    with pytest.raises(ValueError, match="smoothing window"):
        plan(segments, junction_deviation_mm=0.05, smoothing_s=-1.0)
