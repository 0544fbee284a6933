# SPDX-License-Identifier: Apache-2.0
"""G38.2 .. G38.5 probing: the interpreter's probe moves and their results (interpret's probes),
`interp gcode` (the touch taken at the end of the move) and `interp send` against the Python
model of the controller with a touch plate: the program runs in pieces, the probe move holds
at the touch (G38.4 / G38.5: where the probe loses contact), and what follows is interpreted
from where the machine stopped (a Z touch-off: G38.2, then G10 L20 sets the work zero)."""
from __future__ import annotations

import pytest

from interp.cli import main
from interp.commands import send
from interp.gcode.errors import GcodeError
from interp.gcode.interpreter import interpret
from interp.gcode.moves import Line, ProbeResult
from interp.gcode.parameter_file import read_parameters
from interp.link import protocol as p
from interp.link.devicemodel import DeviceModel

TOUCH_OFF = "G21 G90\nG0 X5\nG38.2 Z-10 F50\nG10 L20 P1 Z1.5\nG0 Z5\nM2\n"


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def attach(monkeypatch, device):
    monkeypatch.setattr(send, "open_transport", lambda args, machine: (device, 115200))


def send_program(capsys, tmp_path, monkeypatch, device, text, *flags):
    """`interp send` of `text` to `device` (the controller model; flags: --sim-model by
    default): (exit status, stdout, stderr)."""
    attach(monkeypatch, device)
    program = tmp_path / "p.nc"
    program.write_text(text)
    return run(capsys, "send", str(program), *(flags or ("--sim-model",)))


def linear_moves(device):
    return [(r["x"], r["y"], r["z"]) for r in device.executed if r["kind"] == 0]


# ---------------- the interpreter ----------------

def test_the_interpretation_stops_at_a_probe_move_until_its_result_is_known():
    program = interpret(TOUCH_OFF, probes=[])
    assert program.probe_pending and program.moves[-1] == Line((5.0, 0.0, 0.0), (5.0, 0.0, -10.0), 50.0, 3, probe=382)
    touched = ProbeResult(True, (5.0, 0.0, -3.2), (5.0, 0.0, -3.25))
    program = interpret(TOUCH_OFF + "", probes=[touched])
    assert not program.probe_pending
    assert program.moves[2] == Line((5.0, 0.0, -3.25), (5.0, 0.0, 0.25), None, 5)      # from where it stopped
    assert program.saved[5223] == pytest.approx(-4.75)


def test_the_probe_parameters():
    text = "G21 G90\nG10 L2 P1 Z-1\nG38.3 Z-10 F50\nG0 X#5063 Y#5070\n"
    program = interpret(text, probes=[ProbeResult(True, (0.0, 0.0, -3.0), (0.0, 0.0, -3.1))])
    assert program.moves[-1].end == (-2.0, 1.0, -3.1)                 # #5063 in G54: -3 - (-1); #5070 = 1
    program = interpret(text, probes=[ProbeResult(False, (0.0, 0.0, -11.0), (0.0, 0.0, -11.0))])
    assert program.moves[-1].end == (-10.0, 0.0, -11.0)               # G38.3 without a touch: #5070 = 0


def test_without_a_machine_the_touch_is_at_the_end_of_the_move():
    program = interpret(TOUCH_OFF)
    assert not program.probe_pending and program.saved[5223] == pytest.approx(-11.5)
    assert program.warnings == ["line 3: G38.2: the probe's touch is taken at the end of the move (only the "
                                "machine knows where it is)"]


@pytest.mark.parametrize("text, message", [
    ("G38.4 Z-1\n", "feed move without a feed rate"),
    ("G38.5 Z0 F50\n", "the probe move has no length"),
    ("G38.2 Z-1\n", "feed move without a feed rate"),
    ("G38.2 Z0 F50\n", "the probe move has no length"),
    ("G38.2 @1 F50\n", "polar coordinates cannot be used with G38.2"),
])
def test_probe_moves_refused(text, message):
    with pytest.raises(GcodeError) as info:
        interpret(text)
    assert message in str(info.value)


def test_probing_away_from_the_work():
    """G38.4 / G38.5: #5070 = 1 where the probe lost contact, #5061..#5063 that position; a
    G38.4 that keeps contact to its end is an error, a G38.5 sets #5070 = 0 and goes on."""
    text = "G21 G90\nG38.4 Z5 F50\nG0 X#5063 Y#5070\n"
    program = interpret(text, probes=[ProbeResult(True, (0.0, 0.0, 0.5), (0.0, 0.0, 0.53))])
    assert program.moves[0] == Line((0.0, 0.0, 0.0), (0.0, 0.0, 5.0), 50.0, 2, probe=384)
    assert program.moves[-1].end == (0.5, 1.0, 0.53)
    with pytest.raises(GcodeError, match="line 2, column 1: G38.4: the probe did not lose contact before the end"):
        interpret(text, probes=[ProbeResult(False, (0.0, 0.0, 5.0), (0.0, 0.0, 5.0))])
    program = interpret(text.replace("G38.4", "G38.5"), probes=[ProbeResult(False, (0.0, 0.0, 5.0), (0.0, 0.0, 5.0))])
    assert program.moves[0].probe == 385 and program.moves[-1].end == (5.0, 0.0, 5.0)
    assert interpret(text).warnings == ["line 2: G38.4: the probe's loss of contact is taken at the end of the "
                                        "move (only the machine knows where it is)"]


def test_a_g382_result_without_a_touch_is_an_error():
    with pytest.raises(GcodeError, match="the probe did not touch"):
        interpret(TOUCH_OFF, probes=[ProbeResult(False, (5.0, 0.0, -10.0), (5.0, 0.0, -10.0))])


# ---------------- interp send ----------------

def test_a_z_touch_off(capsys, tmp_path, monkeypatch):
    """The plate's top is 3.2 mm below where Z starts: the probe touches there and stops 3
    steps further (the model's overshoot), G10 L20 makes that Z1.5 (the plate's thickness) in
    G54, and G0 Z5 goes to machine 0.27 mm."""
    device = DeviceModel(probe=(2, "min", -320))
    attach(monkeypatch, device)
    machine = tmp_path / "m.toml"
    machine.write_text('[gcode]\nparameter_file = "m.var"\n')
    program = tmp_path / "touch.nc"
    program.write_text(TOUCH_OFF)
    code, out, err = run(capsys, "send", str(program), "--sim-model", "--machine", str(machine))
    assert code == 0, err
    assert linear_moves(device) == [(500, 0, 0), (0, 0, -1000), (0, 0, 350)]
    assert device.position == [500, 0, 27] and device.probe_position == [500, 0, -320]
    assert read_parameters(tmp_path / "m.var")[5223] == pytest.approx(-4.73)
    assert out.startswith("sent 4 records") and "saved the offsets" in err     # (and the M2 event)


def test_no_touch_is_an_error_for_g382(capsys, tmp_path, monkeypatch):
    device = DeviceModel(probe=(2, "min", -2000))
    code, out, err = send_program(capsys, tmp_path, monkeypatch, device, TOUCH_OFF)
    assert code == 1
    assert err.strip() == "interp: error: line 3: G38.2: the probe did not touch before the end of the move"
    assert device.position == [500, 0, -1000] and len(linear_moves(device)) == 2


def test_no_touch_goes_on_for_g383(capsys, tmp_path, monkeypatch):
    device = DeviceModel(probe=(2, "min", -2000))
    code, out, err = send_program(capsys, tmp_path, monkeypatch, device, "G21 G90\nG38.3 Z-10 F50\no1 if [#5070 EQ 0]\nG0 X1\no1 else\nG0 X2\no1 endif\nM2\n")
    assert code == 0, err
    assert device.position == [100, 0, -1000]


BACK_OFF = "G21 G90\nG38.2 Z-10 F50\nG91 G38.4 Z2 F25\n(debug, lost at #5063)\nG90 G0 Z0\nM2\n"


def test_backing_off_the_plate(capsys, tmp_path, monkeypatch):
    """G38.2 touches the plate at Z-3.2 and stops 3 steps below; G38.4 backs up until the probe
    loses contact one step above the touch (the controller's probe inverted for the move,
    then as before), stopping 3 steps further."""
    device = DeviceModel(probe=(2, "min", -320))
    code, out, err = send_program(capsys, tmp_path, monkeypatch, device, BACK_OFF)
    assert code == 0, err
    assert linear_moves(device) == [(0, 0, -1000), (0, 0, 200), (0, 0, 316)]
    assert device.probe_position == [0, 0, -319] and device.position == [0, 0, 0]
    assert "interp: message: line 4: lost at -3.190000" in err.splitlines()
    inverts = [value for name, value in device.writes if name == "INPUT_INVERT"]
    assert inverts == [p.PROBE_INPUT, 0] and device.regs["INPUT_INVERT"] == 0


@pytest.mark.parametrize("code, expected", [
    ("G38.4", "interp: error: line 3: G38.4: the probe did not lose contact before the end of the move"),
    ("G38.5", ""),
])
def test_a_probe_that_keeps_contact(capsys, tmp_path, monkeypatch, code, expected):
    """A back-off shorter than the overshoot past the touch (3 steps): G38.4 stops the program,
    G38.5 goes on with #5070 = 0; the probe's polarity is restored either way."""
    device = DeviceModel(probe=(2, "min", -100))
    text = f"G21 G90\nG38.2 Z-10 F50\nG91 {code} Z0.02 F25\no1 if [#5070 EQ 0]\nG0 X1\no1 endif\nM2\n"
    status, out, err = send_program(capsys, tmp_path, monkeypatch, device, text)
    assert (status, err.strip()) == ((1, expected) if expected else (0, ""))
    assert linear_moves(device)[1:] == [(0, 0, 2)] + ([] if expected else [(100, 0, 0)])
    assert device.regs["INPUT_INVERT"] == 0


def test_probing_away_needs_a_touch(capsys, tmp_path, monkeypatch):
    device = DeviceModel(probe=(2, "min", -320))
    code, out, err = send_program(capsys, tmp_path, monkeypatch, device, "G21 G90\nG0 X1\nG38.5 Z5 F50\n")
    assert code == 1 and err.strip() == ("interp: error: line 3: G38.5: the probe does not touch before the move "
                                         "(it backs away from a touch)")
    assert linear_moves(device) == [(100, 0, 0)] and device.regs["INPUT_INVERT"] == 0


def test_a_probe_touching_before_the_move(capsys, tmp_path, monkeypatch):
    device = DeviceModel(probe=(2, "min", 0))
    code, out, err = send_program(capsys, tmp_path, monkeypatch, device, TOUCH_OFF)
    assert code == 1 and err.strip() == "interp: error: line 3: G38.2: the probe touches already before the move"
    assert linear_moves(device) == [(500, 0, 0)]


@pytest.mark.parametrize("argv, word", [
    (["--port", "loop://", "--probe-at", "Z-1"], "--probe-at goes with --sim, not --port"),
    (["--sim", "--probe-at", "Z0"], "--probe-at Z0: give an axis and a machine position in mm at least a step from 0"),
    (["--sim", "--probe-at", "z-0.004"], "--probe-at z-0.004: give an axis"),         # 0.4 steps
    (["--sim", "--probe-at", "Z-1", "--probe-at", "z-2"], "--probe-at z-2: Z given twice (one touch per axis)"),
    (["--sim", "--probe-at", "A-1"], "--probe-at A-1: give an axis"),
    (["--sim", "--probe-at", "Z"], "--probe-at Z: give an axis"),
    (["--sim-model", "--probe-at", "Z-1"], "--probe-at goes with --sim"),
])
def test_probe_at_usage(capsys, tmp_path, monkeypatch, argv, word):
    """--probe-at: only with --sim, an axis and a non-zero position: one line, exit status 2."""
    device = DeviceModel()
    code, out, err = send_program(capsys, tmp_path, monkeypatch, device, TOUCH_OFF, *argv)
    assert code == 2 and word in err and len(err.strip().splitlines()) == 1, err
    assert not device.executed


def test_an_abort_comment_after_a_probe_stops_the_run(capsys, tmp_path, monkeypatch):
    """(ABORT, ...) on the probe's result (#5070 = 0: G38.3 found nothing) stops the program
    after the probe move, with its text; the check before the run (every probe touching at
    its move's end) does not reach it."""
    device = DeviceModel(probe=(2, "min", -500))
    text = "G21 G90\nG38.3 Z-1 F300\no1 if [#5070 EQ 0]\n(abort, no touch: #5070)\no1 endif\nG0 X1\nM2\n"
    code, out, err = send_program(capsys, tmp_path, monkeypatch, device, text)
    assert code == 2 and err.strip().splitlines()[-1] == "interp: error: line 4, column 1: (ABORT) no touch: 0.000000"
    assert linear_moves(device) == [(0, 0, -100)]


def test_an_abort_on_the_probed_position(capsys, tmp_path, monkeypatch):
    """An (ABORT, ...) on the touch's position is checked on the true touch: the check before
    the run (every touch at its move's end, Z-10) only warns of it, the touch at Z-2 passes and
    the program runs on; a touch at Z-7 stops the run after the probe move, with the messages
    before the abort, and the spindle and coolant are switched off (CONTROL.abort at rest)."""
    text = ("G21 G90\nG38.2 Z-10 F300\n(debug, touched at #5063)\no1 if [#5063 LT -5]\n(abort, too deep: #5063)\n"
            "o1 endif\nG0 Z0\nM2\n")
    device = DeviceModel(probe=(2, "min", -200))
    code, out, err = send_program(capsys, tmp_path, monkeypatch, device, text)
    assert code == 0, err
    assert "interp: message: line 3: touched at -2.000000" in err and "ABORT" not in err
    device = DeviceModel(probe=(2, "min", -700))
    code, out, err = send_program(capsys, tmp_path, monkeypatch, device, text)
    assert code == 2, err
    assert err.strip().splitlines()[-2:] == ["interp: message: line 3: touched at -7.000000",
                                             "interp: error: line 5, column 1: (ABORT) too deep: -7.000000"], err
    assert [n for n, _ in device.writes][-1] == "CONTROL" and device.writes[-1][1] & p.CONTROL_ABORT


def test_the_simulator_needs_a_touch(capsys, tmp_path, monkeypatch):
    device = DeviceModel()
    code, out, err = send_program(capsys, tmp_path, monkeypatch, device, TOUCH_OFF, "--sim")
    assert code == 2 and "line 3: G38.2: give the simulated controller's probe a touch with --probe-at" in err
    assert not device.executed


def test_gcode_runs_a_probe_program_to_the_end(capsys, tmp_path):
    program = tmp_path / "touch.nc"
    program.write_text(TOUCH_OFF)
    code, out, err = run(capsys, "gcode", str(program), "--check")
    assert code == 0 and "G38.2: the probe's touch is taken at the end of the move" in err


def test_probes_in_a_loop(capsys, tmp_path, monkeypatch):
    """Two probe moves from a loop, each followed by a retract: every move runs once, in order,
    and the loop's message is printed once per pass."""
    device = DeviceModel(probe=(2, "min", -320))
    code, out, err = send_program(capsys, tmp_path, monkeypatch, device, "G21 G90\no1 repeat [2]\n(MSG, probing)\nG38.2 Z-10 F50\nG0 Z0\no1 endrepeat\nM2\n")
    assert code == 0, err
    assert linear_moves(device) == [(0, 0, -1000), (0, 0, 323)] * 2
    assert err.splitlines() == ["interp: message: line 3: probing"] * 2


def test_a_stop_code_in_the_probe_block_waits_for_the_result(capsys, tmp_path, monkeypatch):
    """G38.2 ... M0: the pause comes after the probe move, which runs armed."""
    device = DeviceModel(probe=(2, "min", -320))
    code, out, err = send_program(capsys, tmp_path, monkeypatch, device, "G21 G90\nG38.2 Z-10 F50 M0\nG0 Z0\nM2\n")
    assert code == 0, err
    assert linear_moves(device) == [(0, 0, -1000), (0, 0, 323)] and device.probe_position[2] == -320


def test_probing_with_the_spindle_on_is_refused_before_anything_moves(capsys, tmp_path, monkeypatch):
    device = DeviceModel(probe=(2, "min", -320))
    code, out, err = send_program(capsys, tmp_path, monkeypatch, device, "G21 G90\nG0 X1\nM3 S1000\nG38.2 Z-10 F50\n")
    assert code == 2 and not device.executed
    assert err.strip() == ("interp: error: line 4, column 1: G38.2: G38.2 with the spindle or coolant on: stop "
                           "them (M5, M9) before probing")


def test_a_probe_touching_before_the_first_move(capsys, tmp_path, monkeypatch):
    device = DeviceModel(probe=(2, "min", 0))
    code, out, err = send_program(capsys, tmp_path, monkeypatch, device, "G21 G90\nG38.2 Z-10 F50\n")
    assert code == 1 and err.strip() == "interp: error: line 2: G38.2: the probe touches already before the move"


def test_a_gcode_error_after_a_probe_stops_the_program_before_anything_moves(capsys, tmp_path, monkeypatch):
    device = DeviceModel(probe=(2, "min", -320))
    code, out, err = send_program(capsys, tmp_path, monkeypatch, device, "G21 G90\nG0 X5\nG38.2 Z-10 F50\nG0 X1 I5\n")
    assert code == 2 and not device.executed and "line 4" in err


def test_a_touch_off_macro_from_a_subroutine_file(capsys, tmp_path, monkeypatch):
    """docs/gcode.md's touch_off.ngc next to the program: its probe move runs as a piece of its
    own, and G54 Z0 is then the plate's underside, 1.5 mm (150 steps) below where it stopped."""
    (tmp_path / "touch_off.ngc").write_text("o<touch_off> sub\n  G91 G38.2 Z-20 F100\n  G90 G10 L20 P0 Z#1\n"
                                            "  G91 G0 Z2\n  G90\no<touch_off> endsub\nM2\n")
    device = DeviceModel(probe=(2, "min", -320))
    code, out, err = send_program(capsys, tmp_path, monkeypatch, device, "G21 G90\no<touch_off> call [1.5]\nG0 Z0\nM2\n")
    assert code == 0, err
    assert linear_moves(device) == [(0, 0, -2000), (0, 0, 200), (0, 0, -350)]
    assert device.position == [0, 0, -473]          # stopped at -323 (3 past the touch): Z1.5
