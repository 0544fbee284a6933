# SPDX-License-Identifier: Apache-2.0
"""Run from a line (interp/gcode/restart.py; `interp gcode --start-line`, `interp send
--start-line`): the state the dropped lines left, the approach, the moves from the start on,
and the refusals as one line."""
from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from interp.cli import main
from interp.commands import send
from interp.cores import UsageError
from interp.gcode.interpreter import interpret
from interp.gcode.moves import Arc, Dwell, Event, Line
from interp.gcode.restart import start_at
from interp.link.devicemodel import DeviceModel

CORPUS = Path(__file__).resolve().parents[1] / ".." / "shared" / "gcode"

PROGRAM = """G21 G90 G17
G0 Z10
T2 M6
M3 S12000
M8
M64 P1
G0 X5 Y5
G0 Z1
G1 Z-1 F300
G1 X20 F900
G1 Y20
G0 Z10
S9000
G0 X40 Y40
G1 Z-2 F200
G2 X60 Y40 I10 J0 F700
G0 Z10
M5 M9
M65 P1
M2
"""


def events(program):
    return [(m.name, m.value) for m in program.moves if isinstance(m, Event)]


def test_the_state_before_the_line_and_the_approach():
    """Starting at line 11 (G1 Y20): the program stood at X20 Y5 Z-1 with tool 2 changed to,
    the spindle on at S12000, flood and output 1 on.  From the machine at X0 Y0 Z0: the
    output, the M6's pause, up to the clearance Z10 and across, the spindle and flood, down as
    a rapid to the last rapid's height (Z1, line 8) and at the plunge feed (F300, line 9) to
    Z-1; then line 11's move, everything from there as the whole program runs it."""
    whole = interpret(PROGRAM)
    run = start_at(whole, 11, (0.0, 0.0, 0.0))
    shown = [(m.name, m.value) if isinstance(m, Event) else (m.end, m.feed) for m in run.moves[:9]]
    assert shown == [("output_on", 1.0), ("tool_change", 2.0), ("pause", 6.0), ((0, 0, 10), None),
                     ((20, 5, 10), None), ("spindle_cw", 12000.0), ("flood_on", 0.0), ((20, 5, 1), None),
                     ((20, 5, -1), 300.0)]
    assert all(m.line == 11 for m in run.moves[:9]) and [m.origin for m in run.moves[:9]] == [11] * 9
    kept = whole.moves[[m.line for m in whole.moves].index(11):]
    assert run.moves[9:] == kept and run.moves[9] == Line((20, 5, -1), (20, 20, -1), 900.0, 11)
    info = run.restart
    assert (info.tool, info.spindle, info.speed, info.coolant, info.outputs) == (2, "M3", 12000.0, ("flood",),
                                                                                 {1: True})
    assert info.describe() == ("starting at line 11: tool 2: the program pauses first for its M6; spindle M3 "
                               "S12000; coolant flood; outputs 1 on; approach in 4 moves to X20 Y5 Z-1 (machine mm), "
                               "the last at F300")


def test_after_a_subroutine_that_restores_its_callers_state():
    """Line 10 follows a call of a subroutine that saved the state with M73 and turned the
    spindle to S2000 and flood on: its return restored S1000 and coolant off, so the run from
    line 10 starts with those (the restore's events count as the call's line)."""
    text = ("o1 sub\nM73\nM3 S2000 M8\nG91 G1 X5 F300\no1 endsub\nG21 G90 G0 Z5\nM3 S1000\nG0 X0 Y0\n"
            "o1 call\nG1 X20 Y0 F200\nG1 X20 Y20\nM2")
    run = start_at(interpret(text), 10, (0.0, 0.0, 0.0))
    info = run.restart
    assert (info.spindle, info.speed, info.coolant) == ("M3", 1000.0, ())
    assert [m.name for m in run.moves if isinstance(m, Event)] == ["spindle_cw", "program_end"]


def test_the_spin_up_dwell_and_a_laser():
    """A dwell right after M3 is its spin-up: restored after the spindle, before the descent.
    On a laser no dwell is kept and the beam's M3 comes after the approach (the rapids keep it
    dark), before the first move or spindle word of the run; a kept dwell before it stays dark."""
    text = "G21 G90\nG0 X5 Y0 Z1\nM3 S500\nG4 P2\nG0 X0\nG1 Z-1 F100\nG4 P1\nG1 X10 F1000\nM5\n"
    mill = start_at(interpret(text, start=(3.0, 0.0, 5.0)), 7, (3.0, 0.0, 5.0))
    order = [type(m).__name__ if not isinstance(m, Event) else m.name for m in mill.moves]
    assert order == ["Line", "spindle_cw", "Dwell", "Line", "Line", "Dwell", "Line", "spindle_off"]
    assert mill.moves[2] == Dwell(2.0, 7) and mill.restart.spin_up == 2.0
    laser = start_at(interpret(text, start=(3.0, 0.0, 5.0)), 7, (3.0, 0.0, 5.0), laser=True)
    order = [type(m).__name__ if not isinstance(m, Event) else m.name for m in laser.moves]
    assert order == ["Line", "Line", "Line", "Dwell", "spindle_cw", "Line", "spindle_off"]
    assert laser.restart.spin_up == 0.0
    at_m5 = start_at(interpret(text), 9, (0.0, 0.0, 5.0), laser=True)     # the run's own M5 first
    assert [m.name for m in at_m5.moves if isinstance(m, Event)] == ["spindle_cw", "spindle_off"]


def test_a_later_s_word_and_the_plunge_feed():
    """Line 16 (the arc): S9000 changed the running spindle's speed; the plunge is line 15's
    F200, from Z10 (the last rapid, line 14, ran there); the arc itself is kept whole."""
    run = start_at(interpret(PROGRAM), 16, (0.0, 0.0, 0.0))
    assert ("spindle_cw", 9000.0) in events(run)
    first_arc = next(k for k, m in enumerate(run.moves) if isinstance(m, Arc))
    assert run.moves[first_arc - 1] == Line((40, 40, 10), (40, 40, -2), 200.0, 16)
    assert run.moves[first_arc].start == (40, 40, -2)


def test_the_machine_elsewhere_and_above():
    """The machine stands at X50 Y0 Z30 (above everything the program reached): across at
    Z30, down as a rapid to Z1, at F300 to Z-1."""
    run = start_at(interpret(PROGRAM, start=(50.0, 0.0, 30.0)), 11, (50.0, 0.0, 30.0))
    assert [m.end for m in run.moves if isinstance(m, Line)][:3] == [(20, 5, 30), (20, 5, 1), (20, 5, -1)]


def test_line_one_is_the_whole_program():
    whole = interpret(PROGRAM)
    run = start_at(whole, 1, (0.0, 0.0, 0.0))
    assert run.moves == whole.moves
    assert run.restart.approach == () and run.restart.spindle is None


def test_a_line_without_a_move_starts_at_the_next():
    """Line 13 (S9000: no move, the spindle speed event is line 13's) and a line past a blank
    one start at the first move at that line or after."""
    run = start_at(interpret(PROGRAM), 13, (0.0, 0.0, 0.0))
    assert ("spindle_speed", 9000.0) in events(run)
    run = start_at(interpret("G21\n\nG1 X1 F100\n\n\nG1 X2\n"), 4, (0.0, 0.0, 0.0))
    assert [m.end for m in run.moves if isinstance(m, Line)] == [(1, 0, 0), (2, 0, 0)]


def test_a_loop_starts_at_its_first_pass():
    text = "G21 G91\n#1 = 0\no1 while [#1 LT 3]\nG1 X1 F100\nG1 Y1\n#1 = [#1 + 1]\no1 endwhile\nG90 G0 X0 Y0\n"
    run = start_at(interpret(text), 5, (0.0, 0.0, 0.0))
    lines = [m for m in run.moves if isinstance(m, Line)]
    assert lines[0].end == (1, 0, 0) and lines[1] == Line((1, 0, 0), (1, 1, 0), 100.0, 5)
    assert len(lines) == 1 + 1 + 2 * 2 + 1            # approach, the first pass's Y, two passes, the G0


def test_messages_by_the_order_they_run_in():
    """A message shows when the run from the line runs it: one in a subroutine called after
    the start (its body is on an earlier line) shows, one before the start does not."""
    text = "o1 sub\n(MSG, in sub)\nG1 X1 F100\no1 endsub\n(MSG, before)\nG1 Y5 F100\nG1 Y6\no1 call\nM2\n"
    run = start_at(interpret(text), 7, (0.0, 0.0, 0.0))
    assert run.messages == ["line 2: in sub"]


def test_a_subroutine_counts_with_its_calls_line():
    """Subroutines after M2 (their bodies on later lines): a call before the start is dropped
    (the approach goes where it left the machine), one at the start runs; a line inside a
    subroutine's body is refused."""
    text = ("G21 G90\nG0 Z5\no100 call [1]\nG0 X0 Y0\no100 call [2]\nG0 X0 Y0\nM2\n"
            "o100 sub\nG1 X#1 F300\nG1 Y#1\no100 endsub\n")
    whole = interpret(text)
    assert [m.origin for m in whole.moves] == [2, 3, 3, 4, 5, 5, 6, 7]
    run = start_at(whole, 4, (0.0, 0.0, 5.0))
    assert [m.end for m in run.moves if isinstance(m, Line)] == [(1, 1, 5), (0, 0, 5), (2, 0, 5), (2, 2, 5), (0, 0, 5)]
    run = start_at(whole, 5, (0.0, 0.0, 5.0))
    assert [m.end for m in run.moves if isinstance(m, Line)][:2] == [(2, 0, 5), (2, 2, 5)]
    with pytest.raises(UsageError) as error:
        start_at(whole, 9, (0.0, 0.0, 5.0))
    assert str(error.value) == ("--start-line 9: the line is in subroutine o100 (lines 8 .. 11); start at a line "
                                "outside it (a call runs it from its first line)")


@pytest.mark.parametrize("text", [
    "G21 G90\nG92 X0 Y0 Z0\nG0 Z5\nG0 X10\nG1 Z-1 F100\nG1 X20\nG1 Y10\n",       # the origin where it started
    "G21 G90\nG0 Z5\nG91 G0 X10 Y10\nG90 G1 Z-1 F100\nG1 Z-2\nG1 X50 Y10 F300\n",  # G91 from the start, then G90
    "G21 G90\nG28.1\nG0 Z5\nG0 X10 Y10\nG1 Z-1 F100\nG1 X20 F300\nG28\n",        # G28 back where it started
    "G21 G91\nG0 Z5\nG0 X10\nG1 Z-6 F100\nG1 X10\nG1 Y10\n",                      # incremental from its start
    "G21 G90\nG10 L20 P1 X0 Y0\nG0 X10 Z5\nG1 Z-1 F100\nG1 X20\nG1 Y10\n",        # an offset from there
])
def test_a_program_anchored_where_it_started_is_refused(tmp_path, capsys, text):
    """Moves from the start line that depend on where the program started would run shifted
    by where the machine is now: one line, exit status 2.  From its first line it runs."""
    path = tmp_path / "anchored.ngc"
    path.write_text(text)
    assert main(["gcode", str(path), "--check", "--start-line", "6"]) == 2
    assert capsys.readouterr().err.strip() == (
        "interp: error: --start-line 6: the moves from there depend on where the program started (G92 or G10 L20 "
        "from where the machine stood, or incremental moves from its start): run from here they would be shifted; "
        "run it from its first line where it started")
    assert main(["gcode", str(path), "--check", "--start-line", "1"]) == 0
    capsys.readouterr()


@pytest.mark.parametrize("line, text", [
    (30, "--start-line 30: the program has no move or event there or after it (its last is at line 20)"),
    (0, "--start-line 0: lines count from 1"),
])
def test_lines_refused(line, text):
    with pytest.raises(UsageError) as error:
        start_at(interpret(PROGRAM), line, (0.0, 0.0, 0.0))
    assert str(error.value) == text


def test_a_probe_before_the_line_is_refused():
    """What a probe measured decides the moves after it: a start after one is refused (also
    when the interpretation stopped at it for the machine's result)."""
    text = "G21 G90\nG38.2 Z-10 F100\nG10 L20 P1 Z0\nG0 Z5\nG1 X5 F300\n"
    expected = ("--start-line 5: line 2 probes (G38.2) before it, and what it measures decides the moves after "
                "it; start at the probe or before it")
    for probes in (None, []):
        with pytest.raises(UsageError) as error:
            start_at(interpret(text, probes=probes), 5, (0.0, 0.0, 0.0))
        assert str(error.value) == expected
    assert start_at(interpret(text), 2, (0.0, 0.0, 0.0)).moves[0].probe == 382


def test_an_axis_not_programmed_yet_stays_where_the_machine_is(tmp_path, capsys):
    """Y is first programmed after the start line, Z never: they stay where the machine is,
    as a run from the first line would leave them, so the start is not refused."""
    path = tmp_path / "late_y.ngc"
    path.write_text("G21 G90\nG0 X5\nG1 X8 F100\nG1 X9\nG1 Y3\n")
    assert main(["gcode", str(path), "--check", "--start-line", "4"]) == 0
    assert "end X9 Y3 Z0 mm" in capsys.readouterr().out


def test_a_probe_after_the_start_runs_on_the_controller(tmp_path, capsys, monkeypatch):
    """`interp send --start-line` before a probe move: the pieces run as in the whole program
    (the probe's touch, its G10 L20, the moves after it) and the run ends where it ends."""
    path = tmp_path / "probe.ngc"
    path.write_text("G21 G90\nG0 Z5\nM3 S1000\nG0 X5\nG1 Z-1 F100\nG1 X8 F300\nM5\nG38.2 Z-10 F50\n"
                    "G10 L20 P1 Z1.5\nG0 Z5\nG1 X10 F300\nG1 Z0 F80\nG1 Y3\nM2\n")
    ends = []
    for line in (None, 6):
        device = DeviceModel(probe=(2, "min", -320))
        monkeypatch.setattr(send, "open_transport", lambda args, machine: (device, 115200))
        assert main(["send", str(path), "--sim-model"] + (["--start-line", str(line)] if line else [])) == 0
        ends.append(capsys.readouterr().out.rstrip().rsplit("end ", 1)[1])
    assert ends[0] == ends[1] == "(1000, 300, -473) steps"


@pytest.mark.parametrize("text, line", [
    ("G21 G90\nG0 Z5\nM3 S1000\nG0 X0 Y0\nG1 Z-1 F100\nG1 X10\nM5\n", 3),      # G0 X0 Y0: no move from 0
    ("G21 G90\nG0 Z5\nM3 S1000\nG0 X0 Y0\nG1 Z-1 F100\nG1 X10\nM5\n", 4),
    ("M3 S1000\nG0 X10 Y10\nG0 Z4\nG1 Z-1 F100\nG1 X20 F300\nM5\n", 3),
])
def test_ordinary_programs_are_not_taken_for_anchored(tmp_path, capsys, text, line):
    """A move that has no length from where the machine stands, but has from another start, does
    not make a program look anchored where it started."""
    path = tmp_path / "plain.ngc"
    path.write_text(text)
    assert main(["gcode", str(path), "--check", "--start-line", str(line)]) == 0, capsys.readouterr().err
    capsys.readouterr()


def test_a_run_from_a_tool_change_changes_the_tool_once():
    """Starting at an operation's T2 M6: the dropped T1 M6 is not asked for as well."""
    text = "G21 G90\nT1 M6\nM3 S1000\nG0 X10 Z5\nG1 Z-1 F100\nM5\nT2 M6\nM3 S500\nG1 X20 F300\nM5\n"
    run = start_at(interpret(text), 7, (0.0, 0.0, 0.0))
    assert [(m.name, m.value) for m in run.moves if isinstance(m, Event) and m.name in ("tool_change", "pause")] \
        == [("tool_change", 2.0), ("pause", 6.0)]
    assert run.restart.tool is None and "tool" not in run.restart.describe()


def test_the_longest_spin_up_after_a_start_or_a_new_speed():
    """M3 S1000 G4 P3, then M3 S12000 (a new speed, no dwell): the 3 s spin-up is kept; a later
    S with a longer dwell after it takes that one."""
    text = "G21 G90\nM3 S1000\nG4 P3\nG0 X5 Z1\nM3 S12000\nG1 Z-1 F100\nG1 X10\nS600\nG4 P5\nG1 X20\n"
    assert start_at(interpret(text), 7, (0.0, 0.0, 0.0)).restart.spin_up == 3.0
    assert start_at(interpret(text), 10, (0.0, 0.0, 0.0)).restart.spin_up == 5.0


def test_a_laser_approaches_with_rapids():
    """On a laser the approach is all rapids (the beam's M3 after it stays dark until the first
    feed move), even where the program stood below its last rapid's height."""
    text = "G21 G90\nG0 X5 Z3\nM3 S500\nG1 Z0 F100\nG1 X10 F1000\nG1 Y10\nM5\n"
    run = start_at(interpret(text), 6, (0.0, 0.0, 0.0), laser=True)
    assert [m.feed for m in run.moves if isinstance(m, Line) and m.line == 6][:-1] == [None, None, None]


def test_origins_under_cutter_compensation():
    """A subroutine's move under compensation settles after its call line ran again: it keeps the
    line of its own call, and a message on the start line shows."""
    text = ("G21 G90\nG0 X-5 Y-5\nG41.1 D2\no100 call\no100 call\no100 call\nG40\nG0 X-5 Y-5\nM2\n"
            "o100 sub\nG91 G1 X10 F300\nG90\no100 endsub\n")
    assert [m.origin for m in interpret(text).moves] == [2, 4, 5, 6, 8, 9]
    text = "G21 G90\nG0 X-5 Y-5\nG41.1 D2\nG1 X0 Y0 F300\nG1 X10\n(MSG, at six)\nG1 Y10\nG1 X0\nG40\n"
    assert start_at(interpret(text), 6, (0.0, 0.0, 0.0)).messages == ["line 6: at six"]


def test_compensated_moves_start_on_the_offset_path():
    """Cutter compensation's moves are the tool's: the approach meets the offset path (a 2 mm
    tool left of a counter-clockwise square: line 6's move starts at the inside corner X9 Y1)."""
    text = "G21 G90\nG0 X-5 Y-5\nG41.1 D2\nG1 X0 Y0 F300\nG1 X10\nG1 Y10\nG1 X0\nG40\nG0 X-5 Y-5\n"
    whole = interpret(text)
    run = start_at(whole, 6, (0.0, 0.0, 0.0))
    kept = [m for m in whole.moves if m.line >= 6]
    assert run.moves[-len(kept):] == kept and kept[0].start == pytest.approx((9.0, 1.0, 0.0))
    assert run.moves[len(run.moves) - len(kept) - 1].end == kept[0].start


@pytest.mark.skipif(not (CORPUS / "lcnc_3D_Chips.ngc").exists(), reason="the G-code corpus is not beside the repository")
@settings(max_examples=25, deadline=None)
@given(st.integers(min_value=1, max_value=4706), st.tuples(*[st.integers(-20, 20)] * 3))
def test_every_start_joins_the_path(line, here):
    """From any line of a CAM program and anywhere the machine is: the moves join end to
    start, and they end where the whole program ends."""
    here = tuple(float(v) for v in here)
    whole = interpret((CORPUS / "lcnc_3D_Chips.ngc").read_text(), start=here)
    run = start_at(whole, line, here)
    at = here
    for move in run.moves:
        if isinstance(move, (Line, Arc)):
            assert move.start == at, move
            at = move.end
    assert at == whole.end_machine


def test_the_command_lines(capsys, tmp_path, monkeypatch):
    """`interp gcode --start-line` prints what it restored and ends where the program ends;
    `interp send --start-line` runs the same commands (the controller's model); a bad value is
    one line, exit status 2."""
    path = tmp_path / "job.ngc"
    path.write_text(PROGRAM)
    assert main(["gcode", str(path), "--check", "--start-line", "14"]) == 0
    out, err = capsys.readouterr()
    assert err.startswith("interp: starting at line 14: tool 2: the program pauses first") and "end X60 Y40 Z10" in out
    device = DeviceModel()
    monkeypatch.setattr(send, "open_transport", lambda args, machine: (device, 115200))
    assert main(["send", str(path), "--sim-model", "--start-line", "14"]) == 0
    out, err = capsys.readouterr()
    assert "interp: starting at line 14:" in err and out.rstrip().endswith("end (6000, 4000, 1000) steps")
    assert main(["gcode", str(path), "--check", "--start-line", "99"]) == 2
    assert capsys.readouterr().err.strip() == ("interp: error: --start-line 99: the program has no move or event "
                                               "there or after it (its last is at line 20)")
    for bad, why in (("0", "0: lines count from 1"), ("x", "'x' is not a line number")):
        assert main(["send", str(path), "--sim-model", "--start-line", bad]) == 2
        assert capsys.readouterr().err.strip() == f"interp: error: interp send: argument --start-line: {why}"
