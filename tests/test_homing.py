# SPDX-License-Identifier: Apache-2.0
"""`interp home` (interp/commands/home.py) against the Python model of the controller with
limit switches where the machine's true travel ends are (the position counters know nothing
of them until homing sets them): the seek, pull-off, slow approach and position set of each
axis; switches not found, stuck or wrong; `homing.required` in `interp send`; and the
model's POS writes (refused while busy) and STATUS.position_set."""
from __future__ import annotations

import pytest

from interp.cli import main
from interp.commands import send
from interp.link.devicemodel import DeviceModel

MACHINE = """
[axis.x]
min_mm = -100
max_mm = 300
home = "min"
[axis.z]
min_mm = -80
max_mm = 50
home = "max"
[homing]
seek_mm_min = 600
locate_mm_min = 60
pull_off_mm = 2
"""


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def machine_file(tmp_path):
    path = tmp_path / "mill.toml"
    path.write_text(MACHINE)
    return str(path)


def attach(monkeypatch, device):
    monkeypatch.setattr(send, "open_transport", lambda args, machine: (device, 115200))


def test_homing_sets_each_axis_at_its_switch(capsys, machine_file, monkeypatch):
    """The machine powered up somewhere: X's switch 123.45 mm below, Z's 7.77 mm above (in
    the counters' frame).  After homing each axis stands at its travel end (X at min_mm
    -100, Z at max_mm 50), its switch a pull-off (2 mm) beyond; Y (no home end) is left
    alone."""
    device = DeviceModel(switches={0: ("min", -12345), 2: ("max", 777)})
    attach(monkeypatch, device)
    code, out, err = run(capsys, "home", "--sim-model", "--machine", machine_file)
    assert code == 0, err
    lines = out.splitlines()
    assert lines[:2] == ["homed Z: switch at 52.000 mm, now at 50.000 mm",
                         "homed X: switch at -102.000 mm, now at -100.000 mm"]
    assert lines[2].startswith("machine position X-100.000 Y0.000 Z50.000 mm (")
    assert device.position == [-10000, 0, 5000] and device.position_set == 0b101
    assert [w for w in device.writes if w[0].startswith("POS")] == [("POS_Z", 5000), ("POS_X", -10000 & 0xFFFFFFFF)]
    assert device.switches == {0: ("min", -10200), 2: ("max", 5200)}     # on the machine: where they were
    # Z: seek up to the switch, 2 mm down, 4 mm up (slow) to the switch again, set, 2 mm down
    z_moves = [r["z"] for r in device.executed if r["kind"] == 0 and r["z"]]
    assert z_moves == [19700, -200, 400, -200]          # the seek record: 1.5 travels + a pull-off
    assert device.error == 0 and not any(device.switch_active(a) for a in range(3))


def test_one_axis_only(capsys, machine_file, monkeypatch):
    device = DeviceModel(switches={0: ("min", -500), 2: ("max", 777)})
    attach(monkeypatch, device)
    code, out, err = run(capsys, "home", "--sim-model", "--machine", machine_file, "--axes", "x")
    assert code == 0, err
    assert out.startswith("homed X:")
    assert device.position_set == 0b001 and device.position[2] == 0


@pytest.mark.parametrize("switches, message", [
    ({0: ("min", -12345)}, "homing Z: no limit switch was found during the seek (197 mm towards max)"),
])
def test_homing_errors_are_one_line(capsys, machine_file, monkeypatch, switches, message):
    attach(monkeypatch, DeviceModel(switches=switches))
    code, out, err = run(capsys, "home", "--sim-model", "--machine", machine_file)
    assert code == 1
    assert err.strip() == f"interp: error: {message}"


def test_another_axis_on_its_switch(capsys, tmp_path, monkeypatch):
    """X rests on its switch (no edge, no trip) while Y homes."""
    path = tmp_path / "m.toml"
    path.write_text('[axis.y]\nhome = "min"\n')
    device = DeviceModel(switches={0: ("min", 0), 1: ("min", -10)})
    attach(monkeypatch, device)
    code, out, err = run(capsys, "home", "--sim-model", "--machine", str(path))
    assert code == 0, err
    assert out.startswith("homed Y: switch at -1001.000 mm, now at -1000.000 mm") and device.switch_active(0)


def test_a_switch_wired_to_another_input(capsys, machine_file, monkeypatch):
    class Crossed(DeviceModel):
        def _line(self, record):
            tripped = super()._line(record)
            if tripped:
                self.limits = 0b001                 # Z's switch on X's input
            return tripped

    attach(monkeypatch, Crossed(switches={2: ("max", 777)}))
    code, out, err = run(capsys, "home", "--sim-model", "--machine", machine_file)
    assert code == 1
    assert err.strip() == "interp: error: homing Z: the X limit switch tripped during the seek (197 mm towards max)"


def test_a_switch_that_stays_active_after_the_pull_off(capsys, machine_file, monkeypatch):
    class Sticky(DeviceModel):
        def switch_active(self, axis):
            return axis == 2 and self.position[2] >= 500 if self.executed else False

    attach(monkeypatch, Sticky(switches={2: ("max", 777)}))
    code, out, err = run(capsys, "home", "--sim-model", "--machine", machine_file)
    assert code == 1
    assert err.strip() == ("interp: error: homing Z: the limit switch is still active after the pull-off of 2 mm: "
                           "raise homing.pull_off_mm")


@pytest.mark.parametrize("argv, word", [
    ([], "interp home: give --port DEVICE or --sim"),
    (["--sim", "--sim-model"], "give one of --port DEVICE or --sim (got --sim and --sim-model)"),
    (["--sim-model", "--seed", "3"], "unrecognized arguments: --seed"),
    (["--sim-model", "--axes", "q"], "--axes q: give axes of XYZ"),
    (["--sim-model", "--axes", "zz"], "--axes zz: an axis given twice"),
    (["--sim-model", "--axes", "y"], "--axes y: Y has no home end"),
])
def test_usage_errors(capsys, machine_file, argv, word):
    code, out, err = run(capsys, "home", "--machine", machine_file, *argv)
    assert code == 2 and word in err and len(err.strip().splitlines()) == 1


def test_no_axis_to_home(capsys, tmp_path):
    code, out, err = run(capsys, "home", "--sim-model")
    assert code == 2 and "no axis to home" in err
    path = tmp_path / "m.toml"
    path.write_text("[homing]\nrequired = true\n")
    code, out, err = run(capsys, "home", "--sim-model", "--machine", str(path))
    assert code == 2 and "homing.required needs an axis to home" in err


def test_an_axis_resting_on_its_switch_pulls_off_first(capsys, machine_file, monkeypatch):
    device = DeviceModel(switches={2: ("max", 0)})
    attach(monkeypatch, device)
    code, out, err = run(capsys, "home", "--sim-model", "--machine", machine_file, "--axes", "z")
    assert code == 0, err
    assert out.startswith("homed Z: switch at 52.000 mm, now at 50.000 mm") and device.position[2] == 5000


def test_a_switch_that_bounces_as_it_lets_go(capsys, machine_file, monkeypatch):
    """The pull-off trips the limit again (ERROR 17 on the same axis): the rest of it is run
    again, and the axis ends where it would have."""
    class Bouncy(DeviceModel):
        bounces = 2

        def _line(self, record):
            if record["z"] < 0 and self.bounces:            # moving off Z's switch
                self.bounces -= 1
                self.position[2] += record["z"] // 4
                self.error, self.limits = 17, 0b100
                return True
            return super()._line(record)

    device = Bouncy(switches={2: ("max", 777)})
    attach(monkeypatch, device)
    code, out, err = run(capsys, "home", "--sim-model", "--machine", machine_file, "--axes", "z")
    assert code == 0, err
    assert out.startswith("homed Z: switch at 52.000 mm, now at 50.000 mm") and device.position[2] == 5000
    assert device.bounces == 0


def test_send_refuses_an_unhomed_machine_when_homing_is_required(capsys, tmp_path, machine_file, monkeypatch):
    path = tmp_path / "required.toml"
    path.write_text(MACHINE + "required = true\n")
    program = tmp_path / "p.nc"
    program.write_text("G0 X0\n")
    device = DeviceModel(switches={0: ("min", -12345), 2: ("max", 777)})
    attach(monkeypatch, device)
    code, out, err = run(capsys, "send", str(program), "--sim-model", "--machine", str(path))
    assert code == 1
    assert err.strip() == ("interp: error: the machine is not homed since the controller's reset (Z X): "
                           "run interp home (homing.required)")
    assert not device.executed
    assert run(capsys, "home", "--sim-model", "--machine", str(path))[0] == 0
    code, out, err = run(capsys, "send", str(program), "--sim-model", "--machine", str(path))
    assert code == 0, err
    assert device.position == [0, 0, 5000]
    # a limit tripped at speed: the motors may have lost steps, home again (Grbl's alarm)
    device.error, device.limits = 17, 1
    code, out, err = run(capsys, "send", str(program), "--sim-model", "--machine", str(path))
    assert code == 1 and err.strip() == ("interp: error: the controller stopped on error 17 (limit switch): the "
                                         "motors may have lost steps: run interp home (homing.required)")
    assert run(capsys, "home", "--sim-model", "--machine", str(path))[0] == 0
    assert run(capsys, "send", str(program), "--sim-model", "--machine", str(path))[0] == 0
    # an abort at speed (Ctrl-X twice, Ctrl-C: Grbl's alarm 3) too
    device.error = 19
    code, out, err = run(capsys, "send", str(program), "--sim-model", "--machine", str(path))
    assert code == 1 and "stopped on error 19 (aborted at speed): the motors may have lost steps" in err, err
    assert run(capsys, "home", "--sim-model", "--machine", str(path))[0] == 0
    # without homing.required the same controller runs at once
    assert run(capsys, "send", str(program), "--sim-model", "--machine", machine_file)[0] == 0


def test_the_model_refuses_a_position_write_while_busy():
    device = DeviceModel()
    device.queue += bytes(200)                      # a whole record waits: busy
    device.hold = True
    device.write_register(0x24, 5)
    assert device.refused and device.position == [0, 0, 0] and device.position_set == 0
    device.hold, device.queue = False, bytearray()
    device.write_register(0x24, 0xFFFFFFFB)
    assert device.position == [-5, 0, 0] and device.position_set == 1
