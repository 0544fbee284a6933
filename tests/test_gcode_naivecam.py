# SPDX-License-Identifier: Apache-2.0
"""Joined moves (interp/gcode/naivecam.py, machine file motion.naive_cam): LinuxCNC's naive
CAM detector, runs of G1 moves within G64's Q (or P) of a straight line as that line."""
from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from interp.cli import main
from interp.commands.gcode import compile_text
from interp.gcode.interpreter import interpret
from interp.gcode.machine import load_machine
from interp.gcode.moves import Event, Line
from interp.gcode.naivecam import MAX_CHAIN, collapse, distance_to_segment
from interp.gcode.restart import start_at

CORPUS = Path(__file__).resolve().parents[1] / ".." / "shared" / "gcode"
JOINING = load_machine(sets=["motion.naive_cam=true"])


def ends(moves):
    return [(m.start, m.end, m.line) for m in moves]


def joined(text: str):
    return collapse(interpret(text).moves)


def feed_lines(moves):
    return [m for m in moves if isinstance(m, Line) and m.feed is not None]


def test_a_gentle_curve_within_the_tolerance_is_one_line():
    """Four G1 moves whose middle points are 0.04 mm off the chord: one line from the first
    start to the last end, counted as the first move's line; the fifth, back off the chord by
    0.5 mm, starts a chain of its own."""
    moves, removed = joined("G21 G90 G64 P0.05\nG0 X0 Y0\nG1 X1 Y0.03 F600\nX2 Y0.04\nX3 Y0.03\nX4 Y0\n"
                            "X5 Y0.5\nM2\n")
    lines = [m for m in moves if isinstance(m, Line) and m.feed is not None]
    assert ends(lines) == [((0, 0, 0), (4, 0, 0), 3), ((4, 0, 0), (5, 0.5, 0), 7)]
    assert removed == 3


@pytest.mark.parametrize("mode, count", [
    ("G64 P0.05", 2),           # Q = P
    ("G64 P0.01 Q0.05", 2),     # Q decides, not P
    ("G64 P0.05 Q0", 5),        # Q0: off
    ("G64 P0.05 Q0.005", 5),    # the points are more than Q off every chord
    ("G64", 5),                 # no tolerance
    ("G61", 5), ("G61.1", 5),   # exact path / exact stop
])
def test_the_tolerance_follows_linuxcnc(mode, count):
    moves, _ = joined(f"G21 G90 {mode}\nG1 X1 Y0.03 F600\nX2 Y0.04\nX3 Y0.03\nX4 Y0\nX5 Y0.5\nM2\n")
    assert len([m for m in moves if isinstance(m, Line)]) == count


@pytest.mark.parametrize("between, feed_lines_wanted", [
    ("", 1),                    # G1 X1, X2, X3 along one line: one move
    ("F700", 2),                # another F
    ("G0 X1.5", 2),             # a rapid
    ("M8", 2),                  # an event
    ("G4 P0.1", 2),             # a dwell
    ("G64 P0.05", 2),           # a new path-control block
    ("(MSG, hello)", 2),        # a message (LinuxCNC's canonical layer ends a chain there)
    ("G92 X1", 2), ("G92.1", 2), ("G52 X0", 2), ("G10 L2 P1 X0", 2), ("G54", 2), ("G43.1 Z0", 2),
    ("G49", 2),                 # an offset change (one that changes nothing too, as LinuxCNC)
])
def test_what_ends_a_chain(between, feed_lines_wanted):
    moves, _ = joined(f"G21 G90 G64 P0.05\nG0 X0 Y0\nG1 X1 F600\n{between}\nG1 X2\nX3\nM2\n")
    assert len(feed_lines(moves)) == feed_lines_wanted


def test_arcs_and_probes_are_not_joined():
    moves, removed = joined("G21 G90 G64 P1\nG1 X1 F600\nG2 X3 I1\nG1 X4\nX5\nM2\n")
    assert removed == 1 and [type(m).__name__ for m in moves if not isinstance(m, Event)] == ["Line", "Arc", "Line"]
    moves, removed = joined("G21 G90 G64 P1\nG38.2 Z-1 F100\nG1 Z-2\nZ-3\nM2\n")
    assert removed == 1 and [(m.end[2], m.probe) for m in moves if isinstance(m, Line)] == [(-1, 382), (-3, 0)]


def test_at_most_101_moves_a_chain():
    moves = [Line((k, 0, 0), (k + 1, 0, 0), 600.0, k + 2, join=(1, 0.1)) for k in range(250)]
    out, removed = collapse(moves)
    assert [m.end[0] for m in out] == [MAX_CHAIN, 2 * MAX_CHAIN, 250] and removed == 250 - 3


def test_the_foot_is_clamped_to_the_segment():
    """A point beyond the segment's end is as far as that end: out and back along one line is
    not straight (LinuxCNC's test)."""
    assert distance_to_segment((3, 0, 0), (0, 0, 0), (2, 0, 0)) == 1
    assert distance_to_segment((1, 1, 0), (0, 0, 0), (2, 0, 0)) == 1
    assert distance_to_segment((1, 1, 0), (0, 0, 0), (0, 0, 0)) == math.sqrt(2)
    out, _ = collapse([Line((0, 0, 0), (3, 0, 0), 600.0, 2, join=(1, 0.5)),
                       Line((3, 0, 0), (2, 0, 0), 600.0, 3, join=(1, 0.5))])
    assert len(out) == 2


def test_a_chain_back_to_its_start_is_not_joined():
    """A plunge and its return end where they began: joined they would be a line of no length
    and the dot would never be cut (LinuxCNC does not link a move ending at the chain's start)."""
    moves, removed = joined("G21 G90 G64 P0.1\nG1 Z-0.05 F100\nG1 Z0\nG0 Z5\nM2\n")
    assert removed == 0 and [m.end[2] for m in feed_lines(moves)] == [-0.05, 0]


SUBROUTINE_AFTER_A_CALL = """o<finish> sub
G64 P0.01
G1 X1 F600
o<finish> endsub
G21 G90
G64 P0.5
G0 X0 Y0
o<finish> call
G1 X2 Y0.3 F600
X3 Y0.4
X4 Y0.3
X5 Y0
M2
"""

BODY_AFTER_A_G64_LINE = """G21 G90
G61
G0 X0 Y0
G1 F600 X0
o100 call
G64 P0.5
G0 X0 Y0
M2
o100 sub
G1 X1 Y0.3
X2 Y0.4
X3 Y0.3
X4 Y0
o100 endsub
"""

LOOP = """G21 G90
#2 = 0.001
#3 = 0
o1 while [#3 LT 2]
G64 P#2
G1 X1 Y0.3 F600
X2 Y0.4
X3 Y0.3
X4 Y0
G0 X0 Y0
#2 = 1
#3 = [#3 + 1]
o1 endwhile
M2
"""


@pytest.mark.parametrize("text, lines", [
    (SUBROUTINE_AFTER_A_CALL, 5),           # the subroutine's P0.01 is in force after the call
    (BODY_AFTER_A_G64_LINE, 4),             # G61 is in force when the body runs
    (LOOP, 5),                              # P0.001 in the first pass, P1 in the second
])
def test_the_tolerance_in_force_in_the_order_the_program_runs(text, lines):
    """Subroutines and loops: the tolerance of a move is the one in force when it runs, not the
    one of the G64 line above it in the file."""
    moves, _ = joined(text)
    assert len(feed_lines(moves)) == lines


def test_a_run_from_a_line_approaches_without_joining():
    """The approach's plunge is not joined with the program's moves after it."""
    text = "G21 G90 G64 P0.5\nG0 X0 Y0 Z0.3\nG1 Z0 F300\nG1 X10 F300\nG1 X20\nG1 X30 Y0.2\nM2\n"
    run = start_at(interpret(text), 5, (0.0, 0.0, 0.0))
    moves, _ = collapse(run.moves)
    assert [m.start for m in feed_lines(moves)][-2:] == [(10, 0, 0.3), (10, 0, 0)]


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.floats(-2, 2), st.floats(-2, 2), st.floats(-2, 2)), min_size=1, max_size=60),
       st.floats(0.001, 1.0), st.lists(st.sampled_from([600.0, 900.0]), min_size=60, max_size=60))
def test_every_dropped_point_stays_within_the_tolerance(steps, tolerance, feeds):
    """Random polylines: the joined path starts and ends where the program does, its corners
    are program points in order, and every point it drops lies within the tolerance of the
    joined line that replaced it."""
    points, here = [(0.0, 0.0, 0.0)], (0.0, 0.0, 0.0)
    moves = []
    for k, (step, feed) in enumerate(zip(steps, feeds)):
        end = tuple(h + s for h, s in zip(here, step))
        moves.append(Line(here, end, feed, k + 2, join=(1, tolerance)))
        points.append(end)
        here = end
    out, removed = collapse(moves)
    assert len(out) + removed == len(moves) and out[0].start == points[0] and out[-1].end == points[-1]
    firsts = [m.line - 2 for m in out] + [len(moves)]         # each joined line's first move
    for m, first, after in zip(out, firsts, firsts[1:]):
        assert m.start == points[first] and m.end == points[after]
        assert all(distance_to_segment(p, m.start, m.end) <= tolerance for p in points[first + 1:after])
        assert len({f.feed for f in moves[first:after]}) == 1


def test_corpus_program_joins_and_ends_alike():
    """3D_Chips.ngc (G64 P.1): with naive_cam the compile has far fewer commands, the same end
    point and nearly the same step events; without it, every move runs as programmed."""
    path = CORPUS / "lcnc_3D_Chips.ngc"
    if not path.exists():
        pytest.skip("the G-code corpus is not beside the project")
    text = path.read_text()
    _, plain = compile_text(text)
    _, joined_run = compile_text(text, JOINING)
    assert plain.joined == 0 and joined_run.joined > 3000
    assert len(joined_run.commands) < len(plain.commands) // 3
    assert joined_run.end_steps == plain.end_steps
    assert abs(joined_run.step_events - plain.step_events) < plain.step_events // 100


def test_check_reports_the_joined_moves(tmp_path, capsys):
    program = tmp_path / "p.ngc"
    program.write_text("G21 G90 G64 P0.05\nG1 X1 Y0.03 F600\nX2 Y0.04\nX3 Y0.03\nX4 Y0\nM2\n")
    assert main(["gcode", str(program), "--check", "--set", "motion.naive_cam=true"]) == 0
    assert "1 moves (0 arcs, 3 joined (naive CAM))" in capsys.readouterr().out
    assert main(["gcode", str(program), "--check", "--json", "--set", "motion.naive_cam=true"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert (info["moves"], info["joined_moves"], info["commands"]) == (1, 3, 2)     # (and M2)
    assert main(["gcode", str(program), "--check", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["joined_moves"] == 0
