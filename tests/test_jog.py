# SPDX-License-Identifier: Apache-2.0
"""`interp jog` (interp/commands/jog.py) against the Python model of the controller: one
move from axis words, the keys' loop, the travel limits, bad words as one line; the keys
through a real terminal (a pty)."""
from __future__ import annotations

import os
import pty
import select
import termios
import sys
import time

import pytest

from interp.cli import main
from interp.commands import jog, send
from interp.gcode.machine import load_machine
from interp.link.devicemodel import DeviceModel
from interp.link.driver import Driver

RIGHT, LEFT, UP, DOWN, PAGE_UP, PAGE_DOWN = "\x1b[C", "\x1b[D", "\x1b[A", "\x1b[B", "\x1b[5~", "\x1b[6~"


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def device(monkeypatch):
    model = DeviceModel()
    monkeypatch.setattr(send, "open_transport", lambda args, machine: (model, 115200))
    return model


def moves(device):
    return [(r["x"], r["y"], r["z"]) for r in device.executed if r["kind"] == 0]


def test_one_move(capsys, device):
    code, out, err = run(capsys, "jog", "--sim-model", "X1", "y-0.5", "--feed", "600")
    assert code == 0 and err == "" and out == "machine position X1.000 Y-0.500 Z0.000 mm\n"
    assert moves(device) == [(100, -50, 0)] and device.position == [100, -50, 0]
    code, out, err = run(capsys, "jog", "--sim-model", "Z.25X-1")          # from where the first ended
    assert code == 0 and out == "machine position X0.000 Y-0.500 Z0.250 mm\n"
    assert device.position == [0, -50, 25]
    code, out, err = run(capsys, "jog", "X1", "--feed", "600", "Y0.5", "--sim-model", "z-.25")  # words and options mixed
    assert code == 0 and out == "machine position X1.000 Y0.000 Z0.000 mm\n", err


def test_the_work_position_with_a_parameter_file(capsys, device, tmp_path):
    """With a parameter file the jog also prints the work position its offsets give (to set a
    work origin by eye, as a sender shows WPos next to MPos)."""
    machine = tmp_path / "m.toml"
    machine.write_text('[gcode]\nparameter_file = "mill.var"\n')
    (tmp_path / "mill.var").write_text("5221\t-10.0\n")               # G54 X offset -10 mm
    code, out, err = run(capsys, "jog", "--sim-model", "X1", "--machine", str(machine))
    assert code == 0, err
    assert out.splitlines() == ["machine position X1.000 Y0.000 Z0.000 mm",
                                f"work position X11.000 Y0.000 Z0.000 mm (G54 X-10 Y0 Z0 mm: {tmp_path / 'mill.var'})"]


def test_beyond_the_travel_nothing_moves(capsys, device):
    """The travel of a homed axis (STATUS.position_set) holds; an axis not homed since the
    controller's reset jogs freely, as Grbl keeps soft limits only once homed."""
    device.position_set = 0b001                                  # X homed
    code, out, err = run(capsys, "jog", "--sim-model", "X1001")
    assert code == 2 and out == ""
    assert err == "interp: error: jog: X 1001 mm is beyond the X travel -1000 .. 1000 mm (machine file)\n"
    assert device.executed == []
    code, out, err = run(capsys, "jog", "--sim-model", "Y1001")
    assert code == 0 and out == "machine position X0.000 Y1001.000 Z0.000 mm\n", err


def test_less_than_half_a_step_is_refused(capsys, device):
    code, out, err = run(capsys, "jog", "--sim-model", "X0.004", "Y-0.0049")   # 100 steps/mm
    assert code == 2 and err == "interp: error: jog: less than half a step on every axis: nothing to move\n"
    assert device.executed == []


def test_a_stop_is_warned_of_and_homing_required_refuses(capsys, device, tmp_path):
    """An error latched in ERROR (here an abort at speed) is warned of, as interp send does; with
    homing.required the jog is refused until interp home, as Grbl's alarm lock refuses $J."""
    device.error = 19
    code, out, err = run(capsys, "jog", "--sim-model", "X1")
    assert code == 0 and "interp jog: warning: the controller stopped on error 19" in err
    device.error = 19
    machine = tmp_path / "m.toml"
    machine.write_text("[homing]\nrequired = true\n[axis.x]\nhome = \"min\"\n")
    code, out, err = run(capsys, "jog", "--sim-model", "X1", "--machine", str(machine))
    assert code == 1 and "run interp home (homing.required)" in err and len(moves(device)) == 1


@pytest.mark.parametrize("argv, word", [
    (["X1", "Q2"], "jog: Q2: give axis words in mm"),
    (["X1", "x2"], "jog: X given twice"),
    (["X"], "jog: X: give axis words"),
    (["X0", "Y0"], "every axis word is 0"),
    (["X1", "--feed", "0"], "--feed 0: give mm/min > 0"),
    (["X1", "--feed", "nan"], "--feed nan"),
    ([], "give the move (e.g. X10 Y-2.5), or run it on a terminal"),
    (["X1", "--port", "loop://"], "give one of --port DEVICE or --sim"),
    (["X1", "--bogus", "Y1"], "unrecognized arguments: --bogus"),
])
def test_usage_errors(capsys, device, argv, word):
    code, out, err = run(capsys, "jog", "--sim-model", *argv)
    assert code == 2 and word in err and len(err.splitlines()) == 1 and out == "", err
    assert device.executed == []


class Keys:
    """The keyboard: each call gives the next string of keys typed."""

    def __init__(self, *typed):
        self.typed = list(typed)

    def __call__(self) -> str:
        return self.typed.pop(0) if self.typed else "q"


def connected(model):
    driver = Driver(model, baud=115200)
    driver.connect()
    return driver


def test_the_keys(capsys):
    """Arrows X/Y, page keys Z, one jog of the increment a key; ] and [ change the increment
    (1 mm at first); keys typed in the same read after a jog key are dropped, a key that is no
    command is ignored."""
    model = DeviceModel()
    machine = load_machine()
    keys = Keys(RIGHT, "]", UP + RIGHT + RIGHT, PAGE_DOWN, "[[", "", "x", "\x1b[", "D", DOWN, "\x1b", "[5~", "q",
                RIGHT)
    assert jog.interactive(connected(model), machine, 600.0, keys, jog_keys=str) == 0
    assert moves(model) == [(100, 0, 0), (0, 1000, 0), (0, 0, -1000), (-10, 0, 0), (0, -10, 0), (0, 0, 10)]
    assert model.position == [90, 990, -990]
    out, err = capsys.readouterr()
    assert out.splitlines()[-1] == "machine position X0.900 Y9.900 Z-9.900 mm"
    assert "increment 1 mm at 600 mm/min" in err and "increment 0.1 mm" in err and keys.typed == [RIGHT]
    assert "increment 0.01 mm" not in err               # (an arrow cut between two reads is one key)


def test_ctrl_c_between_jogs_quits(capsys):
    def keys():
        raise KeyboardInterrupt
    assert jog.interactive(connected(DeviceModel()), load_machine(), 600.0, keys) == 0


def test_a_key_beyond_the_travel_is_refused_and_the_keys_go_on(capsys):
    model = DeviceModel()
    model.position, model.position_set = [95000, 0, 0], 0b111   # homed; X 950 mm of a travel to 1000 mm
    keys = Keys("]]", RIGHT, "[", RIGHT, "q")
    assert jog.interactive(connected(model), load_machine(), 6000.0, keys, jog_keys=str) == 0
    assert moves(model) == [(1000, 0, 0)] and model.position == [96000, 0, 0]
    err = capsys.readouterr().err
    assert "interp: jog: X 1050 mm is beyond the X travel -1000 .. 1000 mm (machine file)\n" in err, err


def test_ctrl_x_stops_a_jog_and_the_keys_go_on(capsys):
    """Ctrl-X during a jog: hold, then abort; the position is printed and the loop goes on."""
    model = DeviceModel(records_per_second=1.0)
    keys = Keys(RIGHT, "y", jog.STOP, "q")
    assert jog.interactive(connected(model), load_machine(), 600.0, keys) == 0
    out = capsys.readouterr().out
    assert out.startswith("machine position X") and out.rstrip().endswith(": the jog was stopped"), out


def test_a_controller_error_ends_the_keys(capsys):
    """A limit switch during a jog (ERROR 17): the position and the error, exit status 1."""
    model = DeviceModel(fail_at=1)
    assert jog.interactive(connected(model), load_machine(), 600.0, Keys(RIGHT, RIGHT), jog_keys=str) == 1
    assert capsys.readouterr().out.rstrip().endswith(": controller error 17 (limit switch)")


@pytest.mark.skipif(sys.platform != "linux", reason="a pty")
def test_the_keys_on_a_terminal(tmp_path):
    """interp jog without words on a real terminal: cbreak keys, one jog, q quits, the terminal's
    mode restored."""
    pid, fd = pty.fork()
    if pid == 0:                                        # the child: interp jog on the pty
        os.execv(sys.executable, [sys.executable, "-m", "interp.cli", "jog", "--sim-model", "--feed", "600"])
    output = b""

    def read_until(text: bytes, seconds: float = 60.0) -> None:
        nonlocal output
        end = time.monotonic() + seconds
        while text not in output and time.monotonic() < end:
            if select.select([fd], [], [], 0.1)[0]:
                try:
                    output += os.read(fd, 4096)
                except OSError:
                    break
        assert text in output, output

    try:
        read_until(b"keys: arrows")
        assert not termios.tcgetattr(fd)[3] & (termios.ICANON | termios.ECHO)       # cbreak, no echo
        os.write(fd, RIGHT.encode())
        read_until(b"machine position X1.000 Y0.000 Z0.000 mm")
        os.write(fd, b"q")
        _, status = os.waitpid(pid, 0)
        pid = 0
        assert os.waitstatus_to_exitcode(status) == 0, output
        assert termios.tcgetattr(fd)[3] & termios.ICANON and termios.tcgetattr(fd)[3] & termios.ECHO
    finally:
        if pid:
            os.kill(pid, 9)
            os.waitpid(pid, 0)
        os.close(fd)
