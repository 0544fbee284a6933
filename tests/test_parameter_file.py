# SPDX-License-Identifier: Apache-2.0
"""The parameter file (interp/gcode/parameter_file.py): work offsets, G92, the coordinate
system and the G28 / G30 positions outlive a program, as LinuxCNC's var file keeps them.
The file's format and its errors, the interpreter's start and end values, and `interp send`
/ `interp gcode` / `interp status` with a machine file that names one."""
from __future__ import annotations

import argparse

import pytest

from interp.cli import main
from interp.commands import send
from interp.cores import UsageError
from interp.gcode.interpreter import interpret
from interp.gcode.parameter_file import SAVED, describe, offset_number, read_parameters, write_parameters
from interp.link.devicemodel import DeviceModel


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


# ---------------- the file ----------------

def test_round_trip_in_number_order(tmp_path):
    path = tmp_path / "m.var"
    values = interpret("G10 L2 P2 X1.25 Y-3 Z0.1\nG92 X0\nG28.1\n", start=(7.5, 2.0, 0.0)).saved
    assert sorted(values) == list(SAVED)
    write_parameters(path, values)
    lines = path.read_text().splitlines()
    assert [int(line.split()[0]) for line in lines] == list(SAVED)
    assert "5241\t1.25" in lines and "5211\t7.5" in lines and "5161\t7.5" in lines and "5210\t1.0" in lines
    assert read_parameters(path) == values
    assert not (tmp_path / "m.var.new").exists()


def test_a_missing_file_is_no_parameter(tmp_path):
    assert read_parameters(tmp_path / "none.var") == {}


def test_a_byte_order_mark_and_crlf_are_read(tmp_path):
    path = tmp_path / "notepad.var"
    path.write_bytes(b"\xef\xbb\xbf5221 1.5\r\n5220 2\r\n")
    assert read_parameters(path) == {5221: 1.5, 5220: 2.0}


def test_a_path_the_system_refuses_is_one_line(tmp_path):
    with pytest.raises(UsageError, match="cannot read parameter file"):
        read_parameters(tmp_path / "a\x00b")


def test_a_linuxcnc_var_file_with_its_other_axes_at_zero(tmp_path):
    path = tmp_path / "linuxcnc.var"
    path.write_text("5161\t0.000000\n5164\t0.000000\n5220\t2.000000\n\n5241\t10.000000\n5249\t0.000000\n"
                    "5250\t0.000000\n")
    assert read_parameters(path) == {5161: 0.0, 5220: 2.0, 5241: 10.0}


@pytest.mark.parametrize("text, message", [
    ("5221 1 2\n", "line 1: want a parameter number and its value (got '5221 1 2')"),
    ("5221\n", "line 1: want a parameter number and its value"),
    ("\nX 1\n", "line 2: want a parameter number and its value (got 'X 1')"),
    ("5221 nan\n", "line 1: #5221 must be a finite number (got nan)"),
    ("5221 1\n5221 2\n", "line 2: #5221 is given twice"),
    ("100 1\n", "line 1: #100 is not a saved parameter (the file keeps #5161 .. #5390)"),
    ("5224 3\n", "line 1: #5224 (the G54 offset of axis A) must be 0: this machine has axes X Y Z and no rotation"),
    ("5250 30\n", "line 1: #5250 (the G55 rotation) must be 0"),
    ("5220 10\n", "line 1: #5220 (the coordinate system) must be 1 .. 9 (got 10)"),
    ("5220 1.5\n", "line 1: #5220 (the coordinate system) must be 1 .. 9 (got 1.5)"),
    ("5210 2\n", "line 1: #5210 (G92 applies) must be 0 or 1 (got 2)"),
    ("5222 1e9\n", "line 1: #5222 must be within +-1e+07 mm (got 1e+09)"),
    (b"\xff5221 1\n", "not UTF-8 text (byte 0)"),
])
def test_a_bad_file_is_one_line_naming_the_line(tmp_path, text, message):
    path = tmp_path / "bad.var"
    path.write_bytes(text if isinstance(text, bytes) else text.encode())
    with pytest.raises(UsageError) as info:
        read_parameters(path)
    assert str(info.value).startswith(str(path)) and message in str(info.value)


def test_describe_names_the_offsets_in_force():
    assert describe({}) == ""
    assert describe({5220: 2.0, 5241: 1.5, 5242: -2.0, 5221: 9.0}) == "G55 X1.5 Y-2 Z0 mm"
    assert describe({5210: 1.0, 5213: -1.0}) == "G92 X0 Y0 Z-1 mm"
    assert describe({5210: 0.0, 5213: -1.0}) == ""                       # G92 suspended
    assert describe({5221: -0.0, 5222: 1.0}) == "G54 X0 Y1 Z0 mm"
    assert offset_number(9, 2) == 5383


# ---------------- the interpreter's start and end ----------------

def test_a_program_starts_with_the_saved_offsets():
    saved = {5220: 2.0, offset_number(2, 0): 10.0, offset_number(2, 1): 20.0, 5210: 1.0, 5213: -2.0}
    program = interpret("G0 X1 Y2 Z3\n", saved=saved)
    assert program.moves[0].end == (11.0, 22.0, 1.0)
    assert program.saved[5220] == 2.0 and program.saved[5210] == 1.0     # no M2: kept as they are
    # G54 selected again: its own (zero) offsets, G92 still applies
    assert interpret("G54 G0 X1 Z0\n", saved=saved).moves[0].end == (1.0, 0.0, -2.0)


def test_the_end_values_in_machine_mm():
    program = interpret("G20\nG10 L2 P3 X1\n#5262 = 2\nG28.1\n", start=(5.0, 0.0, 0.0))
    assert program.saved[offset_number(3, 0)] == pytest.approx(25.4)     # inches -> mm
    assert program.saved[offset_number(3, 1)] == pytest.approx(50.8)     # assigned, taken as it is
    assert program.saved[5161] == 5.0


def test_program_end_selects_g54_and_keeps_g92():
    """As Grbl and LinuxCNC end a program: G54 again, the G92 offset still applied."""
    program = interpret("G55\nG92 X0\nM2\n", start=(4.0, 0.0, 0.0))
    assert program.saved[5220] == 1.0 and program.saved[5210] == 1.0 and program.saved[5211] == 4.0
    assert interpret("G0 X1\n", saved=program.saved).moves[0].end == (5.0, 0.0, 0.0)
    suspended = interpret("G92.2\nM30\n", saved=program.saved).saved
    assert suspended[5210] == 0.0 and interpret("G92.3\nG0 X1\n", saved=suspended).moves[0].end == (5.0, 0.0, 0.0)


def test_the_program_reads_the_saved_values():
    program = interpret("#1 = #5241\nG0 X#1 Y#5211\n", saved={5241: 3.0, 5211: 2.0})
    assert program.moves[0].end == (3.0, 2.0, 0.0)


def test_an_assignment_keeps_its_units_when_the_units_change():
    """#5221 = 10 under G21 is 10 mm, whatever G20 comes after, and a saved value does not
    overwrite it."""
    assert interpret("G21\n#5221 = 10\nG20\n").saved[5221] == pytest.approx(10.0)
    assert interpret("G21\n#5221 = 10\nG20\n", saved={5221: 5.0}).saved[5221] == pytest.approx(10.0)
    assert interpret("G21\n#5221 = 10\nG20\nG54\nG0 X0\n").moves[0].end[0] == pytest.approx(10.0)


def test_saved_positions_override_the_machine_files():
    program = interpret("G28\n", g28=(1.0, 1.0, 1.0), saved={5161: 3.0, 5162: 4.0, 5163: 5.0})
    assert program.moves[-1].end == (3.0, 4.0, 5.0)


# ---------------- the commands ----------------

@pytest.fixture
def machine_file(tmp_path):
    path = tmp_path / "mill.toml"
    path.write_text('[gcode]\nparameter_file = "mill.var"\n')
    return path


def test_send_keeps_a_work_offset_for_the_next_program(capsys, tmp_path, machine_file, monkeypatch):
    """Set G54 where the tool is (G10 L20), then run a job in G54: it cuts there.  Without the
    file the second program would start with G54 = machine zero."""
    device = DeviceModel()
    monkeypatch.setattr(send, "open_transport", lambda args, machine: (device, 115200))
    touch_off, job = tmp_path / "touch.nc", tmp_path / "job.nc"
    touch_off.write_text("G21 G90\nG0 X10 Y5\nG10 L20 P1 X0 Y0\n")
    job.write_text("G21 G90 G54\nG0 X1 Y1\nG0 X0 Y0\nM2\n")
    code, out, err = run(capsys, "send", str(touch_off), "--sim-model", "--machine", str(machine_file))
    assert code == 0, err
    var = tmp_path / "mill.var"
    assert err.strip() == f"interp send: saved the offsets to {var}: G54 X10 Y5 Z0 mm"
    assert read_parameters(var)[offset_number(1, 0)] == 10.0
    assert 5161 not in read_parameters(var)             # G28 as the machine file has it: not kept
    code, out, err = run(capsys, "send", str(job), "--sim-model", "--machine", str(machine_file))
    assert code == 0, err
    assert f"interp send: offsets from {var}: G54 X10 Y5 Z0 mm" in err.splitlines()
    assert "saved" not in err                           # nothing changed: the file is left alone
    moves = [(r["x"], r["y"], r["z"]) for r in device.executed if r["kind"] == 0]
    assert moves[-2:] == [(100, 100, 0), (-100, -100, 0)]     # from (1000, 500) to G54 X1 Y1 and back
    code, out, err = run(capsys, "gcode", str(job), "--machine", str(machine_file), "--check")
    assert code == 0 and "end X0 Y0 Z0 mm (work) = (1000, 500, 0) steps" in out
    code, out, err = run(capsys, "status", "--sim-model", "--machine", str(machine_file))
    assert out.splitlines()[-2:] == ["machine position X10.000 Y5.000 Z0.000 mm",
                                     f"work position X0.000 Y0.000 Z0.000 mm (G54 X10 Y5 Z0 mm: {var})"]


def test_a_run_that_does_not_end_saves_nothing(capsys, tmp_path, machine_file, monkeypatch):
    monkeypatch.setattr(send, "open_transport", lambda args, machine: (DeviceModel(fail_at=2), 115200))
    program = tmp_path / "p.nc"
    program.write_text("G10 L2 P1 X5\nG0 X1\nG0 X2\nG0 X3\n")
    code, out, err = run(capsys, "send", str(program), "--sim-model", "--machine", str(machine_file))
    assert code == 1 and "controller error 17" in err
    assert not (tmp_path / "mill.var").exists()


def test_a_simulated_run_reads_the_file_and_leaves_it(tmp_path, machine_file):
    from interp.gcode.machine import load_machine

    machine = load_machine(str(machine_file))
    after = interpret("G10 L2 P1 X5\n").saved
    send.save_parameters(argparse.Namespace(sim=True), machine, {}, after)
    assert not (tmp_path / "mill.var").exists()
    send.save_parameters(argparse.Namespace(sim=False), machine, {}, after)
    homes = {5161, 5162, 5163, 5181, 5182, 5183}             # as the machine file's: not kept
    assert read_parameters(tmp_path / "mill.var") == {k: v for k, v in after.items() if k not in homes}


def test_a_bad_parameter_file_stops_send_before_the_link(capsys, tmp_path, machine_file):
    (tmp_path / "mill.var").write_text("5221 x\n")
    program = tmp_path / "p.nc"
    program.write_text("G0 X1\n")
    code, out, err = run(capsys, "send", str(program), "--sim-model", "--machine", str(machine_file))
    assert code == 2
    assert err.strip() == (f"interp: error: {tmp_path / 'mill.var'} line 1: want a parameter number and its "
                           "value (got '5221 x')")


def test_nothing_set_leaves_no_file(capsys, tmp_path, machine_file, monkeypatch):
    monkeypatch.setattr(send, "open_transport", lambda args, machine: (DeviceModel(), 115200))
    program = tmp_path / "p.nc"
    program.write_text("G0 X1\nG55 G0 X2\nM2\n")
    code, out, err = run(capsys, "send", str(program), "--sim-model", "--machine", str(machine_file))
    assert code == 0 and err == "" and not (tmp_path / "mill.var").exists()


def test_an_offset_the_file_cannot_keep_is_refused_before_the_run(capsys, tmp_path, machine_file, monkeypatch):
    device = DeviceModel()
    monkeypatch.setattr(send, "open_transport", lambda args, machine: (device, 115200))
    program = tmp_path / "p.nc"
    program.write_text("G10 L2 P2 X100000000\nG0 X1\n")
    code, out, err = run(capsys, "send", str(program), "--sim-model", "--machine", str(machine_file))
    assert code == 2 and not device.executed and not (tmp_path / "mill.var").exists()
    assert err.strip() == ("interp: error: the program leaves #5241 at 1e+08 mm: a parameter file keeps at most "
                           "+-1e+07 mm")


def test_a_folder_that_is_missing_is_refused_before_the_run(capsys, tmp_path, monkeypatch):
    device = DeviceModel()
    monkeypatch.setattr(send, "open_transport", lambda args, machine: (device, 115200))
    machine = tmp_path / "m.toml"
    machine.write_text('[gcode]\nparameter_file = "nodir/mill.var"\n')
    program = tmp_path / "p.nc"
    program.write_text("G10 L20 P1 X0\n")
    code, out, err = run(capsys, "send", str(program), "--sim-model", "--machine", str(machine))
    assert code == 2 and not device.frames
    assert err.strip() == (f"interp: error: cannot write parameter file {tmp_path / 'nodir' / 'mill.var'}: "
                           "its folder is missing or not writable")


def test_status_with_a_bad_file_still_prints_the_registers(capsys, tmp_path, machine_file):
    (tmp_path / "mill.var").write_text("5221\n")
    code, out, err = run(capsys, "status", "--sim-model", "--machine", str(machine_file))
    assert code == 0 and out.splitlines()[0].startswith("ID ")
    assert out.splitlines()[-1].startswith(f"work position unknown: {tmp_path / 'mill.var'} line 1: ")
