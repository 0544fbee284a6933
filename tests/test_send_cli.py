# SPDX-License-Identifier: Apache-2.0
"""`interp send` and `interp status` (interp/commands/send.py, status.py) against the Python
model of the controller (the hidden --sim-model) and pyserial URLs: results, errors as one
line, exit status."""
from __future__ import annotations

import io
import sys
from pathlib import Path

import pytest

from interp.cli import main
from interp.commands import gcode, send
from interp.link.devicemodel import DeviceModel
from interp.link.records import Build, encode_program

CORPUS = Path(__file__).resolve().parents[1] / ".." / "shared" / "gcode"
PROGRAM = "G21 G90\nG1 X1 F600\nG1 Y1\nG1 X0\nM3 S1000\nG1 Y0\nM5\nM2\n"


@pytest.fixture
def program(tmp_path):
    path = tmp_path / "square.nc"
    path.write_text(PROGRAM)
    return str(path)


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_send_sim_model(capsys, program):
    code, out, err = run(capsys, "send", program, "--sim-model")
    _, compiled = gcode.compile_text(PROGRAM)
    assert code == 0, err
    size = len(encode_program(compiled.commands, codes=compiled))                   # compact records
    assert 8 * len(compiled.commands) <= size < 42 * len(compiled.commands)
    assert out.startswith(f"sent {len(compiled.commands)} records ({size} bytes)")
    assert err == ""


def test_send_sim_model_noise(capsys, program):
    code, out, err = run(capsys, "send", program, "--sim-model", "--line-noise", "0.002", "--seed", "3")
    assert code == 0, err
    assert "retransmissions" in out and " 0 retransmissions" not in out


@pytest.mark.skipif(not (CORPUS / "ugs_square.nc").exists(), reason="the G-code corpus is not beside the repository")
def test_send_corpus_program(capsys):
    code, out, err = run(capsys, "send", str(CORPUS / "ugs_square.nc"), "--sim-model")
    _, compiled = gcode.compile_text((CORPUS / "ugs_square.nc").read_text())
    assert code == 0 and out.startswith(f"sent 101 records ({len(encode_program(compiled.commands, codes=compiled))} bytes)")


def test_the_model_follows_arcs_in_every_plane(capsys, tmp_path):
    """The controller's model moves arcs (G17, G18, G19, a helix of three turns) to their ends:
    the run ends where `interp gcode` ends."""
    path = tmp_path / "arcs.nc"
    path.write_text("G21 G90\nG1 X10 F1000\nG2 X20 Y0 I5 J0\nG3 X10 Y0 R5\nG18 G2 X0 Z0 I-5 K0\n"
                    "G19 G3 Y5 Z5 J2.5 K2.5\nG17 G2 X2 Y5 Z1 I1 J1 P3\nM2\n")
    code, out, err = run(capsys, "send", str(path), "--sim-model")
    assert code == 0 and err == "" and out.rstrip().endswith("end (200, 500, 100) steps"), (out, err)


def test_program_from_standard_input(capsys, monkeypatch):
    """FILE -: a jog or an MDI line piped in."""
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(b"G21 G91\nG0 X2 Y-1\n")))
    code, out, err = run(capsys, "send", "-", "--sim-model")
    assert code == 0, err
    assert out.rstrip().endswith("end (200, -100, 0) steps")


def test_machine_error_line(capsys, program):
    """A machine error names the record and the program line, and says how to run on from that
    line (run from a line); that run ends where the program ends."""
    _, compiled = gcode.compile_text(PROGRAM)
    line = compiled.commands[2].source
    code, out, err = run(capsys, "send", program, "--sim-model", "--sim-model-fail", "3")
    assert code == 1
    assert err.strip().splitlines() == [
        f"interp: error: controller error 17 (limit switch, x limit) at record 3 of {len(compiled.commands)}, "
        f"line {line}",
        f"interp send: to run on from that line once the machine is ready: interp send {program} --start-line "
        f"{line} ..."]
    code, out, err = run(capsys, "send", program, "--sim-model", "--start-line", str(line))
    assert code == 0 and out.rstrip().endswith("end (0, 0, 0) steps"), (out, err)


def test_run_on_hint_inside_a_subroutine_names_its_call(capsys, tmp_path):
    """An error while a subroutine's body runs: the message names the body's line, the hint the
    call's line (a run from a line inside a body is refused); that run ends where the program
    ends."""
    path = tmp_path / "sub.nc"
    path.write_text("G21 G90\no100 sub\nG1 X[#1] F600\nG1 Y[#1]\no100 endsub\nG1 X1 F600\n"
                    "o100 call [5]\nG1 X0 Y0\nM2\n")
    code, out, err = run(capsys, "send", str(path), "--sim-model", "--sim-model-fail", "3")
    assert code == 1 and err.strip().splitlines() == [
        "interp: error: controller error 17 (limit switch, x limit) at record 3 of 5, line 4",
        f"interp send: to run on from that line once the machine is ready: interp send {path} --start-line 7 ..."], err
    code, out, err = run(capsys, "send", str(path), "--sim-model", "--start-line", "7")
    assert code == 0 and out.rstrip().endswith("end (0, 0, 0) steps"), (out, err)


def test_no_run_on_hint_for_a_program_run_from_its_start(capsys, tmp_path):
    """A G91 program runs from where it started: the run from a line would be refused, so the
    error gives no hint."""
    path = tmp_path / "g91.nc"
    path.write_text("G21 G91\nG1 X1 F600\nG1 Y1\nG1 X-1\nG1 Y-1\nM2\n")
    code, out, err = run(capsys, "send", str(path), "--sim-model", "--sim-model-fail", "3")
    assert code == 1 and len(err.strip().splitlines()) == 1 and "controller error 17" in err, err


def test_a_board_reports_its_end_position(capsys, tmp_path, monkeypatch):
    """A serial port says nothing when it closes: the summary's end position comes from the
    controller's POS_X/Y/Z, read once the program is done."""
    class Port(DeviceModel):
        def close(self):
            super().close()
            return None

    monkeypatch.setattr(send, "open_transport", lambda args, machine: (Port(), 115200))
    program = tmp_path / "p.nc"
    program.write_text("G21 G90\nG1 X8 Y-4 F600\nM2\n")
    code, out, err = run(capsys, "send", str(program), "--sim-model")
    assert code == 0 and err == "" and out.rstrip().endswith("end (800, -400, 0) steps"), out


def test_a_program_starts_where_the_machine_is(capsys, tmp_path, monkeypatch):
    """The controller's position counters survive a run (only its reset clears them): the next
    program is compiled from there, as Grbl runs it, so G90 X0 goes back to machine zero.  A
    program compiled from 0 would run shifted by where the last one ended."""
    device = DeviceModel()
    monkeypatch.setattr(send, "open_transport", lambda args, machine: (device, 115200))
    first, second = tmp_path / "first.nc", tmp_path / "second.nc"
    first.write_text("G21 G90\nG1 X8 Y-4 F600\nM2\n")
    second.write_text("G21 G90\nG1 X1 F600\nG0 X0 Y0\nM2\n")
    code, out, err = run(capsys, "send", str(first), "--sim-model")
    assert code == 0 and err == "" and out.rstrip().endswith("end (800, -400, 0) steps")
    code, out, err = run(capsys, "send", str(second), "--sim-model")
    assert code == 0, err
    assert err.strip() == ("interp send: the machine is at X8.000 Y-4.000 Z0.000 mm (machine coordinates): "
                           "the program starts there")
    assert out.rstrip().endswith("end (0, 0, 0) steps")
    moves = [(r["x"], r["y"], r["z"]) for r in device.executed if r["kind"] == 0]
    assert moves[-2:] == [(-700, 0, 0), (-100, 400, 0)]          # from (800, -400), not from 0
    # compiled only from there: this half circle of radius 1 is too small for a start at 0
    assert run(capsys, "send", str(first), "--sim-model")[0] == 0
    second.write_text("G21 G90\nG2 X10 Y-4 R1 F600\nM2\n")
    code, out, err = run(capsys, "send", str(second), "--sim-model")
    assert code == 0, err


def test_a_run_after_an_alarm_warns_of_lost_steps(capsys, program, monkeypatch):
    """A limit switch stops the steps at once (ALARM): the next run starts from the counters but
    says they may not be where the motors are."""
    device = DeviceModel(fail_at=3)
    monkeypatch.setattr(send, "open_transport", lambda args, machine: (device, 115200))
    assert run(capsys, "send", program, "--sim-model")[0] == 1
    code, out, err = run(capsys, "send", program, "--sim-model")
    assert code == 0, err
    assert ("interp send: warning: the controller stopped on error 17 (limit switch): its steps stopped at "
            "once, so the motors may have lost steps the position counts") in err.splitlines()


def test_the_machine_files_polarity_is_written_once(capsys, program, tmp_path, monkeypatch):
    """input.invert, input.filter_us / unfiltered and output.invert reach INPUT_INVERT,
    INPUT_FILTER and OUTPUT_INVERT before anything runs, and only where they differ: a second
    run writes none of them."""
    device = DeviceModel()
    monkeypatch.setattr(send, "open_transport", lambda args, machine: (device, 115200))
    machine = tmp_path / "m.toml"
    machine.write_text('[input]\ninvert = ["probe"]\nfilter_us = 200\nunfiltered = ["probe"]\n'
                       '[output]\ninvert = ["dir_y", "enable"]\n')
    for _ in range(2):
        assert run(capsys, "send", program, "--sim-model", "--machine", str(machine))[0] == 0
    assert device.regs["INPUT_INVERT"] == 0x10 and device.regs["OUTPUT_INVERT"] == 0x50
    assert device.regs["SPINDLE_PERIOD"] == 50000                      # spindle.pwm_hz 1000 at 50 MHz
    assert device.regs["INPUT_FILTER"] == 0x0F << 16 | 2500             # 50 us a sample at 50 MHz
    written = [name for name, _ in device.writes if name.startswith(("INPUT_", "OUTPUT_"))]
    assert written == ["INPUT_INVERT", "INPUT_FILTER", "OUTPUT_INVERT"]
    assert device.writes[:3] == [("INPUT_INVERT", 0x10), ("INPUT_FILTER", 0x0F09C4), ("OUTPUT_INVERT", 0x50)]


def test_an_input_filter_that_is_off_is_not_written_to_an_older_bitstream():
    """INPUT_FILTER with period 0 counts as equal whatever its mask: a bitstream from before
    the register (which reads 0 there) is not written and raises no error."""
    from interp.link.driver import Driver, apply_pin_settings

    device = DeviceModel()
    device.regs["INPUT_FILTER"] = 0                                    # what an older bitstream reads
    driver = Driver(device, baud=115200)
    driver.connect()
    apply_pin_settings(driver, {"INPUT_FILTER": 0x1F << 16})
    assert [name for name, _ in device.writes] == []
    apply_pin_settings(driver, {"INPUT_FILTER": 0x1F << 16 | 25})
    assert device.writes == [("INPUT_FILTER", 0x1F0019)]


@pytest.mark.parametrize("error, limits, before, after, cleared", [
    (16, 0, 0, 0b00001, True),           # the e-stop's polarity changed, it reads inactive now
    (16, 0, 0b00001, 0b00001, False),    # no change: a real e-stop
    (16, 0, 0, 0b10000, False),          # only the probe's polarity changed
    (17, 0b001, 0, 0b00010, True),       # the X limit's polarity changed
    (17, 0b011, 0, 0b00010, False),      # X and Y tripped, only X's polarity changed
    (19, 0, 0, 0b11111, False),          # an abort at speed is not an input
])
def test_an_error_of_the_old_input_polarity_is_cleared(error, limits, before, after, cleared):
    """apply_pin_settings clears an e-stop or limit error only when the polarity of every input
    behind it changed (a normally-open switch read active under the reset's polarity) and
    the input reads inactive now; any other error stays."""
    from interp.link.driver import Driver, apply_pin_settings

    device = DeviceModel()
    device.error, device.limits, device.regs["INPUT_INVERT"] = error, limits, before
    driver = Driver(device, baud=115200)
    driver.connect()
    apply_pin_settings(driver, {"INPUT_INVERT": after})
    assert device.regs["INPUT_INVERT"] == after
    assert device.error == (0 if cleared else error)


def test_output_polarity_is_written_with_the_drivers_disabled():
    """A changed step bit makes an edge on its pin: CONTROL.enable is off while OUTPUT_INVERT
    changes, then restored; an unchanged value is not written."""
    from interp.link.driver import Driver, apply_pin_settings
    from interp.link import protocol as p

    device = DeviceModel()
    driver = Driver(device, baud=115200)
    driver.connect()
    driver.write_register("CONTROL", p.CONTROL_ENABLE)
    device.writes.clear()
    apply_pin_settings(driver, {"OUTPUT_INVERT": 0x7})
    assert device.writes == [("CONTROL", 0), ("OUTPUT_INVERT", 7), ("CONTROL", p.CONTROL_ENABLE)]
    apply_pin_settings(driver, {"OUTPUT_INVERT": 0x7})
    assert len(device.writes) == 3


def test_the_simulator_takes_no_polarity(capsys, program, tmp_path, monkeypatch):
    """--sim: the simulated pins are ideal (and its steps file counts them): the machine file's
    polarity is not written."""
    device = DeviceModel()
    monkeypatch.setattr(send, "open_transport", lambda args, machine: (device, 115200))
    machine = tmp_path / "m.toml"
    machine.write_text('[input]\ninvert = ["estop"]\n[output]\ninvert = ["step_x"]\n')
    assert run(capsys, "send", program, "--sim", "--machine", str(machine))[0] == 0
    assert not [name for name, _ in device.writes if name.endswith("_INVERT")]


def test_build_mismatch_exit_2(capsys, program, monkeypatch):
    monkeypatch.setattr(send, "open_transport", lambda args, machine: (DeviceModel(build=Build(MW=10)), 115200))
    code, out, err = run(capsys, "send", program, "--sim-model")
    assert code == 2
    assert err.strip() == "interp: error: the controller's build differs: MW 10 (the program needs 12)"


def test_clock_mismatch_exit_2(capsys, program, monkeypatch):
    monkeypatch.setattr(send, "open_transport", lambda args, machine: (DeviceModel(clock_hz=12_000_000), 115200))
    code, out, err = run(capsys, "send", program, "--sim-model")
    assert code == 2 and "clock is 12000000 Hz" in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("argv, word", [
    ([], "give one of --port DEVICE or --sim"),
    (["--port", "loop://", "--sim"], "got --port and --sim"),
    (["--sim-model", "--line-noise", "2"], "--line-noise 2"),
    (["--port", "loop://", "--line-noise", "0.1"], "--line-noise goes with --sim"),
    (["--port", "loop://", "--baud", "0"], "--baud 0"),
    (["--port"], "expected one argument"),
    (["--sim", "--baud", "9600"], "the link runs at 115200 .. 3000000 baud"),      # before any build
    (["--sim", "--baud", "3000000", "--pause-seconds", "-1"], "--pause-seconds -1"),
    (["--sim", "--steps", "/nonexistent/dir/s.csv"], "cannot write /nonexistent/dir/s.csv: no directory"),
    (["--sim", "--steps", "{program}"], "an output would overwrite the input"),
])
def test_usage_errors(capsys, program, argv, word):
    code, out, err = run(capsys, "send", program, *[a.format(program=program) for a in argv])
    assert code == 2 and word in err and len(err.strip().splitlines()) == 1 and out == ""


def test_gcode_error_like_interp_gcode(capsys, tmp_path):
    path = tmp_path / "bad.nc"
    path.write_text("G21\nG1 X1 F600\nG1 Q7 X2\n")
    code, out, err = run(capsys, "send", str(path), "--sim-model")
    code_g, _, err_g = run(capsys, "gcode", str(path), "--check")
    assert code == code_g == 2 and err == err_g and "line 3" in err


@pytest.mark.parametrize("text, word", [
    ("G21\nG1 X1 F600\nG1 Q7 X2\n", "line 3"),
    ("G21\nG1 X5000 F600\n", "line 2: X 5000 mm is beyond the X travel"),
    ("G21\nG38.2 Z-5 F100\nG1 Q7\n", "line 2: G38.2: give the simulated controller's probe a touch with --probe-at"),
])
def test_sim_reports_gcode_errors_before_the_simulator(capsys, tmp_path, monkeypatch, text, word):
    """--sim interprets and compiles the program from 0 (where a fresh simulated controller
    stands) before it builds and starts the simulator: a G-code error, a soft limit or a probe
    move is one line at once, and no transport is opened."""
    def no_transport(args, machine):
        raise AssertionError("the simulator was started")
    monkeypatch.setattr(send, "open_transport", no_transport)
    path = tmp_path / "bad.nc"
    path.write_text(text)
    code, out, err = run(capsys, "send", str(path), "--sim")
    assert code == 2 and word in err and len(err.strip().splitlines()) == 1 and out == "", err


def test_missing_file(capsys):
    code, _, err = run(capsys, "send", "/nonexistent/x.nc", "--sim-model")
    assert code == 2 and "cannot read /nonexistent/x.nc" in err


def test_port_cannot_open(capsys, program):
    for argv in (("send", program), ("status",)):
        code, _, err = run(capsys, *argv, "--port", "/dev/nonexistent-tty")
        assert code == 1 and err.startswith("interp: error: link: cannot open /dev/nonexistent-tty"), argv
        assert len(err.strip().splitlines()) == 1


@pytest.mark.skipif(sys.platform != "linux", reason="a pty")
def test_a_port_another_program_holds(capsys, program):
    """The port is opened exclusively: a second `interp send` or `status` on a port a sender holds
    is refused at once instead of mixing its frames into the running link."""
    import os

    import serial

    master, slave = os.openpty()
    name = os.ttyname(slave)
    holder = serial.serial_for_url(name, baudrate=115200, timeout=0.01, exclusive=True)
    try:
        for argv in (["send", program], ["status"]):
            code, out, err = run(capsys, *argv, "--port", name)
            assert code == 1 and err.strip() == (f"interp: error: link: cannot open {name}: another program has "
                                                 "it open (a sender, interp send or status, a terminal)"), err
    finally:
        holder.close()
        os.close(master)
        os.close(slave)


def test_port_without_controller(capsys, program):
    """loop:// echoes the host's own frames: no controller answers; one line after 2 s."""
    code, _, err = run(capsys, "send", program, "--port", "loop://")
    assert code == 1 and err.strip() == ("interp: error: link: no valid frame from the controller for 2 s "
                                         "(0 retransmissions)")


def test_status_sim_model(capsys):
    code, out, err = run(capsys, "status", "--sim-model")
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0] == "ID 1229870160 (0x494E5450)"
    assert "VERSION 0x20204401: protocol=1 record_bytes=68 w=32 pos_w=32" in lines
    assert any(x.startswith("STATUS 0x") and "state=IDLE" in x for x in lines)
    assert not any(x.startswith("CMD_DATA") for x in lines)
    assert lines[-1] == "machine position X0.000 Y0.000 Z0.000 mm"


def test_status_names_a_polarity_not_written_yet(capsys, tmp_path):
    machine = tmp_path / "m.toml"
    machine.write_text('[input]\ninvert = ["probe"]\n')
    code, out, err = run(capsys, "status", "--sim-model", "--machine", str(machine))
    assert code == 0, err
    assert f"INPUT_INVERT differs from the machine file's (0x10, {machine}): interp send, home and jog write " \
           "it when they connect" in out.splitlines()
    assert not any(line.startswith("OUTPUT_INVERT differs") for line in out.splitlines())


def test_status_usage(capsys):
    code, out, err = run(capsys, "status")
    assert code == 2 and "give one of --port DEVICE or --sim" in err


def test_empty_program(capsys, tmp_path):
    path = tmp_path / "empty.nc"
    path.write_text("(nothing to do)\n")
    code, out, err = run(capsys, "send", str(path), "--sim-model")
    assert code == 0 and out.startswith("sent 0 records (0 bytes)")
    assert "interp: warning: the program has no command to send" in err


def test_a_line_of_mdi_that_sets_an_offset_is_no_empty_program(capsys, tmp_path):
    """G10 L20 sends no record and still did something: no "no command to send" warning."""
    machine = tmp_path / "m.toml"
    machine.write_text('[gcode]\nparameter_file = "mill.var"\n')
    path = tmp_path / "zero.nc"
    path.write_text("G10 L20 P1 X1 Y2\n")                  # (the machine at 0: offsets -1, -2)
    code, out, err = run(capsys, "send", str(path), "--sim-model", "--machine", str(machine))
    assert code == 0 and out.startswith("sent 0 records (0 bytes)") and "no command to send" not in err, err
    assert "saved the offsets" in err


def test_typed_keys_drop_escape_sequences():
    """Arrow keys, PgUp / PgDn, F keys and Alt+key are not the '[' '5' '~' inside them."""
    from interp.commands.send import typed_keys

    assert typed_keys("!~]") == "!~]"
    assert typed_keys("\x1b[A\x1b[5~\x1b[6~\x1bOP\x1b[1;5C") == ""
    assert typed_keys("+\x1b[5~-\x1b!]\x1b") == "+-]"
    assert typed_keys("[\x1b[5") == "["                      # (a sequence cut off at the end of a read)


def test_key_tokens_one_per_key():
    """`interp jog`'s keys: an arrow, a page key, an F key is one token; Esc alone is one, also
    just before another sequence; the other characters one each."""
    from interp.commands.send import key_tokens

    assert key_tokens("a\x1b[A\x1b[5~q\x1b\x1bOP[\x1b[1;5C") == \
        ["a", "\x1b[A", "\x1b[5~", "q", "\x1b", "\x1bOP", "[", "\x1b[1;5C"]
    assert key_tokens("\x1b") == ["\x1b"] and key_tokens("\x1b[") == ["\x1b["] and key_tokens("") == []


def test_sim_baud_is_one_the_clock_makes():
    """--sim's default baud: 3 Mbaud from 12 MHz on; below, the fastest the clock's whole clocks a
    bit make within the receiver's tolerance (230400 at 1 MHz would be 4 clocks, 8.5 % fast)."""
    from interp.link.simlink import baud_problem, default_baud

    assert [default_baud(c) for c in (50_000_000, 12_000_000, 2_000_000, 1_000_000)] == \
        [3_000_000, 3_000_000, 500_000, 250_000]
    assert "8.5 % off" in baud_problem(230_400, 1_000_000)
    assert baud_problem(115_200, 2_000_000) is None                 # 17 clocks: 2.1 %, within 3 %
    assert "4 clocks a bit" in baud_problem(115_200, 200_000)
