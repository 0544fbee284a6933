# SPDX-License-Identifier: Apache-2.0
"""G5 (cubic) and G5.1 (quadratic) splines: interp/gcode/spline.py cuts the curve into arcs
and lines within TOLERANCE_MM of it; the interpreter takes LinuxCNC's words and refusals."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from interp.cli import main
from interp.commands.gcode import compile_text
from interp.gcode.errors import GcodeError
from interp.gcode.interpreter import interpret
from interp.gcode.machine import load_machine
from interp.gcode.moves import Arc
from interp.gcode.spline import TOLERANCE_MM, SplineError, bezier, length, pieces


def off_piece(p, piece) -> float:
    """The distance of p from a piece (a line segment, or an arc: its circle within its sweep,
    else its nearer end)."""
    a, b = piece[1], piece[2]
    if piece[0] == "line":
        dx, dy = b[0] - a[0], b[1] - a[1]
        span = dx * dx + dy * dy
        t = 0.0 if span == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / span))
        return math.hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy)
    centre, ccw = piece[3], piece[4]

    def swept(q):
        angle = math.atan2(q[1] - centre[1], q[0] - centre[0]) - math.atan2(a[1] - centre[1], a[0] - centre[0])
        return (angle if ccw else -angle) % (2 * math.pi)
    if swept(p) <= swept(b):
        return abs(math.dist(p, centre) - math.dist(a, centre))
    return min(math.dist(p, a), math.dist(p, b))


def on_piece(piece, k: int, n: int):
    """The point k/n along a piece."""
    a, b = piece[1], piece[2]
    if piece[0] == "line":
        return (a[0] + (b[0] - a[0]) * k / n, a[1] + (b[1] - a[1]) * k / n)
    centre, ccw = piece[3], piece[4]
    r = math.dist(a, centre)
    a0 = math.atan2(a[1] - centre[1], a[0] - centre[0])
    sweep = (math.atan2(b[1] - centre[1], b[0] - centre[0]) - a0) * (1 if ccw else -1) % (2 * math.pi)
    angle = a0 + (1 if ccw else -1) * sweep * k / n
    return (centre[0] + r * math.cos(angle), centre[1] + r * math.sin(angle))


def check_pieces(control, parts, tolerance=TOLERANCE_MM):
    """The pieces run from the first control point to the last, end to end, the curve within
    tolerance of them and they within tolerance of the curve (both ways, densely sampled)."""
    assert parts[0][1] == control[0] and parts[-1][2] == control[-1]
    for before, after in zip(parts, parts[1:]):
        assert before[2] == after[1]
    curve = [bezier(control, k / 4000) for k in range(4001)]
    for p in curve:
        assert min(off_piece(p, part) for part in parts) <= tolerance + 1e-9
    a, b = np.array(curve[:-1]), np.array(curve[1:])         # the curve as a fine polyline
    span = np.maximum(((b - a) ** 2).sum(axis=1), 1e-300)
    for part in parts:
        for k in range(1, 8):
            q = np.array(on_piece(part, k, 8))
            t = np.clip(((q - a) * (b - a)).sum(axis=1) / span, 0.0, 1.0)
            assert np.sqrt(((a + t[:, None] * (b - a) - q) ** 2).sum(axis=1)).min() <= tolerance + 1e-6


def test_an_s_curve_is_a_few_arcs():
    control = [(0.0, 0.0), (0.0, 10.0), (10.0, 10.0), (10.0, 0.0)]
    parts = pieces(control)
    check_pieces(control, parts)
    assert all(part[0] == "arc" for part in parts) and len(parts) <= 20
    assert length(parts) == pytest.approx(20.0, abs=1e-3)


@pytest.mark.parametrize("control", [
    [(0.0, 7.598), (0.0, 5.356), (0.0, 49.1), (0.0, 46.49)],     # dips below its start, overshoots its end
    [(0.0, 1.0), (0.0, 17.0), (0.0, 0.0)],                        # goes up to 8.7576 and comes back
    [(0.0, 0.0), (0.0, 17.0), (0.0, 1.0)],                        # ... the other way (hypothesis found it)
    [(-161.39, 262.93), (-206.56, 866.76), (977.61, -902.6), (426.53, -763.22)],
    [(0.0, 24.0), (0.0, 0.0), (0.0, 8.0), (1.0, 0.0)],            # a nearly quadratic distance (rounding)
    [(-21.637, 41.817), (-13.117, -22.44), (39.389, -27.735), (-22.907, -1.306)],   # past a line's end
])
def test_curves_that_turn_back_along_a_piece(control):
    """A curve that runs past a chord's end, or back along it, is followed there: lines are
    checked exactly (the polynomials' extremes), arcs at 32 points with a margin (a
    reviewer's cases: 0.11 mm and 7.6 um cut off, 1.0108 um over)."""
    parts = pieces(control)
    check_pieces(control, parts)
    if all(x == 0.0 for x, _y in control):      # (along x = 0: lines, whose ends reach the extremes)
        ys = [bezier(control, k / 10000)[1] for k in range(10001)]
        ends = [part[k][1] for part in parts for k in (1, 2)]
        assert max(ends) >= max(ys) - TOLERANCE_MM and min(ends) <= min(ys) + TOLERANCE_MM


def test_a_far_curve_is_refused_quickly():
    with pytest.raises(SplineError):
        pieces([(0.0, 0.0), (1e8, 1e8), (1 - 1e8, 1e8), (1.0, 0.0)])
    with pytest.raises(GcodeError) as error:
        interpret("G1 F100\nG5 I100000000 J100000000 P-100000000 Q100000000 X1 Y0")
    assert str(error.value).startswith("line 2, column 1: G5: the curve needs more than 20000 arcs and lines")


def test_a_straight_curve_is_one_line():
    assert pieces([(0.0, 0.0), (1.0, 1.0), (2.0, 2.0), (3.0, 3.0)]) == [("line", (0.0, 0.0), (3.0, 3.0))]
    assert pieces([(1.0, 2.0)] * 4) == []


coordinate = st.floats(-50, 50, allow_nan=False).map(lambda v: round(v, 3))


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(coordinate, coordinate), min_size=3, max_size=4))
def test_pieces_follow_any_curve(control):
    """Random quadratic and cubic curves (loops, cusps, straight ones): the pieces join end to
    end from the start to the end and stay within the tolerance of the curve."""
    parts = pieces(control)
    if all(p == control[0] for p in control):
        assert parts == []
    else:
        check_pieces(control, parts)


def test_g5_words_as_linuxcnc_takes_them():
    """G5 I J P Q X Y: P1 = start + (I, J), P2 = end + (P, Q); a G5 right after one may leave
    out I and J (the last one's -P, -Q); G5.1 I J X Y; the moves keep Z, the block's feed and
    line."""
    program = interpret("G21 G1 Z-1 F600\nG5 I0 J10 P0 Q10 X10 Y0\nG5 P0 Q-10 X20 Y0\nG5.1 I5 J5 X30 Y0")
    moves = program.moves[1:]
    assert all(m.start[2] == m.end[2] == -1 and m.feed == 600 for m in moves)
    assert moves[0].start == (0, 0, -1) and moves[-1].end == (30, 0, -1)
    for before, after in zip(moves, moves[1:]):
        assert before.end == after.start
    firsts = {m.line: m for m in reversed(moves)}
    lasts = {m.line: m for m in moves}
    assert sorted(firsts) == [2, 3, 4] and lasts[2].end == (10, 0, -1) and lasts[3].end == (20, 0, -1)
    # the second curve mirrors the first: it leaves (10, 0) downwards, as the first arrived upwards
    assert isinstance(firsts[3], Arc) and firsts[3].ccw != firsts[2].ccw
    inch = interpret("G20 G1 F10\nG5 I0 J1 P0 Q1 X1 Y0")
    assert inch.moves[-1].end == pytest.approx((25.4, 0, 0)) and max(m.end[1] for m in inch.moves) > 15


def test_g5_in_inverse_time_takes_the_whole_curve_in_one_f():
    program = interpret("G21 G93\nG5 I0 J10 P0 Q10 X10 Y0 F2")      # 1/2 minute for about 20 mm
    feeds = {m.feed for m in program.moves}
    assert len(feeds) == 1 and feeds.pop() == pytest.approx(40.0, rel=1e-3)


@pytest.mark.parametrize("text,message", [
    ("G1 F100\nG18 G5 I1 J1 P1 Q1 X1", "line 2, column 5: G5: G5 splines must be in the XY plane (G17)"),
    ("G1 F100\nG5 I1 J1 P1 Q1 X1 Z1", "line 2, column 19: Z1: G5 moves only X and Y"),
    ("G1 F100\nG5 I1 P1 Q1 X1", "line 2, column 4: I1: G5 needs both I and J, or neither"),
    ("G1 F100\nG5 I1 J1 P1 X1", "line 2, column 1: G5: G5 needs both P and Q"),
    ("G1 F100\nG5 P1 Q1 X1", "line 2, column 1: G5: G5 needs I and J (they may be left out only right "
                             "after another G5)"),
    ("G1 F100\nG5 I1 J1 P1 Q1 X1\nG1 X2\nG5 P1 Q1 X3",
     "line 4, column 1: G5: G5 needs I and J (they may be left out only right after another G5)"),
    ("G1 F100\nG5 I1 J1 P1 Q1 X1\nG28\nG5 P1 Q1 X3",
     "line 4, column 1: G5: G5 needs I and J (they may be left out only right after another G5)"),
    ("G1 F100\nG5.1 I1 X1", "line 2, column 1: G5.1: G5.1 needs both I and J"),
    ("G5.1 I1 J1 X1", "line 1, column 1: G5.1: feed move without a feed rate (no F word yet)"),
    ("G1 F100\nG5.1 I1 J1 P1 X1", "line 2, column 12: P1: word not used by any command in this block"),
    ("G1 F100\nG5 I1 J1 P1 Q1 @1", "line 2, column 16: @1: G5 moves only X and Y"),
    ("G5.2 P1 X1 Y1", "line 1, column 1: G5.2: NURBS moves (G5.2) are not supported"),
])
def test_g5_refusals(text, message):
    with pytest.raises(GcodeError) as error:
        interpret(text)
    assert str(error.value) == message


def test_g5_refused_under_cutter_compensation():
    tools = {1: {"length_mm": 0.0, "diameter_mm": 2.0}}
    with pytest.raises(GcodeError) as error:
        interpret("G0 X-5 Y-5\nG41 D1 G1 X0 Y0 F600\nG5 I0 J10 P0 Q10 X10 Y0", tools=tools)
    assert str(error.value) == "line 3, column 1: G5: G5 cannot be used with cutter compensation on (G40 first)"
    with pytest.raises(GcodeError) as error:        # (the exit move after G40 is a straight one)
        interpret("G0 X-5 Y-5\nG41 D1 G1 X0 Y0 F600\nG1 X10 Y0\nG40\nG5.1 I5 J0.0024 X20 Y0", tools=tools)
    assert str(error.value) == ("line 5, column 1: G5.1: G5.1 cannot be the exit move after G40: a straight move "
                                "(G0 or G1) first")


def test_a_spline_is_one_move_for_exact_stop():
    """Under G61 the machine stops before the curve, not between its pieces (as between an
    arc's turns)."""
    machine = load_machine()
    _program, compiled = compile_text("G21 G61 G1 F600 X1\nG5 I0 J10 P0 Q10 X11 Y0\nG1 X12", machine)
    stops = [c.motion.stop_before for c in compiled.commands if c.motion is not None]
    assert len(stops) > 10 and stops == [True, True] + [False] * (len(stops) - 3) + [True]


def test_a_spline_through_the_compiler_and_the_rtl(tmp_path, capsys):
    """A G5 pair and a G5.1 through the front end and motion_top (Verilator): the step sums
    are the programmed end, and the steps stay within the compiler's arc take-in (2 steps)
    of the arcs and lines the curves became."""
    text = "G21 G17 G90\nG1 F600\nG5 I0 J10 P0 Q10 X10 Y0\nG5 P0 Q-10 X20 Y0\nG5.1 I5 J5 X30 Y0\nM2\n"
    machine = load_machine()
    _program, compiled = compile_text(text, machine)
    assert compiled.end_steps == (3000, 0, 0) and compiled.arcs >= 20
    source, steps = tmp_path / "g5.ngc", tmp_path / "steps.csv"
    source.write_text(text)
    assert main(["gcode", str(source), "--clock-hz", "1e5", "--steps", str(steps), "--plot",
                 str(tmp_path / "g5.png")]) == 0
    out = capsys.readouterr().out
    rows = [list(map(int, row.split(","))) for row in steps.read_text().splitlines()[1:]]
    assert [sum(row[k] for row in rows) for k in (1, 2, 3)] == [3000, 0, 0]
    deviation = float(re.search(r"max deviation ([0-9.]+) steps", out).group(1))
    assert deviation <= 2.5 and "monitor: ok" in out
