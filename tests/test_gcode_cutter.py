# SPDX-License-Identifier: Apache-2.0
"""Cutter radius compensation (G40, G41, G42, G41.1, G42.1): the tool's path the interpreter
makes, checked against the programmed path (every point of the compensated contour at the
tool's radius from it), the entry and exit moves, outside-corner arcs, inside-corner trims,
and each refusal with its line."""
from __future__ import annotations

import math
import os
import re
from pathlib import Path

import pytest
from hypothesis import given, settings, strategies as st

from interp.gcode.cutter import BEND, GOUGE_TOLERANCE
from interp.gcode.errors import GcodeError
from interp.gcode.interpreter import interpret
from interp.gcode.moves import PLANES, Arc, Event, Line

CORPUS = Path(os.environ.get("INTERP_GCODE_CORPUS", Path(__file__).resolve().parents[2] / "shared" / "gcode"))


def ends(moves):
    return [tuple(round(v, 9) for v in m.end[:2]) for m in moves]


def close(a, b, tol=1e-9):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


def points(move, n=24):
    """Points along a move (XY)."""
    if isinstance(move, Line):
        return [(move.start[0] + (move.end[0] - move.start[0]) * k / n,
                 move.start[1] + (move.end[1] - move.start[1]) * k / n) for k in range(n + 1)]
    c = move.centre
    a0 = math.atan2(move.start[1] - c[1], move.start[0] - c[0])
    a1 = math.atan2(move.end[1] - c[1], move.end[0] - c[0])
    sweep = (a1 - a0) % (2 * math.pi) if move.ccw else -((a0 - a1) % (2 * math.pi))
    if abs(sweep) < 1e-12:
        sweep = 2 * math.pi if move.ccw else -2 * math.pi
    radius = math.dist(move.start[:2], c[:2])
    return [(c[0] + radius * math.cos(a0 + sweep * k / n), c[1] + radius * math.sin(a0 + sweep * k / n))
            for k in range(n + 1)]


def distance_to_segment(p, a, b):
    ab = (b[0] - a[0], b[1] - a[1])
    length = ab[0] ** 2 + ab[1] ** 2
    t = 0.0 if length == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / length))
    return math.dist(p, (a[0] + t * ab[0], a[1] + t * ab[1]))


def distance_to_move(p, move, plane="XY"):
    """The distance from a point of the plane to a programmed Line or Arc (projected)."""
    u, v, _ = PLANES[plane]
    a, b = (move.start[u], move.start[v]), (move.end[u], move.end[v])
    if isinstance(move, Line):
        return distance_to_segment(p, a, b)
    c = (move.centre[u], move.centre[v])
    radius = math.dist(a, c)
    turn = math.atan2(p[1] - c[1], p[0] - c[0]) - math.atan2(a[1] - c[1], a[0] - c[0])
    sweep = math.atan2(b[1] - c[1], b[0] - c[0]) - math.atan2(a[1] - c[1], a[0] - c[0])
    sign = 1 if move.ccw else -1
    if (sign * turn) % (2 * math.pi) <= (sign * sweep) % (2 * math.pi) or a == b:
        return abs(math.dist(p, c) - radius)
    return min(math.dist(p, a), math.dist(p, b))


def in_plane(move, plane):
    """A move with the plane's (u, v, w) as its (x, y, z)."""
    def turn(point):
        return tuple(point[a] for a in PLANES[plane])
    if isinstance(move, Line):
        return Line(turn(move.start), turn(move.end), move.feed, move.line)
    return Arc(turn(move.start), turn(move.end), turn(move.centre), "XY", move.ccw, move.turns, move.feed, move.line)


def chained(moves):
    """Each move starts where the one before ended."""
    shifts = [m for m in moves if isinstance(m, (Line, Arc))]
    return all(close(a.end, b.start) for a, b in zip(shifts, shifts[1:]))


def square(code, d, extra=""):
    word = "" if d is None else f" D{d}"
    return (f"G21 G90 G17\nG0 X-10 Y-10\n{code}{word} G1 X0 Y0 F600\n{extra}G1 X20\nY20\nX0\nY0\n"
            "G40 G1 X-10 Y-10\nM2\n")


def test_inside_a_square():
    """G41 on a counter-clockwise square keeps the tool inside: its sides 2 mm in, the inside
    corners met; LinuxCNC's entry (square to the line from the tool to the corner), an outside
    arc onto the first side, the exit.  Entering at the corner starts the first side at
    (0, 2), on the last side's wall, and G40 ends the last side at (2, 0), on the first side's:
    the warnings say so.  Entering in the middle of a side from inside, and running on past
    the start, cuts nothing."""
    program = interpret(square("G41.1", 4))
    moves = program.moves
    assert chained(moves) and program.warnings == [
        "line 4: cutter compensation: the tool (radius 2 mm) cuts 2 mm into the programmed path of line 7",
        "line 7: cutter compensation: the tool (radius 2 mm) cuts 2 mm into the programmed path of line 4"]
    program = interpret("G0 X10 Y10\nG41.1 D4 G1 X10 Y0 F600\nX20\nY20\nX0\nY0\nX15\nG40 X10 Y10\n")
    assert chained(program.moves) and program.warnings == []
    assert ends(program.moves[2:7]) == [(18, 2), (18, 18), (2, 18), (2, 2), (15, 2)]
    entry, arc = moves[1], moves[2]
    assert close(entry.end, (-2 ** 0.5, 2 ** 0.5, 0.0))
    assert isinstance(arc, Arc) and not arc.ccw and close(arc.centre, (0, 0, 0)) and close(arc.end, (0, 2, 0))
    assert ends(moves[3:7]) == [(18, 2), (18, 18), (2, 18), (2, 0)]
    assert moves[7] == Line((2.0, 0.0, 0.0), (-10.0, -10.0, 0.0), 600.0, 8) and moves[8].name == "program_end"


def test_outside_a_square():
    """G42 on the same square keeps the tool outside: an arc about each corner but the first
    (the entry turns into it)."""
    moves = interpret(square("G42.1", 4)).moves
    assert chained(moves)
    arcs = [m for m in moves if isinstance(m, Arc)]
    assert [tuple(round(v, 9) for v in a.centre[:2]) for a in arcs] == [(20, 0), (20, 20), (0, 20)]
    assert all(a.ccw for a in arcs)
    assert moves[-2].start[:2] == pytest.approx((-2, 0)) and moves[-2].end[:2] == pytest.approx((-10, -10))


def test_tool_table_diameter_and_loaded_tool():
    tools = {3: {"length_mm": 0.0, "diameter_mm": 6.0}}
    by_d = interpret(square("G41", 3), tools=tools).moves
    assert ends(by_d[3:7]) == [(17, 3), (17, 17), (3, 17), (3, 0)]
    loaded = interpret(square("T3 M6\nG41", None), tools=tools).moves
    assert ends([m for m in loaded if isinstance(m, Line)][2:6]) == [(17, 3), (17, 17), (3, 17), (3, 0)]
    zero = interpret(square("G41", 0)).moves                                 # D0: no offset
    assert ends(zero[1:6]) == [(0, 0), (20, 0), (20, 20), (0, 20), (0, 0)]


def test_arcs_z_moves_and_events():
    """An arc on the inside takes R - r, on the outside R + r; a tangent arc meets its line
    without a corner; a Z move and an M0 wait where the tool is; inch units."""
    text = ("G20 G90\nG0 X-1 Y0 Z0.1\nG42.1 D0.2 G1 X0 Y0 F20\nG1 Z-0.05\nG2 X2 Y0 R1\n"
            "G3 X4 Y0 R1\nM0\nG1 Y-2\nG40 G0 X-1\nM2\n")
    moves = interpret(text).moves
    assert chained(moves)
    arcs = [m for m in moves if isinstance(m, Arc) and m.centre[0] in (25.4, 3 * 25.4)]
    r = 0.1 * 25.4
    assert [math.dist(a.start[:2], a.centre[:2]) for a in arcs] == pytest.approx([25.4 - r, 25.4 + r])
    plunge = next(m for m in moves if m.line == 4)
    assert plunge.start[:2] == plunge.end[:2] == pytest.approx(moves[1].end[:2]) and plunge.end[2] == pytest.approx(-1.27)
    pause = next(k for k, m in enumerate(moves) if isinstance(m, Event) and m.name == "pause")
    assert moves[pause - 1].end[:2] == pytest.approx((4 * 25.4 + r, 0))        # where the arc's end settled
    assert isinstance(moves[pause + 1], Arc) and moves[pause + 1].line == 8     # then the corner's arc


def test_without_g40_the_tool_stays():
    program = interpret("G0 X-10\nG41.1 D2 G1 X0 F100\nX10\nM2\n")
    assert program.end_machine == pytest.approx((10, 1, 0)) and program.moves[-2].end[:2] == pytest.approx((10, 1))
    assert interpret("G0 X-10\nG41.1 D2 G1 X0 F100\nX10\n").end_machine == pytest.approx((10, 1, 0))


@pytest.mark.parametrize("text, message", [
    ("G0 X-1\nG41.1 D4 G1 X0 F100\nX10\n", "line 2, column 1: the entry move after G41 / G42 must be longer than "
                                         "the tool's radius (2 mm): it is 1 mm"),
    ("G0 X-10\nG41.1 D4 G1 X0 F100\nG3 X2 Y0 R1\n", "line 3, column 1: the tool's radius (2 mm) is not less than "
                                                   "the arc's (1 mm) on the side it cuts"),
    ("G0 X-10\nG42.1 D4 G1 X0 F100\nX10\nY1\nX20\n", "line 5, column 1: the tool (radius 2 mm) does not fit here: "
                                                    "the compensated move before this one would run backwards"),
    ("G0 X-10\nG42.1 D4 G1 X0 F100\nX10\nY-1\nG40\n", "line 4, column 1: the tool (radius 2 mm) does not fit here"),
    ("G0 X-10\nG42.1 D4 G1 X0 F100\nX10\nY-1\nM2\n", "line 4, column 1: the tool (radius 2 mm) does not fit here"),
    ("G0 X-10\nG42.1 D4 G1 X0 F100\nX10\nY-1\n", "line 4, column 1: the tool (radius 2 mm) does not fit here"),
    ("G0 X-10\nG41.1 D4 G1 X0 F100\nX10\nG40\nG40\nG2 X20 R5\n", "line 6, column 1: the exit move after G40 "
                                                                  "must be a straight line"),
    ("G19 G41.1 D1\n", "line 1, column 5: G41.1: cutter compensation works in the XY (G17) and XZ (G18) planes"),
    ("G10 L1 P1 R-1\nG41 D1\n", "line 2, column 5: D1: tool 1 has a negative diameter (-2 mm"),
    ("G41.1 D4\nG38.2 Z-1 F100\n", "line 2, column 1: G38.2: G38.2 cannot be used with cutter compensation on"),
    ("G42.1 D4\nG41.1 D2\n", "line 2, column 1: G41.1: cutter compensation is already on: turn it off (G40) first"),
    ("G41.1 D4\nG19\n", "line 2, column 1: G19: a change of plane cannot be used with cutter compensation on"),
    ("G41.1 D4\nG81 X1 Y1 Z-1 R1 F100\n", "line 2, column 1: G81: a canned cycle cannot be used with cutter "
                                          "compensation on"),
    ("G41.1 D4\nG28\n", "line 2, column 1: G28: G28 / G30 cannot be used"),
    ("G41.1 D4\nG53 G0 X1\n", "line 2, column 1: G53: G53 cannot be used"),
    ("G41.1 D4\nM6 T1\n", "line 2, column 1: M6: a tool change cannot be used"),
    ("G41.1 D4\nG2 X1 Y0 R5 F100\n", "line 2, column 1: the entry move after G41 / G42 must be longer than the "
                                      "tool's radius (2 mm): it is 1 mm"),
    ("G0 X-10\nG41.1 D2 G1 X0 F100\nX10\nG40\nG2 X20 R5\n", "line 5, column 1: the exit move after G40 must be a "
                                                           "straight line"),
    ("G41 D3\n", "line 1, column 5: D3: tool 3 is not in the tool table: its diameter is not known"),
    ("G41 D1.5\n", "line 1, column 5: D1.5: D must be a tool number"),
    ("G41.1\n", "line 1, column 1: G41.1: needs a D word (the tool's diameter)"),
    ("G41.1 D-1\n", "line 1, column 7: D-1: the tool's diameter cannot be negative"),
    ("G42.1 D2 L3\n", "line 1, column 10: L3: a lathe tool orientation (L) is not supported"),
    ("G0 X1 D3\n", "line 1, column 7: D3: D word without G41, G42, G41.1 or G42.1"),
])
def test_refused(text, message):
    with pytest.raises(GcodeError) as info:
        interpret(text)
    assert str(info.value).startswith(message), str(info.value)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(0.0, 1.0), min_size=3, max_size=9), st.floats(3.0, 30.0), st.floats(0.05, 6.0),
       st.booleans(), st.booleans())
def test_every_point_of_a_convex_contour_at_the_radius(angles, size, radius, left, ccw):
    """A random convex polygon, run twice round either way with the tool on either side: every
    point of the second round's compensated sides (but the last, which G40 ends without a
    corner) is at the tool's radius from the programmed polygon (within r (1 - cos BEND) where
    a bend below BEND joins two sides as they are); or a gouge warning names one of them and
    the tool does come nearer; or the interpreter refuses the program (a tool too big for the
    inside) with one line."""
    turn = sorted({round(a * 2 * math.pi, 6) for a in angles})
    corners = [(size * math.cos(a), size * math.sin(a)) for a in turn]
    if len(corners) < 3 or any(math.dist(p, q) < 0.5 for p, q in zip(corners, corners[1:] + corners[:1])):
        return
    area = sum(p[0] * q[1] - q[0] * p[1] for p, q in zip(corners, corners[1:] + corners[:1])) / 2
    if area < 1.0:
        return
    if not ccw:
        corners.reverse()
    away = 1 + (2 * size + 2 * radius) / size                  # the entry: longer than the radius
    start = (corners[0][0] * away, corners[0][1] * away)
    text = [f"G21 G90\nG0 X{start[0]:.9f} Y{start[1]:.9f}",
            f"{'G41.1' if left else 'G42.1'} D{2 * radius:.9f} G1 X{corners[0][0]:.9f} Y{corners[0][1]:.9f} F500"]
    text += [f"X{x:.9f} Y{y:.9f}" for x, y in corners[1:] + corners[:1]] * 2
    text += [f"G40 X{start[0]:.9f} Y{start[1]:.9f}", "M2"]
    try:
        program = interpret("\n".join(text) + "\n")
    except GcodeError as error:
        assert "does not fit" in str(error) and "\n" not in str(error)
        return
    moves = program.moves
    n = len(corners)
    assert chained(moves)
    warned = [w for w in program.warnings if 4 + n <= int(w.split(":")[0][5:]) <= 2 + 2 * n]
    radius = round(2 * radius, 9) / 2
    edges = list(zip(corners, corners[1:] + corners[:1]))
    slack = radius * (1 - math.cos(BEND)) + 1e-6
    contour = [m for m in moves if isinstance(m, (Line, Arc)) and 4 + n <= m.line <= 2 + 2 * n]
    assert contour
    nearest = min(min(distance_to_segment(p, a, b) for a, b in edges) for move in contour for p in points(move))
    if warned:                      # (a spike within 0.05 rad of a reversal is rounded, as LinuxCNC does)
        assert nearest < radius - GOUGE_TOLERANCE, warned
        return
    for move in contour:
        for p in points(move):
            assert min(distance_to_segment(p, a, b) for a, b in edges) == pytest.approx(radius, abs=slack), (move, p)


@pytest.mark.skipif(not (CORPUS / "lcnc_comp.ngc").is_file(), reason=f"no G-code corpus at {CORPUS}")
def test_linuxcnc_sample():
    """LinuxCNC's comp.ngc with tool 1 of its sim tool table (1/8 inch): G42 and G41 in the XY
    plane and in the ZX plane (G18), R arcs on both sides of the tool.  Every point of each
    compensated contour (the moves after the entry up to G40) is at the tool's radius from the
    programmed path of those lines, and the moves chain."""
    text = (CORPUS / "lcnc_comp.ngc").read_text()
    program = interpret(text, tools={1: {"length_mm": 0.0, "diameter_mm": 3.175}})
    moves = program.moves
    assert chained(moves) and program.warnings == []
    programmed = interpret(text.replace("g42 d1", "").replace("g41 d1", "")).moves
    lines = text.splitlines()
    comp_lines = [n + 1 for n, t in enumerate(lines) if t.strip() in ("g41 d1", "g42 d1")]
    assert len(comp_lines) == 4
    for first in comp_lines:
        plane = "XY" if first < 30 else "ZX"
        end = next(n + 1 for n in range(first, len(lines)) if lines[n].strip() == "g40")
        contour = range(first + 2, end)                         # after the entry move, up to G40
        path = [m for m in programmed if isinstance(m, (Line, Arc)) and m.line in contour]
        compensated = [m for m in moves if isinstance(m, (Line, Arc)) and m.line in contour]
        assert len(compensated) >= len(path) == 5
        for move in compensated:
            for point in points(in_plane(move, plane)):
                distance = min(distance_to_move(point, m, plane) for m in path)
                assert distance == pytest.approx(3.175 / 2, abs=1e-6), (first, move, point)


@pytest.mark.parametrize("chord, digits", [(0.01, 4), (0.05, 3)])
@pytest.mark.parametrize("code, offset", [("G41.1", 3.0), ("G42.1", -3.0)])
def test_a_cam_polyline(code, offset, chord, digits):
    """A circle of 20 mm radius in short chords with few decimals, as CAM programs give it:
    the rounding makes small bends both ways (up to about 0.01 rad), which join as they are
    (LinuxCNC's 0.05 rad tolerance) instead of refusing the program; the tool's centre stays
    within 0.01 mm of the circle 3 mm outside (G41, clockwise) or inside (G42), after a
    tangential lead-in."""
    n = round(2 * math.pi * 20 / chord)
    ring = [(20 * math.cos(-2 * math.pi * k / n), 20 * math.sin(-2 * math.pi * k / n)) for k in range(n + 1)]
    text = ["G21 G90 G0 X20 Y10", f"{code} D6 G1 X20 Y0 F600"]
    text += [f"X{x:.{digits}f} Y{y:.{digits}f}" for x, y in ring[1:]] + ["G40 G1 X30 Y0", "M2"]
    program = interpret("\n".join(text) + "\n")
    moves = [m for m in program.moves if isinstance(m, (Line, Arc))]
    assert chained(moves) and program.warnings == []
    contour = [m for m in moves if 4 <= m.line <= n + 2]
    assert len(contour) >= n - 1
    assert all(abs(math.dist(m.end[:2], (0, 0)) - 20 - offset) < 0.01 for m in contour)


def test_an_arc_entry_and_a_rapid_corner():
    """An arc as the entry move (LinuxCNC's): it ends the radius from its programmed end along
    the arc's radius, about a centre moved so that it stays an arc.  A bend before a G0 gets a
    straight rapid, not an arc."""
    moves = interpret("G0 X-10 Y0\nG41.1 D2 G2 X10 Y0 R10 F100\nG0 X0 Y-10\nG40 X20 Y-20\n").moves
    assert chained(moves)
    entry = moves[1]
    assert isinstance(entry, Arc) and not entry.ccw and close(entry.end, (11, 0, 0))
    assert math.dist(entry.start[:2], entry.centre[:2]) == pytest.approx(math.dist(entry.end[:2], entry.centre[:2]))
    corner = moves[2]
    assert isinstance(corner, Line) and corner.feed is None and close(corner.end, (10 + 0.5 ** 0.5, -(0.5 ** 0.5), 0))


def test_a_gouge_is_a_warning():
    """Each corner is decided from the two moves that meet there (LinuxCNC's way); a shape the
    tool is too big for beyond that (here a half circle of 5 mm radius turning back over the
    line before it, a 2 mm tool outside it) runs with one warning per line that cuts in."""
    program = interpret("G0 X-10\nG41.1 D4 G1 X0 F100\nX10\nG2 X10 Y10 J5\nG40 G1 X20\nM2\n")
    assert chained(program.moves)
    assert [re.sub(r"cuts 1\.\d+ mm", "cuts 1.x mm", w) for w in program.warnings] == [
        "line 3: cutter compensation: the tool (radius 2 mm) cuts 1.x mm into the programmed path of line 4",
        "line 4: cutter compensation: the tool (radius 2 mm) cuts 1.x mm into the programmed path of line 3"]
    # a corner's arc is checked against two moves on: the corner of line 4 cuts into line 6
    program = interpret("G0 X-10 Y0\nG42.1 D4 G1 X0 Y0 F100\nX10 Y0\nX10 Y10\nX20 Y10\nX11 Y-6\nX11 Y-20\n"
                        "G40 X40 Y-20\n")
    assert program.warnings[0].startswith("line 4: cutter compensation: the tool (radius 2 mm) cuts 0.18")
    assert program.warnings[0].endswith("mm into the programmed path of line 6")


def test_a_tool_bigger_than_an_inside_curve_of_chords():
    """A pocket of 2 mm radius in 0.05 mm chords with a 3 mm tool inside: every bend is below
    0.05 rad and joined as it is, which carries the tool to the far side; the bends' sum over
    the tool's radius of path says so."""
    n = round(2 * math.pi * 2 / 0.05)
    ring = [(2 * math.cos(2 * math.pi * k / n), 2 * math.sin(2 * math.pi * k / n)) for k in range(n + 1)]
    text = ["G0 X2 Y-20", "G41.1 D6 G1 X2 Y0 F100"] + [f"X{x:.4f} Y{y:.4f}" for x, y in ring[1:]] + ["G40 X0 Y0"]
    warnings = interpret("\n".join(text) + "\n").warnings
    assert len(warnings) > n / 2
    assert any("is bigger than the inside curve here" in w and "it cuts into the far side" in w for w in warnings)


@pytest.mark.parametrize("text", [
    # a tangent line -> arc -> line with coordinates rounded to 3 decimals (LinuxCNC runs it)
    "G0 X-7.071 Y-7.071\nG41.1 D2 G1 X0 Y0 F100\nX7.071 Y7.071\nG3 X7.071 Y14.142 I-3.536 J3.536\n"
    "G1 X0.000 Y21.213\nG40 G1 X10.000 Y21.213\n",
    # a line ending 3e-7 mm from the next arc's start: still joined
    "G0 X20.3184 Y10.0051\nG41.1 D2 G1 X20 Y20 F100\nX19.6816 Y29.9949\nG3 X12.5763 Y34.3697 I-4.9975 J-0.1592\n"
    "G1 X3.5083 Y30.1540\nG40 X0 Y0\n",
    # a reversal off by 0.0001 mm: round the outside, as LinuxCNC does within 0.05 rad of it
    "G0 X-10 Y5\nG41.1 D4 G1 X0 Y0 F100\nX10\nX0 Y0.0001\nX-5 Y0.0001\nG40 X-10 Y10\n",
    # an arc whose end radius differs from its start's by 0.002 mm (within the tolerance)
    "G0 X0 Y-10\nG41.1 D2 G1 X0 Y0 F100\nX10\nG3 X19.998 Y10 I0 J10\nG1 Y20\nG40 X0 Y30\n",
])
def test_rounded_contours_run(text):
    program = interpret(text)
    assert chained(program.moves) and program.warnings == []


def test_after_g40():
    """A plane change before the exit move leaves the path where it was; G38.2 runs after G40
    (the exit move); D0 compensates nothing, so an arc may follow its G40."""
    moves = interpret("G0 X-10 Y0\nG41.1 D4 G1 X0 Y0 F100\nX10\nG40\nG18\nG1 X20\nG0 X30\n").moves
    assert chained(moves) and ends(moves[-2:]) == [(20, 0), (30, 0)]
    moves = interpret("G0 X-10\nG41.1 D4 G1 X0 F100\nX10\nG40\nG38.2 Z-5 F100\n").moves
    assert chained(moves) and moves[-1].probe == 382 and moves[-1].end == (10, 2, -5)
    moves = interpret("G0 X-10\nG41.1 D0 G1 X0 F100\nX10\nG40 G2 X20 R10\n").moves
    assert chained(moves) and isinstance(moves[-1], Arc)


def test_a_second_g40_keeps_the_exit_move():
    moves = interpret("G0 X-10\nG41.1 D4 G1 X0 F100\nX10\nG40\nG40\nG1 X20\nM2\n").moves
    assert chained(moves) and moves[-2].start[:2] == pytest.approx((10, 2)) and moves[-2].end[:2] == (20, 0)
