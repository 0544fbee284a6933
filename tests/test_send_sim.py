# SPDX-License-Identifier: Apache-2.0
"""`interp send --sim`: the Verilator model of rtl/uart_controller.v behind SimLink
(interp/link/simlink.py, interp/simulation/native/board_main.cpp), driven bit by bit
through its UART pins in simulated time.

  * the bridge: frames through the real link RTL (HELLO, READ), a frame with a bad CRC
    is refused and not executed, its retransmission is executed once, a duplicate is
    acknowledged and not executed again (LINK_FRAMES / LINK_ERRORS, EXECUTED);
  * the input pins (set_pin): INPUTS, a limit switch's ERROR and ALARM;
  * homing (set_switch: a switch that follows the position): interp home's cycle on the RTL;
  * a tiny built-in program: `interp send --sim --steps A` equals `interp gcode --steps B`
    byte for byte; the end position registers equal the programmed end;
  * line noise 0.01 (most frames corrupted): the run completes and its steps CSV equals
    `interp gcode`'s byte for byte (the driver fills the queue before the run starts),
    the end position registers show the programmed end, nothing ran twice;
  * a record left half-sent by a dead session: IDLE, and the next run completes;
  * determinism: the same seed, the same frames and figures;
  * bad input: one line, no traceback;
  * a program pause (M0, M6) is released after --pause-seconds without a terminal;
  * Ctrl-X in a move: the RTL's hold slows the steps to rest before the abort, and the
    position registers count the steps that went out;
  * feed override keys in a move: slower steps, the same path step by step;
  * Ctrl-X twice at speed: ERROR 19, the position registers count the steps that went out;
  * a short corpus program that starts with an event (slow; skipped without
    ../shared/gcode), without noise and at line noise 0.01: the steps CSV equals
    `interp gcode`'s byte for byte.

The machine file of these tests runs the controller at 12 MHz (the lowest clock for
3 Mbaud: the link needs 4 clocks a bit) so that the simulated seconds cost few cycles.
"""
import os
import re
import subprocess

import pytest

from interp.cli import main
from interp.link import protocol as p
from interp.link.driver import POSITION, signed32
from interp.link.simlink import SimLink, SimLinkError
from interp.simulation.runner import RTL
from interp.testing.seeds import seeded_random

pytestmark = pytest.mark.skipif(not (RTL / "uart_controller.v").is_file(),
                                reason="rtl/uart_controller.v is not in this tree")

CORPUS = os.path.join(os.path.dirname(__file__), "..", "..", "shared", "gcode")
MACHINE = """[controller]
clock_hz = 12_000_000
"""
# starts with a move long enough (~40 ms) for the second record to arrive over the link
PROGRAM = """G21 G90
G1 X1 Y0.5 F3000
G1 X1.5 Y1.2
G0 X0.2 Y0
M2
"""
PROGRAM_END = (20, 0, 0)        # steps at 100 steps/mm


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("send_sim")
    (folder / "machine.toml").write_text(MACHINE)
    (folder / "tiny.nc").write_text(PROGRAM)
    return folder


@pytest.fixture(scope="module")
def gcode_steps(files):
    """`interp gcode --steps` of the tiny program (the reference)."""
    out = files / "gcode.csv"
    assert main(["gcode", str(files / "tiny.nc"), "--machine", str(files / "machine.toml"), "--steps", str(out)]) == 0
    return out.read_text()


def exchange(link, parser, frame: bytes, seconds: float = 0.001):
    link.write(frame)
    link.timeout = seconds
    return parser.feed(link.read(256))


def register(link, parser, address: int) -> int:
    (reply,) = exchange(link, parser, p.encode_frame(p.READ, 0, address.to_bytes(2, "little")))
    assert reply.type == p.REPLY and int.from_bytes(reply.payload[:2], "little") == address
    return int.from_bytes(reply.payload[2:6], "little")


def test_bridge_hello_and_registers(files):
    with SimLink(machine=files / "machine.toml") as link:
        parser = p.FrameParser()
        (ack,) = exchange(link, parser, p.encode_frame(p.HELLO, 7, b""))
        assert ack.type == p.ACK and ack.seq == 0
        assert register(link, parser, 0x00) == 0x494E5450           # ID "INTP"
        assert register(link, parser, 0x10) == 12_000_000           # CLOCK_HZ
        assert 0 < link.now() < 0.01
        result = link.close()
    assert result["chars_dropped"] == 0 and result["flipped_to_device"] == 0
    assert result["cycles"] == round(result["seconds"] * 12_000_000)


def test_corrupted_frame_is_not_executed_and_a_duplicate_not_twice(files):
    """A WRITE with a bad CRC: NAK 1, not executed; the retransmission: executed (ACK, E = 1);
    the same frame again: a duplicate, acknowledged, not executed.  A DATA frame (a zero dwell
    record) sent twice runs once (EXECUTED)."""
    from interp.link.records import encode

    with SimLink(machine=files / "machine.toml") as link:
        parser = p.FrameParser()
        exchange(link, parser, p.encode_frame(p.HELLO, 0, b""))
        frames0 = register(link, parser, 0x6C)
        write = p.encode_frame(p.WRITE, 0, bytes([0x44, 0]) + (150).to_bytes(4, "little"))   # OVERRIDE 150
        bad = bytearray(write)
        bad[-1] ^= 0x10
        (nak,) = exchange(link, parser, bytes(bad))
        assert nak.type == p.NAK and nak.payload[0] == p.NAK_CRC
        assert register(link, parser, 0x44) == 100                  # not executed
        (ack,) = exchange(link, parser, write)
        assert ack.type == p.ACK and ack.seq == 1
        assert register(link, parser, 0x44) == 150
        (ack,) = exchange(link, parser, p.encode_frame(p.WRITE, 0, bytes([0x44, 0]) + (120).to_bytes(4, "little")))
        assert ack.type == p.ACK and ack.seq == 1                   # seq 0 again: a duplicate
        assert register(link, parser, 0x44) == 150                  # not executed again
        record = encode({"kind": 4})                                # DWELL of 0 cycles
        data = p.encode_frame(p.DATA, 1, record[:60])
        for _ in range(2):
            (ack,) = exchange(link, parser, data)
            assert ack.type == p.ACK and ack.seq == 2
        (ack,) = exchange(link, parser, p.encode_frame(p.DATA, 2, record[60:]), 0.002)
        assert ack.type == p.ACK and ack.seq == 3
        executed = register(link, parser, 0x78)
        frames = register(link, parser, 0x6C)
        errors = register(link, parser, 0x70)
        link.close()
    assert executed == 1
    # frames executed after the READ of frames0 (which counts itself): READ, WRITE, READ, READ,
    # DATA, DATA, READ, READ = 8 (the bad WRITE is an error, the two duplicates are not executed)
    assert frames & 0xFFFF == frames0 + 8
    assert frames >> 16 == 2
    assert errors & 0xFFFF == 1


def test_input_pins(files):
    """set_pin drives the model's inputs: INPUTS shows the pins, a limit switch latches ERROR 17
    with the axes that tripped and ALARM."""
    with SimLink(machine=files / "machine.toml") as link:
        parser = p.FrameParser()
        exchange(link, parser, p.encode_frame(p.HELLO, 0, b""))
        assert register(link, parser, 0x1C) & 0xFF == 0              # ERROR
        link.set_pin("limit", 0b101)
        link.set_pin("probe", 1)
        link.sleep(0.0001)
        assert register(link, parser, 0x3C) & 0x1F == 0b11010         # INPUTS: probe, limit z, limit x
        assert register(link, parser, 0x1C) & 0x7FF == 0b101 << 8 | 17  # limit switch, x and z
        assert register(link, parser, 0x18) & 0x7 == 4                # ALARM
        link.set_pin("limit", 0)
        link.set_pin("probe", 0)
        link.set_pin("estop", 1)
        link.sleep(0.0001)
        assert register(link, parser, 0x3C) & 0x1F == 0b00001         # INPUTS: estop
        with pytest.raises(SimLinkError, match="unknown pin"):
            link.set_pin("spindle", 1)


def test_polarity_on_the_rtl(files):
    """apply_pin_settings through the link on the RTL: OUTPUT_INVERT, INPUT_FILTER and SPINDLE_PERIOD take the machine
    file's values (a name left out is not written); an e-stop pin that reads active only under the new INPUT_INVERT (a real
    e-stop) latches ERROR 16, which the write's clear cannot clear while it is active."""
    from interp.gcode.machine import load_machine
    from interp.link.driver import Driver, apply_pin_settings

    with SimLink(machine=load_machine(str(files / "machine.toml"))) as link:
        driver = Driver(link, baud=link.baud)
        driver.connect()
        apply_pin_settings(driver, {"OUTPUT_INVERT": 0x1FFFF})
        assert driver.read_register("OUTPUT_INVERT") == 0xFFFF and driver.read_register("ERROR") == 0
        apply_pin_settings(driver, {"INPUT_INVERT": 1, "INPUT_FILTER": 0x0F << 16 | 40, "OUTPUT_INVERT": 0,
                                    "SPINDLE_PERIOD": 600})
        assert driver.read_register("OUTPUT_INVERT") == 0 and driver.read_register("SPINDLE_PERIOD") == 600
        assert driver.read_register("INPUT_FILTER") == 0x0F0028
        assert driver.read_register("ERROR") & 0xFF == 16       # the e-stop pin is low: active low, pressed
        link.set_pin("estop", 1)
        driver.write_register("CONTROL", p.CONTROL_CLEAR)
        assert driver.read_register("ERROR") == 0 and driver.read_register("INPUTS") == 0


class ResetAt:
    """The SimLink, with the controller's reset pressed once at `at` simulated seconds (None: not yet)."""

    def __init__(self, link, at):
        self.link, self.at, self.done = link, at, False

    def _maybe(self):
        if not self.done and self.at is not None and self.link.now() >= self.at:
            self.done = True
            self.link.set_pin("rst", 1)
            self.link.sleep(2e-6)
            self.link.set_pin("rst", 0)

    def read(self, size=1):
        self._maybe()
        return self.link.read(size)

    @property
    def in_waiting(self):
        self._maybe()
        return self.link.in_waiting

    @property
    def timeout(self):
        return self.link.timeout

    @timeout.setter
    def timeout(self, value):
        self.link.timeout = value

    def __getattr__(self, name):
        return getattr(self.link, name)


@pytest.mark.parametrize("at", [0.005, 0.06])
def test_a_reset_during_a_run_on_the_rtl(files, at):
    """The board's reset pressed during a run (while the records stream; after they are all in,
    with moves still to run): the driver stops with one LinkError that says so, instead of
    waiting for records the controller lost."""
    from interp.commands.gcode import compile_text
    from interp.commands.send import compile_build
    from interp.gcode.machine import load_machine
    from interp.link.driver import Driver, LinkError, configure, run_program
    from interp.link.records import encode_program

    machine = load_machine(str(files / "machine.toml"))
    _, compiled = compile_text("G21 G91\n" + "G1 X0.3 F3000\nG1 Y0.3\nG1 X-0.3\nG1 Y-0.3\n" * 10, machine)
    with SimLink(machine=machine) as link:
        port = ResetAt(link, None)
        driver = Driver(port, baud=link.baud)
        driver.connect()
        configure(driver, machine.timing(), compiled.settings, compiled)
        at = port.at = link.now() + at                  # (seconds into the run)
        with pytest.raises(LinkError, match="reset"):
            run_program(driver, encode_program(compiled.commands, compile_build(),
                                                 codes=compiled), len(compiled.commands),
                        max_seconds=5.0)
        assert port.done and link.now() < at + 1.0


def test_homing_on_the_rtl(files, tmp_path):
    """interp home's cycle through the controller's RTL: a switch that follows the pulses
    counted at the step pins (0.37 mm below where the machine powered up) stops the seek and
    the slow approach on its edge, the pull-offs move off it after CONTROL.clear, and the
    POS_X write over the link puts the axis at machine -1 mm (min_mm), the switch a pull-off
    (0.2 mm) beyond; STATUS.position_set has x, and the pins moved exactly to the switch and
    back."""
    from interp.commands import home
    from interp.gcode.machine import load_machine
    from interp.link.driver import Driver

    path = tmp_path / "home.toml"
    path.write_text(MACHINE + '[axis.x]\nmin_mm = -1\nmax_mm = 1\nhome = "min"\n'
                    "[homing]\nseek_mm_min = 600\nlocate_mm_min = 60\npull_off_mm = 0.2\n")
    machine = load_machine(str(path))
    with SimLink(machine=machine) as link:
        link.set_switch(0, "min", -37)
        driver = Driver(link, baud=link.baud)
        driver.connect()
        assert home.home_axis(driver, machine, 0) == (-1.2, -1.0)
        assert [signed32(driver.read_register(name)) for name in POSITION] == [-100, 0, 0]
        assert driver.read_register("STATUS") >> 16 == 0b001 and driver.read_register("ERROR") == 0
        result = link.close()
    assert result["position"] == [-17, 0, 0]                   # the switch, then a pull-off of 20 steps


def test_home_sim(files, tmp_path, capsys):
    """`interp home --sim`: the simulated machine powers up two pull-offs (0.4 mm, 40 steps)
    from X's switch, at its home end (min); the cycle through the board's RTL sets X at its
    travel end, -1 mm, the switch a pull-off beyond, and leaves Y and Z alone."""
    path = tmp_path / "home.toml"
    path.write_text(MACHINE + '[axis.x]\nmin_mm = -1\nmax_mm = 1\nhome = "min"\n'
                    "[homing]\nseek_mm_min = 600\nlocate_mm_min = 60\npull_off_mm = 0.2\n")
    assert main(["home", "--sim", "--machine", str(path)]) == 0
    out, err = capsys.readouterr()
    lines = out.splitlines()
    assert lines[0] == "homed X: switch at -1.200 mm, now at -1.000 mm", out
    assert lines[1].startswith("machine position X-1.000 Y0.000 Z0.000 mm ("), out
    assert "the simulated machine powers up 0.400 mm from each limit switch" in err, err


PROBE = """G21 G90
G38.2 Z-5 F300
G91 G38.4 Z1 F300
(debug, lost at #5063)
G0 Z1
G90 G38.3 X-3 F600
M2
"""


def end_steps(out: str) -> tuple[int, int, int]:
    return tuple(int(v) for v in re.search(r"end \((-?\d+), (-?\d+), (-?\d+)\) steps", out).groups())


def test_probe_on_the_sim(files, capsys):
    """`interp send --sim --probe-at Z-1.5`: the simulated probe touches at machine Z -1.5 mm
    (150 steps), the G38.2 move holds there and stops a few steps past the touch; the G38.4
    backs up from there until the probe loses contact (PROBE_Z at 149 steps) and stops a few
    steps further, the next move starts from where it stopped; the G38.3 finds no touch on X
    and runs to its end.  A plate below the G38.2 move's end: one line, exit status 1.  No
    touch given: refused."""
    program = files / "probe.nc"
    program.write_text(PROBE)
    machine = str(files / "machine.toml")
    assert main(["send", str(program), "--sim", "--machine", machine, "--probe-at", "Z-1.5"]) == 0
    out, err = capsys.readouterr()
    x, y, z = end_steps(out)
    assert (x, y) == (-300, 0) and -149 + 100 < z <= -149 + 100 + 5, out
    assert "interp: message: line 4: lost at -1.490000" in err.splitlines(), err
    assert main(["send", str(program), "--sim", "--machine", machine, "--probe-at", "Z-6"]) == 1
    out, err = capsys.readouterr()
    assert err.strip().splitlines()[-1] == ("interp: error: line 2: G38.2: the probe did not touch before the end "
                                            "of the move"), err
    assert main(["send", str(program), "--sim", "--machine", machine]) == 2
    assert "G38.2: give the simulated controller's probe a touch with --probe-at" in capsys.readouterr().err


def test_send_sim_equals_gcode(files, gcode_steps, capsys):
    steps = files / "send.csv"
    assert main(["send", str(files / "tiny.nc"), "--sim", "--steps", str(steps),
                 "--machine", str(files / "machine.toml")]) == 0
    out = capsys.readouterr().out
    assert f"end {PROGRAM_END} steps" in out, out
    assert steps.read_text() == gcode_steps


RESTART = """G21 G90
G0 Z1
M3 S1000
M8
G0 X0.5 Y0.2
G1 Z-0.3 F600
G1 X1 F3000
G1 Y0.6
G0 Z1
M5 M9
M2
"""


def test_start_line_on_the_rtl(files, capsys):
    """`interp send --sim --start-line 8`: the spindle and flood the lines
    before it switched on, the approach (up to Z1, across, down at line 6's F600 to Z-0.3),
    then line 8 on: the steps equal `interp gcode --start-line 8`'s, the end the program's."""
    program = files / "restart.nc"
    program.write_text(RESTART)
    machine = str(files / "machine.toml")
    expected, steps = files / "restart_gcode.csv", files / "restart_send.csv"
    assert main(["gcode", str(program), "--machine", machine, "--start-line", "8", "--steps", str(expected)]) == 0
    capsys.readouterr()
    assert main(["send", str(program), "--sim", "--machine", machine, "--start-line", "8", "--steps", str(steps)]) == 0
    out, err = capsys.readouterr()
    assert err.startswith("interp: starting at line 8: spindle M3 S1000; coolant flood; approach in 3 moves to "
                          "X1 Y0.2 Z-0.3 (machine mm), the last at F600"), err
    assert end_steps(out) == (100, 60, 100), out
    assert steps.read_text() == expected.read_text()


LASER = """G21 G90
M3 S200
G1 X1 Y0.5 F3000
G1 X1.5 S800
G1 X2 S400
G0 X0.5 Y0
G1 X1 S600
M5
M2
"""


def test_laser_mode_on_the_rtl(files, capsys):
    """Laser mode (spindle.laser): the S changes run inline, without a stop, and the G0 with the
    beam off; through the link into the board's RTL the steps CSV equals `interp gcode`'s and
    the run takes less time than without laser mode (which stops at every S)."""
    laser = files / "laser.toml"
    laser.write_text(MACHINE + "[spindle]\nlaser = true\nmax_s = 1000\n")
    program = files / "laser.nc"
    program.write_text(LASER)
    runs = {}
    for name, machine in (("laser", laser), ("spindle", files / "machine.toml")):
        reference, steps = files / f"{name}_gcode.csv", files / f"{name}_send.csv"
        assert main(["gcode", str(program), "--machine", str(machine), "--steps", str(reference)]) == 0
        assert main(["send", str(program), "--sim", "--steps", str(steps), "--machine", str(machine)]) == 0
        assert steps.read_text() == reference.read_text(), name
        runs[name] = int(steps.read_text().splitlines()[-1].split(",")[0])     # the last step's cycle
    capsys.readouterr()
    assert runs["laser"] < runs["spindle"], runs


def test_program_pause_is_released(files, capsys):
    """M0 and M6 make the controller hold by itself; without a terminal the driver releases each
    pause after --pause-seconds (here 0.01 s of machine time) and the program ends where it should."""
    program = files / "pause.nc"
    program.write_text("G21 G90\nG1 X0.5 F3000\nM0\nG1 X1\nT2 M6\nG1 X0.3\nM2\n")
    assert main(["send", str(program), "--sim", "--pause-seconds", "0.01",
                 "--machine", str(files / "machine.toml")]) == 0
    captured = capsys.readouterr()
    assert "end (30, 0, 0) steps" in captured.out, captured
    assert captured.err.count("program paused at line") == 2, captured.err
    assert "line 3: resuming after 0.01 s" in captured.err, captured.err
    assert "line 5, tool change to T2: resuming after 0.01 s" in captured.err, captured.err


def test_pauses_in_a_row_each_hold_once(files, capsys):
    """M0, M0, T2 M6, G4, M1 with no move between some of them, on a noisy line: each pause holds
    the controller once, in order, for --pause-seconds (against a run with 0), and each
    message names its own line (the dwell waits while held)
    (a poll round from before a release no longer counts as a new pause, and the pause is
    found from EXECUTED read at rest)."""
    program = files / "pauses.nc"
    program.write_text("G21\nG1 X0.5 F600\nM0\nM0\nG1 X1\nT2 M6\nG4 P0.02\nM1\nG1 X0.2\nM2\n")
    seconds = []
    for pause in ("0.1", "0"):
        assert main(["send", str(program), "--sim", "--pause-seconds", pause, "--line-noise", "0.01",
                     "--machine", str(files / "machine.toml")]) == 0
        captured = capsys.readouterr()
        lines = [int(re.match(r"\d+", w).group()) for w in captured.err.split("program paused at line ")[1:]]
        assert lines == [3, 4, 6, 8], captured.err
        assert "end (20, 0, 0) steps" in captured.out
        seconds.append(float(captured.out.split(" s link time")[0].split(" in ")[-1]))
    assert seconds[0] - seconds[1] > 4 * 0.1 * 0.9, seconds         # four pauses, each held 0.1 s


def run_driver(files, steps, noise: float, seed: int = 1, before=None, keys=None, override=None,
               program: str = "tiny.nc"):
    """The host driver's run through SimLink; (outcome, registers after the run, link result, records).
    before(link, stream): what an earlier session did on the link; keys(link): the keys typed
    since the last call (run_program's keys)."""
    from interp.commands.gcode import compile_text, read_program
    from interp.commands.send import compile_build, encode_program
    from interp.gcode.machine import load_machine
    from interp.link.driver import Driver, check_controller, configure, run_program

    machine = load_machine(str(files / "machine.toml"))
    _, compiled = compile_text(read_program(str(files / program)), machine)
    stream = encode_program(compiled.commands, compile_build(), codes=compiled)
    link = SimLink(steps=steps, line_noise=noise, seed=seed, machine=machine)
    if before is not None:
        before(link, stream)
    driver = Driver(link, baud=link.baud)
    driver.connect()
    check_controller(driver, compile_build(), machine.clock_hz)
    configure(driver, machine.timing(), compiled.settings, compiled)
    outcome = run_program(driver, stream, len(compiled.commands), override=override,
                          keys=None if keys is None else lambda: keys(link))
    registers = {name: driver.read_register(name) for name in ("POS_X", "POS_Y", "POS_Z", "EXECUTED",
                                                                "LINK_FRAMES", "LINK_ERRORS", "ERROR", "STATUS")}
    return outcome, registers, link.close(), compiled


def test_line_noise_completes_with_the_same_steps(files, gcode_steps):
    """--line-noise 0.01: the steps CSV is the gcode run's, cycles included (the program fits
    the queue, which the driver fills before the run starts); the registers show the
    programmed end, every record executed once, frames repeated.  (600-900 frames are
    refused per run; CRC-16 passes about one corrupted frame in 270,000, so about one seed
    in 300 fails here for that reason: docs/link-protocol.md.)"""
    steps = files / "noise.csv"
    _, seed = seeded_random("line noise 0.01")
    outcome, regs, result, compiled = run_driver(files, steps, 0.01, seed=seed)
    assert outcome.status == "done", outcome
    assert result["flipped_to_device"] > 0 and result["flipped_from_device"] > 0
    assert steps.read_text() == gcode_steps
    end = tuple(signed32(regs[n]) for n in POSITION)
    assert end == tuple(compiled.end_steps) == PROGRAM_END
    assert tuple(result["position"]) == PROGRAM_END
    assert outcome.executed == len(compiled.commands)
    assert regs["LINK_FRAMES"] >> 16 > 0 or regs["LINK_ERRORS"] & 0xFFFF > 0    # the noise did hit


def test_a_half_sent_record_does_not_block_the_next_run(files, gcode_steps):
    """A session that died in the middle of a record left its first bytes in the queue: the
    controller is IDLE and not busy (nothing it could run), so the next run flushes them
    (CONTROL.abort) and completes with the same steps as `interp gcode` (had they stayed,
    every record after them would be misaligned: ERROR 18)."""
    from interp.link.driver import Driver

    def dead_session(link, stream):
        driver = Driver(link, baud=link.baud)
        driver.connect()
        driver.start_stream(stream[:5])                 # a record cut after 5 bytes
        while not driver.stream_done():
            driver.pump()
        status = driver.read_register("STATUS")
        assert status & 0xFF0F == p.IDLE, f"STATUS {status:#x}"    # (the 5 bytes wait in the unpacker)

    steps = files / "after_half.csv"
    outcome, regs, _, compiled = run_driver(files, steps, 0.0, before=dead_session)
    assert outcome.status == "done" and outcome.executed == len(compiled.commands), outcome
    assert steps.read_text() == gcode_steps
    assert tuple(signed32(regs[n]) for n in POSITION) == PROGRAM_END


def test_stop_key_decelerates_then_aborts(files):
    """Ctrl-X in the first move (50 mm/s): the RTL's feed hold brings the machine to rest on the
    path before the abort, so the steps slow down to the last one (no stop at speed), the
    position registers count exactly the steps that went out, and the outcome carries no
    lost-steps warning."""
    steps = files / "stopped.csv"
    start, typed = [], []

    def keys(link):
        start.append(start[0] if start else link.now())
        if not typed and link.now() > start[0] + 0.015:      # well inside the first move (at cruise)
            typed.append(link.now())
            return "\x18"
        return ""

    outcome, regs, _, compiled = run_driver(files, steps, 0.0, keys=keys)
    assert typed and outcome.status == "aborted" and outcome.message == "", outcome
    rows = [tuple(int(v) for v in line.split(",")) for line in steps.read_text().splitlines()[1:]]
    position = tuple(signed32(regs[n]) for n in POSITION)
    assert position == tuple(sum(r[k] for r in rows) for k in (1, 2, 3))
    assert 0 < position[0] < 100, (typed, position, outcome)          # stopped inside the first move
    gaps = [b[0] - a[0] for a, b in zip(rows, rows[1:])]
    cruise = min(gaps)
    after = gaps[gaps.index(cruise):]                                 # from the fastest step on
    assert len(after) >= 4 and after == sorted(after), after          # slowing down to the last
    assert gaps[-1] > 2 * cruise, (cruise, gaps[-5:])


def test_feed_override_keys_change_the_pace_not_the_path(files):
    """A 4 mm move at 10 mm/s (12,000 clocks a step): '-' five times at 0.1 s (50 %), '0' at
    0.3 s (100 %): the RTL slows the steps to twice their interval and speeds them up again at
    its acceleration, and not one step changes: the same steps in the same order as
    `interp gcode`'s, the programmed end, every record executed once."""
    from interp.link.driver import FeedOverride

    (files / "slow.nc").write_text("G21 G90\nG1 X4 F600\nM2\n")
    reference = files / "slow_gcode.csv"
    assert main(["gcode", str(files / "slow.nc"), "--machine", str(files / "machine.toml"),
                 "--steps", str(reference)]) == 0
    steps = files / "override.csv"
    start, typed = [], []

    def keys(link):
        start.append(start[0] if start else link.now())
        for at, key in ((0.1, "-----"), (0.3, "0")):
            if len(typed) == [0.1, 0.3].index(at) and link.now() > start[0] + at:
                typed.append(key)
                return key
        return ""

    held = FeedOverride()
    outcome, regs, _, compiled = run_driver(files, steps, 0.0, keys=keys, override=held, program="slow.nc")
    assert outcome.status == "done" and outcome.executed == len(compiled.commands), outcome
    assert typed == ["-----", "0"] and held.percent == 100
    rows = [tuple(int(v) for v in line.split(",")) for line in steps.read_text().splitlines()[1:]]
    alone = [tuple(int(v) for v in line.split(",")) for line in reference.read_text().splitlines()[1:]]
    assert len(rows) == 400 and [r[1:] for r in rows] == [r[1:] for r in alone]     # the path, step by step
    assert tuple(signed32(regs[n]) for n in POSITION) == (400, 0, 0)
    gaps = [b[0] - a[0] for a, b in zip(rows, rows[1:])]
    plain = [b[0] - a[0] for a, b in zip(alone, alone[1:])]
    cruise = min(plain)                                 # 12,000 clocks: 10 mm/s at 12 MHz
    assert 11_500 < cruise <= 12_000 and min(gaps) == cruise, (cruise, min(gaps))
    assert 1.95 * cruise < max(gaps[50:-50]) <= 2 * cruise + 1, max(gaps[50:-50])      # 50 %
    slow = [g for g in gaps if g > 1.95 * cruise]
    assert 60 < len(slow) < 120, len(slow)              # 0.2 s at 5 mm/s: about 100 steps
    assert rows[-1][0] - alone[-1][0] > 0.08 * 12e6, "about 0.1 s longer than at 100 %"


def test_stop_key_twice_aborts_at_speed_with_error_19(files):
    """Ctrl-X twice in the first move: the abort cuts the steps at speed, so the RTL latches
    ERROR 19 (ALARM, as Grbl's alarm 3) and the outcome says the motors may have lost steps;
    the position registers still count exactly the steps that went out."""
    steps = files / "cut.csv"
    start, typed = [], []

    def keys(link):
        start.append(start[0] if start else link.now())
        if not typed and link.now() > start[0] + 0.015:
            typed.append(link.now())
            return "\x18\x18"
        return ""

    outcome, regs, _, _ = run_driver(files, steps, 0.0, keys=keys)
    assert typed and outcome.status == "aborted" and "may have lost steps" in outcome.message, outcome
    assert regs["ERROR"] & 0xFF == 19 and regs["STATUS"] & 7 == p.ALARM, regs
    rows = [tuple(int(v) for v in line.split(",")) for line in steps.read_text().splitlines()[1:]]
    position = tuple(signed32(regs[n]) for n in POSITION)
    assert position == tuple(sum(r[k] for r in rows) for k in (1, 2, 3)) and 0 < position[0] < 100


def test_same_seed_same_run(files):
    """Lockstep: a run depends on the seed only (not on the host's speed)."""
    runs = []
    _, seed = seeded_random("line noise 0.05")
    for _ in range(2):
        with SimLink(machine=files / "machine.toml", line_noise=0.05, seed=seed, timeout=0.0005) as link:
            parser = p.FrameParser()
            got = []
            for n in range(5):
                got += [str(f) for f in exchange(link, parser, p.encode_frame(p.HELLO, n, b""), 0.0005)]
            runs.append((got, link.close()))
    assert runs[0][0] == runs[1][0]
    assert {k: v for k, v in runs[0][1].items() if "wall" not in k and "per_second" not in k} == \
        {k: v for k, v in runs[1][1].items() if "wall" not in k and "per_second" not in k}


def test_bad_input_one_line(files, capsys):
    with pytest.raises(SimLinkError, match="line noise"):
        SimLink(machine=files / "machine.toml", line_noise=1.5)
    with pytest.raises(SimLinkError, match="baud"):
        SimLink(machine=files / "machine.toml", baud=7_000_000)
    assert main(["send", str(files / "tiny.nc"), "--sim", "--line-noise", "-1"]) != 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "line-noise" in err[0] and "Traceback" not in err[0]
    # a simulator that stopped: SimLinkError with its one line, close() still answers
    link = SimLink(machine=files / "machine.toml")
    link._proc.stdin.write("zz\n")
    link._proc.stdin.flush()
    with pytest.raises(SimLinkError, match='status 2.*unknown request "zz"'):
        link.read(1)
    assert link.close()["stopped"] is True
    # the harness itself: a bad request ends it with one line, status 2
    from interp.simulation.native.build import board_executable

    exe = board_executable({"CLK_HZ": 12_000_000, "BAUD": 3_000_000})
    proc = subprocess.run([str(exe), "--clock-hz", "12000000", "--baud", "3000000"], input="w 1\n",
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2 and proc.stderr.strip() == "w: odd number of hex digits"
    proc = subprocess.run([str(exe), "--clock-hz", "12000000"], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1


@pytest.mark.slow
@pytest.mark.skipif(not os.path.isdir(CORPUS), reason="no G-code corpus beside the repository (../shared/gcode)")
def test_corpus_program_steps_equal_gcode(files, tmp_path, capsys):
    """A short corpus program (ugs_window.nc: 24 records, 11 s of machine time, starting with
    an event, M3) streamed through the simulated link, without noise and at line noise 0.01
    (seeded): both steps CSVs equal `interp gcode`'s byte for byte, and both runs end at the
    programmed position."""
    program = os.path.join(CORPUS, "ugs_window.nc")
    machine = str(files / "machine.toml")
    reference = tmp_path / "gcode.csv"
    assert main(["gcode", program, "--machine", machine, "--steps", str(reference)]) == 0
    _, seed = seeded_random("corpus program at line noise 0.01")
    for name, noise in (("clean", []), ("noisy", ["--line-noise", "0.01", "--seed", str(seed)])):
        sent = tmp_path / f"{name}.csv"
        assert main(["send", program, "--sim", "--machine", machine, "--steps", str(sent), *noise]) == 0
        assert "end (0, 0, 1000) steps" in capsys.readouterr().out
        assert sent.read_text() == reference.read_text(), name
