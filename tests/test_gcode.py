# SPDX-License-Identifier: Apache-2.0
"""The G-code front end (`interp gcode`): parsing, conversion to motion_top commands, bad input.

These run the parser only; the RTL run of a program is in test_motion_top.py.
"""
import pytest

from interp.cli import main
from interp.commands.gcode import FEED_MAX, LINE_MAX, GcodeError, feed_word, parse
from interp.models.motion import ARC_CCW, ARC_CW, DWELL, LINE, queue_steps


def kinds(prog):
    return [(c.kind, c.x, c.y, c.z) for c in prog.commands]


def test_absolute_relative_and_scale():
    prog = parse("G90 G01 X1.5 Y2 F50\nG91 X1 Y-1 Z0.5\nG90 X0 Y0 Z0\n", scale=10)
    assert kinds(prog) == [(LINE, 15, 20, 0), (LINE, 10, -10, 5), (LINE, -25, -10, -5)]
    assert prog.commands[0].feed == round(50 * 10 / 1000 * 65536) and prog.end == (0, 0, 0)
    assert prog.z_moves


def test_rounding_does_not_drift():
    prog = parse("G91 G01 F10\n" + "X0.3\n" * 10, scale=1)
    assert sum(c.x for c in prog.commands) == 3           # 10 x 0.3 units = 3 steps, not 0


def test_arcs_full_circle_and_dwell():
    prog = parse("G02 X10 Y10 I10 J0 F50\nG03 I-5 J0\nG04 P25\n")
    assert [(c.kind, c.x, c.y, c.i, c.j) for c in prog.commands[:2]] == [(ARC_CW, 10, 10, 10, 0),
                                                                       (ARC_CCW, 0, 0, -5, 0)]
    assert (prog.commands[2].kind, prog.commands[2].x) == (DWELL, 25)
    steps, errors = queue_steps(prog.commands)
    assert errors == [] and sum(s[0] for s in steps) == 10 and sum(s[1] for s in steps) == 10


def test_long_line_is_split():
    prog = parse(f"G00 X{3 * LINE_MAX + 5}")
    assert len(prog.commands) == 4 and sum(c.x for c in prog.commands) == 3 * LINE_MAX + 5
    assert all(abs(c.x) <= LINE_MAX for c in prog.commands) and prog.commands[0].feed == FEED_MAX


def test_comments_and_line_numbers():
    prog = parse("%\n(setup)\nN10 G01 X3 F20 ; go\n\nN20 Y4 (up)\n%\n")
    assert kinds(prog) == [(LINE, 3, 0, 0), (LINE, 0, 4, 0)]
    assert [c.source for c in prog.commands] == [3, 5]


@pytest.mark.parametrize("text,line,message", [
    ("G01 X1 F10\nM03\n", 2, "unsupported word M3"),
    ("G01 X1 F10\nG05 X2\n", 2, "unsupported G-code G5"),
    ("G01 X1 F10\nG01 X2 $\n", 2, "cannot read"),
    ("G01 X1 F0\n", 1, "feed 0"),
    ("G01 X1 F0.001\n", 1, "feed 0"),
    ("G01 X1 F2000\n", 1, "above the maximum"),
    ("G01 X1\n", 1, "without a feed rate"),
    ("G01 X1 F10\nG02 X10 Y0 I3 J0\n", 2, "inconsistent centre"),
    ("G03 X1 Y1 I0 J0 F10\n", 1, "radius 0"),
    ("G02 X0 Y0 Z3 I5 F10\n", 1, "helical"),
    ("G03 X0 Y0 I9000 F10\n", 1, "too large"),
    ("G01 X1 I1 F10\n", 1, "I/J on a line"),
    ("G04 P-3\n", 1, "dwell"),
    ("G01 X1 X2 F10\n", 1, "given twice"),
])
def test_bad_input_names_the_line(text, line, message):
    with pytest.raises(GcodeError) as err:
        parse(text)
    assert str(err.value).startswith(f"line {line}:") and message in str(err.value), str(err.value)


def test_cli_reports_bad_line(tmp_path, capsys):
    src = tmp_path / "bad.nc"
    src.write_text("G01 X5 F10\nG01 Y5\nG17 G42 X1\n")
    assert main(["gcode", str(src), "--steps", str(tmp_path / "s.csv")]) == 2
    assert "line 3: unsupported G-code G42" in capsys.readouterr().err
    assert main(["gcode", str(tmp_path / "missing.nc"), "--steps", str(tmp_path / "s.csv")]) == 2
    assert main(["gcode", str(src), "--steps", str(tmp_path / "s.csv"), "--setup", "99"]) == 2


def test_clock_hz_gives_machine_units():
    """With a clock, F is units per minute and G04 P seconds, as on a machine."""
    prog = parse("G21 G01 X10 F600\nG04 P0.2\n", scale=100, clock_hz=100_000)
    line, dwell = prog.commands[0], prog.commands[-1]
    # 600 mm/min * 100 steps/mm = 1000 steps/s = 0.01 steps per clock at 100 kHz
    assert line.feed == feed_word(0.01 * 1000, 1)
    assert dwell.kind == DWELL and dwell.x == 20_000
