# SPDX-License-Identifier: Apache-2.0
"""The Grbl planner reference of the machine-time benchmark (interp.benchmarks.grbl_planner)."""
from __future__ import annotations

import math

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from interp.benchmarks import grbl_planner as grbl
from interp.benchmarks.machine_time import arc_geometry, program_segments
from interp.gcode.machine import load_machine
from interp.gcode.moves import PLANES, Arc, Dwell, Event, Line, Program
from interp.gcode.planner import junction_speed, machine_time, plan, trapezoid_time

MACHINE = load_machine()              # 100 steps/mm, 6000 mm/min, 500 mm/s^2, delta 0.01 mm
SETTINGS = grbl.GrblSettings.from_machine(MACHINE)


def test_settings_from_the_machine_file():
    assert SETTINGS.steps_per_mm == (100.0, 100.0, 100.0)
    assert SETTINGS.max_rate_mm_s == (100.0, 100.0, 100.0)
    assert SETTINGS.accel_mm_s2 == (500.0, 500.0, 500.0)
    assert (SETTINGS.junction_deviation_mm, SETTINGS.arc_tolerance_mm, SETTINGS.buffer_size) == (0.01, 0.002, 16)


def test_chord_count_known_value():
    # a full circle of radius 10 mm at 0.002 mm: floor(pi * 10 / sqrt(0.002 * 19.998)) = 157
    assert grbl.chord_count(10.0, 2 * math.pi, 0.002) == 157
    arc = Arc((10.0, 0.0, 0.0), (10.0, 0.0, 0.0), (0.0, 0.0, 0.0), "XY", True, 1, 600.0, 1)
    assert len(grbl.arc_points(arc)) == 157
    # a quarter circle of 0.004 mm: 0.5 * pi/2 * 0.004 < sqrt(0.002 * 0.006): one line
    tiny = Arc((0.004, 0.0, 0.0), (0.0, 0.004, 0.0), (0.0, 0.0, 0.0), "XY", True, 1, 600.0, 1)
    assert grbl.chord_count(0.004, math.pi / 2, 0.002) == 0 and len(grbl.arc_points(tiny)) == 1
    assert grbl.chord_count(0.01, math.pi / 2, 0.002) == 1


@settings(max_examples=200, deadline=None)
@given(radius=st.floats(0.01, 200), start=st.floats(-math.pi, math.pi), turn=st.floats(0.001, 2 * math.pi),
       ccw=st.booleans(), turns=st.integers(1, 3), rise=st.floats(-5, 5),
       plane=st.sampled_from(sorted(PLANES)), tolerance=st.sampled_from([0.002, 0.01, 0.0005]))
def test_arc_points_follow_mc_arc(radius, start, turn, ccw, turns, rise, plane, tolerance):
    """The chord count is Grbl's formula; every point lies on the circle (helix: on the
    helix) and every chord stays within the tolerance of the arc, widened by the floor of
    the formula (n chords where the arc length / chord of sagitta `tolerance` is n + a bit:
    the sagitta grows with the square of the chord)."""
    assume(tolerance * 20 <= radius)         # chords of up to about 0.6 rad
    u, v, w = PLANES[plane]
    centre = [1.0, -2.0, 3.0]
    end_angle = start + (turn if ccw else -turn)

    def point(angle, height):
        p = list(centre)
        p[u] += radius * math.cos(angle)
        p[v] += radius * math.sin(angle)
        p[w] += height
        return tuple(p)

    arc = Arc(point(start, 0.0), point(end_angle, rise), tuple(centre), plane, ccw, turns, 600.0, 1)
    travel = grbl.angular_travel(arc)
    expected_travel = (turn + 2 * math.pi * (turns - 1)) * (1 if ccw else -1)
    if turn > 2e-6:
        assert travel == pytest.approx(expected_travel, abs=1e-9)
    points = grbl.arc_points(arc, tolerance)
    assert len(points) == max(1, grbl.chord_count(radius, travel, tolerance))
    # mc_arc's third-order rotation drifts off the circle by up to theta^4 / 24 of the radius
    # per chord, for N_ARC_CORRECTION chords between exact corrections
    theta = abs(travel) / len(points)
    drift = radius * grbl.N_ARC_CORRECTION * theta ** 4 / 24 * 1.01 + 1e-9
    assert points[-1] == arc.end
    previous = arc.start
    for index, p in enumerate(points, start=1):
        assert math.hypot(p[u] - centre[u], p[v] - centre[v]) \
            == pytest.approx(radius, abs=drift)
        assert p[w] - arc.start[w] == pytest.approx(rise * index / len(points), abs=1e-9)
        middle = (math.hypot((p[u] + previous[u]) / 2 - centre[u], (p[v] + previous[v]) / 2 - centre[v]))
        if len(points) > 1:
            widened = tolerance * ((len(points) + 1) / len(points)) ** 2
            assert radius - middle <= widened * (1 + 1e-6) + drift         # the sagitta
        previous = p


def test_junction_formula_is_the_planners():
    accel = SETTINGS.accel_mm_s2
    for before, after in [((1, 0, 0), (0, 1, 0)), ((1, 0, 0), (0.6, 0.8, 0)), ((0, 0, 1), (0.6, 0, -0.8))]:
        assert math.sqrt(grbl.junction_speed_sqr(before, after, accel, 0.01)) == pytest.approx(
            junction_speed(before, after, accel, 0.01))
    assert math.sqrt(grbl.junction_speed_sqr((1, 0, 0), (0, 1, 0), accel, 0.01)) == pytest.approx(4.1317148754)
    assert grbl.junction_speed_sqr((1, 0, 0), (1, 0, 0), accel, 0.01) == grbl.SOME_LARGE_VALUE
    assert grbl.junction_speed_sqr((1, 0, 0), (-1, 0, 0), accel, 0.01) == 0.0


def test_one_line_and_a_dwell():
    program = Program([Line((0, 0, 0), (10, 0, 0), 3000.0, 1), Dwell(1.5, 2), Event("spindle_off", 0, 3)])
    result = grbl.run(program, SETTINGS)
    assert result.time_s == pytest.approx(trapezoid_time(10, 0, 0, 50, 500) + 1.5)
    assert (result.blocks, result.dwell_s) == (1, 1.5)


def test_buffer_limits_the_speed_of_short_blocks():
    """100 collinear 0.1 mm blocks at a high feed: the running block's exit is what the 14
    blocks behind it in the 15-block buffer can brake from."""
    program = Program([Line((i / 10, 0, 0), ((i + 1) / 10, 0, 0), 6000.0, i) for i in range(100)])
    result = grbl.run(program, SETTINGS, keep_speeds=True)
    top = max(exit_speed for _, exit_speed, _ in result.speeds)
    assert top == pytest.approx(math.sqrt(2 * 500 * 1.4))
    small = grbl.run(program, grbl.GrblSettings(**{**SETTINGS.__dict__, "buffer_size": 4}), keep_speeds=True)
    assert max(e for _, e, _ in small.speeds) == pytest.approx(math.sqrt(2 * 500 * 0.2))


def test_rapids_and_empty_blocks():
    program = Program([Line((0, 0, 0), (0, 0, 0.001), None, 1),          # no step: dropped
                       Line((0, 0, 0.001), (30, 40, 0), None, 2)])
    result = grbl.run(program, SETTINGS, keep_speeds=True)
    assert result.blocks == 1
    assert result.speeds[0][2] == pytest.approx(100.0 / 0.8)               # y at 100 mm/s caps it


# moves on the 0.01 mm step grid: short ones (up to 0.3 mm, where the look-ahead binds) and
# long ones; runs of short ones along one direction, whose junctions do not slow them
short = st.lists(st.integers(1, 10).map(lambda n: (3 * n / 100, n / 100, 0.0)), min_size=1, max_size=40)
# (longer than the junction deviation: runs shorter than it are corners of their own here)
long = st.integers(2, 3000).map(lambda n: n / 100) | st.integers(-3000, -2).map(lambda n: n / 100)
feeds = st.none() | st.floats(30, 9000)
items = st.one_of(st.tuples(st.just("line"), st.tuples(long, long, long).map(lambda m: [m]), feeds),
                  st.tuples(st.just("line"), short, feeds),
                  st.tuples(st.just("dwell"), st.floats(0, 2)), st.tuples(st.just("event")))


@settings(max_examples=150, deadline=None)
@given(st.lists(items, min_size=1, max_size=20))
def test_grbl_streaming_equals_our_plan_with_its_window(sequence):
    """On lines, Grbl's streamed plan is our planner's with a window of buffer_size - 2 (the
    block running and the 14 behind it): both implementations agree on every program."""
    program_moves = []
    position = (0.0, 0.0, 0.0)
    for number, item in enumerate(sequence, start=1):
        if item[0] == "line":
            for delta in item[1]:
                end = tuple(round(p + d, 2) for p, d in zip(position, delta))
                program_moves.append(Line(position, end, item[2], number))
                position = end
        elif item[0] == "dwell":
            program_moves.append(Dwell(item[1], number))
        else:
            program_moves.append(Event("coolant_off", 0, number))
    program = Program(program_moves)
    segments, dwell = program_segments(program, MACHINE)
    ours = machine_time(plan(segments, junction_deviation_mm=0.01, window=SETTINGS.buffer_size - 2)) + dwell
    reference = grbl.run(program, SETTINGS)
    assert reference.blocks == len(segments)
    assert reference.time_s == pytest.approx(ours, rel=1e-9, abs=1e-12)
    whole = machine_time(plan(segments, junction_deviation_mm=0.01)) + dwell
    assert whole <= reference.time_s * (1 + 1e-9)


def test_arc_geometry_of_a_helix():
    arc = Arc((1.0, 0.0, 0.0), (1.0, 0.0, 2.0), (0.0, 0.0, 0.0), "XY", True, 1, 600.0, 1)
    length, radius, start_unit, end_unit = arc_geometry(arc)
    assert radius == 1.0
    assert length == pytest.approx(math.hypot(2 * math.pi, 2.0))
    assert start_unit == pytest.approx((0.0, 2 * math.pi / length, 2.0 / length))
    assert end_unit == pytest.approx(start_unit)
    clockwise = Arc((0.0, 1.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, 0.0), "XY", False, 1, 600.0, 1)
    length, _, start_unit, end_unit = arc_geometry(clockwise)
    assert length == pytest.approx(math.pi / 2)
    assert start_unit == pytest.approx((1.0, 0.0, 0.0), abs=1e-12)
    assert end_unit == pytest.approx((0.0, -1.0, 0.0), abs=1e-12)


def test_program_segments_stops_and_tolerances():
    from interp.gcode.interpreter import interpret
    program = interpret("G21 G90 G1 X10 F600\nX10 Y10\nG4 P0.5\nG64 P0.002 X0 Y10\nG61 X0 Y0\n"
                        "G64 G2 X0 Y0 I5 J0\nM2\n")
    segments, dwell = program_segments(program, MACHINE)
    assert dwell == 0.5
    assert [s.stop_before for s in segments] == [True, False, True, True, False]
    assert [s.tolerance_mm for s in segments] == [None, None, 0.002, None, None]
    assert segments[-1].radius_mm == 5.0 and segments[-1].length_mm == pytest.approx(10 * math.pi)
    assert segments[1].start_unit == (0.0, 1.0, 0.0) and segments[1].feed_mm_s == 10.0


def test_benchmark_table(tmp_path, monkeypatch, capsys):
    from interp.benchmarks import machine_time as benchmark
    (tmp_path / "a.ngc").write_text("G21 G90 G1 X10 F6000\nY10\nG2 X10 Y10 I-1 J0\nG1 G61 X0\nY0\nM2\n")
    (tmp_path / "b.nc").write_text("G21 G42 X1\n")          # refused by the front end
    monkeypatch.setattr(benchmark, "corpus_files", lambda: sorted(tmp_path.iterdir()))
    assert benchmark.main([]) == 0
    out = capsys.readouterr().out
    row = next(line for line in out.splitlines() if line.startswith("| a.ngc"))
    ours, window, grbl_s, ratio, arcs = [c.strip() for c in row.split("|")[2:7]]
    assert float(ratio) == pytest.approx(float(ours) / float(grbl_s), abs=1e-4)
    assert float(window) >= float(ours) and arcs.startswith("1 / ")
    assert "refused: b.nc" in out
    assert "a.ngc" in out.split("whole-program plan slower")[1]      # the G61 stops: slower
    assert "G61 exact stops" in out
