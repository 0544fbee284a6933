# SPDX-License-Identifier: Apache-2.0
"""`interp send FILE`: a G-code program to the board controller over its UART link
(docs/host-driver.md).

  interp send FILE.nc --port DEVICE [--baud B] [--machine FILE.toml]
  interp send FILE.nc --sim [--steps FILE] [--line-noise P] [--seed S] [--machine FILE.toml]
  (both: [--pause-seconds S], how long a program pause lasts without a terminal)

The program is compiled as `interp gcode` compiles it (interp.commands.gcode.compile_text),
encoded into records (interp.link.records) and streamed by the driver (interp.link.driver).
--port takes a device or a pyserial URL (loop://, socket://HOST:PORT); --sim runs the
Verilator model of rtl/uart_controller.v (interp.link.simlink).  Keys while it runs
(stdin a terminal): '!' feed hold, '~' resume, Ctrl-X abort (after a feed hold has brought
the machine to rest; twice: at once), feed override '+' '-' (10 %), '>' '<' (1 %), '1' .. '9'
(10 .. 90 %), '0' (100 %), spindle override ']' '[' (10 %), '}' '{' (1 %), '\\' (100 %).  Exit status: 0 done,
1 machine or link error (or an abort), 2 usage or G-code error.
"""
from __future__ import annotations

import dataclasses
import math
import re
import shlex
import sys

from ..cores import UsageError
from ..gcode import compile as gc
from ..gcode.machine import AXES, Machine, load_machine
from ..gcode.parameter_file import check_lengths, check_writable, describe, write_parameters
from ..link import protocol as p
from ..gcode.compile import compile_program
from ..gcode.errors import GcodeError
from ..gcode.interpreter import PROBE_AWAY, PROBE_FAIL
from ..gcode.moves import ProbeResult
from ..link.driver import (Driver, FeedOverride, LinkError, MachineError, MismatchError, SpindleOverride,
                           apply_pin_settings, check_controller, check_idle, configure, read_position, run_program,
                           signed32)
from ..link.records import DEFAULT_BUILD, Build, encode_program
from ..models.motion import to_machine
from ..simulation.output import check_outputs
from . import gcode as gcode_command          # (its interpret_program looked up at each call)
from .gcode import read_program, saved_parameters

DEFAULT_BAUD = 115200
CURVE = 3
KEYS_HELP = ("keys: ! hold, ~ resume, Ctrl-X abort (twice: at once), feed override + - > < 1..9 0, "
             "spindle override ] [ } { \\")


def compile_build() -> Build:
    """The build the compiler's commands are for (records.Build's defaults)."""
    return DEFAULT_BUILD


# ---------------- the transports (tests replace open_transport) ----------------

def open_transport(args, machine: Machine):
    """(transport, baud) for --port, --sim or the hidden --sim-model."""
    if args.port:
        try:
            import serial
        except ImportError:
            raise RuntimeError("pyserial is not installed (pip install pyserial)") from None
        try:
            # exclusive: a second sender (or `interp status`) on the same port would mix its frames in
            return serial.serial_for_url(args.port, baudrate=args.baud, timeout=0.01, exclusive=True), args.baud
        except (serial.SerialException, ValueError) as err:
            cause = err.__context__
            text = cause.strerror if isinstance(cause, OSError) and cause.strerror else str(err)
            if isinstance(cause, BlockingIOError) or "exclusively lock" in str(err):
                text = "another program has it open (a sender, interp send or status, a terminal)"
            raise LinkError(f"cannot open {args.port}: {text}") from None
    seed = 1 if getattr(args, "seed", None) is None else args.seed        # (send's --seed only)
    if getattr(args, "sim_model", False):
        from ..link.devicemodel import DeviceModel

        baud = args.baud or DEFAULT_BAUD
        return DeviceModel(clock_hz=round(machine.clock_hz), baud=baud, line_noise=args.line_noise or 0.0,
                           seed=seed, records_per_second=args.sim_model_rate,
                           fail_at=args.sim_model_fail), baud
    from ..link.simlink import SimLink, baud_problem, default_baud

    clock = round(machine.clock_hz)
    baud = args.baud or default_baud(clock)
    problem = baud_problem(baud, clock)
    if problem:                     # before the simulator is built
        raise UsageError(f"--sim: {problem}" + ("" if args.baud else " (give --baud)"))
    link = SimLink(steps=getattr(args, "steps", None), line_noise=getattr(args, "line_noise", None) or 0.0,
                   seed=seed, machine=machine, baud=baud)
    return link, link.baud


def open_or_report(args, machine: Machine):
    """open_transport's (transport, baud), or None after one line on stderr when the link
    cannot be opened (`interp send`, `status`, `home`: exit status 1)."""
    try:
        return open_transport(args, machine)
    except LinkError as err:
        print(f"interp: error: link: {err}", file=sys.stderr)
        return None


def switch_off(driver: Driver) -> None:
    """A program stopped between its pieces (an (ABORT, ...) or a failed probe after a
    probe move): CONTROL.abort at rest switches the spindle and coolant off, as LinuxCNC's
    abort does, and latches no error."""
    try:
        driver.write_register("CONTROL", p.CONTROL_ABORT | p.CONTROL_ENABLE)
    except LinkError as err:
        print(f"interp: warning: switching the spindle and coolant off failed ({err})", file=sys.stderr)


def interrupted(driver: Driver | None) -> int:
    """Ctrl-C in `interp home` or `jog`: nothing more is sent and the controller is told to
    abort (at once: the motors may lose steps, as a second Ctrl-X); one line, exit status 1."""
    told = ""
    if driver is not None:
        try:
            driver.drop_stream()
            driver.write_register("CONTROL", p.CONTROL_ABORT | p.CONTROL_ENABLE)
            told = ": the controller was told to abort"
        except LinkError as err:
            told = f": telling the controller to abort failed ({err})"
    print(f"interp: interrupted{told}", file=sys.stderr)
    return 1


def check_link_args(args) -> None:
    chosen = [name for name, on in (("--port", args.port), ("--sim", args.sim),
                                    ("--sim-model", getattr(args, "sim_model", False))) if on]
    if len(chosen) != 1:
        raise UsageError("give one of --port DEVICE or --sim" + (f" (got {' and '.join(chosen)})" if chosen else ""))
    if args.baud is not None and args.baud <= 0:
        raise UsageError(f"--baud {args.baud}: give a positive number of bits per second")
    if args.port:
        if args.baud is None:
            args.baud = DEFAULT_BAUD
        for flag, value in (("--steps", getattr(args, "steps", None)), ("--line-noise", getattr(args, "line_noise", None)),
                            ("--seed", getattr(args, "seed", None)), ("--probe-at", getattr(args, "probe_at", None))):
            if value is not None:
                raise UsageError(f"{flag} goes with --sim, not --port")
    pause = getattr(args, "pause_seconds", 0.0)
    if not (math.isfinite(pause) and pause >= 0.0):
        raise UsageError(f"--pause-seconds {pause:g}: give a number of seconds >= 0")
    noise = getattr(args, "line_noise", None)
    if noise is not None and not (math.isfinite(noise) and 0.0 <= noise <= 1.0):
        raise UsageError(f"--line-noise {noise:g}: give a bit-flip probability 0 .. 1")
    if getattr(args, "steps", None) is not None:        # before the simulator is built or run
        check_outputs(args.steps, inputs=(getattr(args, "file", None), args.machine))


# ---------------- the keyboard ----------------

# a terminal's escape sequences: CSI (arrow keys ESC [ A, PgUp ESC [ 5 ~, also cut off at the
# end of a read), SS3 (F1 ESC O P), ESC + a key other than ESC (Alt+key), a lone ESC
ESCAPE = re.compile(r"\x1b(?:\[[0-?]*[ -/]*(?:[@-~]|$)|O[^\x1b]?|[^\x1b])?", re.DOTALL)


KEY = re.compile(f"{ESCAPE.pattern}|.", re.DOTALL)


def key_tokens(text: str) -> list[str]:
    """The keys typed as tokens: an escape sequence (an arrow, a page key, Alt+key, a lone
    Esc) is one, any other character one."""
    return KEY.findall(text)


def typed_keys(text: str) -> str:
    """The keys typed, without the terminal's escape sequences: an arrow key or PgUp must not
    act as the '[' (spindle override), '5' (feed override) and '~' (resume) inside them."""
    return ESCAPE.sub("", text)


class Keyboard:
    """Single keys from a terminal's stdin (cbreak mode, no echo) without blocking, as typed
    (`interp jog` reads the arrow keys' escape sequences; `interp send` drops them: typed_keys)."""

    def __init__(self, enabled: bool):
        self.saved = None
        if enabled:
            import termios
            import tty

            self.fd = sys.stdin.fileno()
            self.saved = termios.tcgetattr(self.fd)
            tty.setcbreak(self.fd)

    def __call__(self) -> str:
        if self.saved is None:
            return ""
        import os
        import select

        out = ""
        while select.select([self.fd], [], [], 0)[0]:
            chunk = os.read(self.fd, 64)
            if not chunk:
                break
            out += chunk.decode("latin-1")
        return out

    def close(self) -> None:
        if self.saved is not None:
            import termios

            termios.tcsetattr(self.fd, termios.TCSADRAIN, self.saved)
            self.saved = None


# ---------------- progress ----------------

def mm_text(machine: Machine, steps) -> str:
    """A position in steps as "X1.000 Y2.000 Z0.000" (mm)."""
    return " ".join(f"{a}{v / s:.3f}" for a, v, s in zip("XYZ", steps, machine.steps_per_mm))


class Progress:
    """tqdm bar over the records (stderr, only on a terminal): line, position (mm), queue, state."""

    def __init__(self, compiled, machine: Machine, show: bool):
        self.compiled, self.machine, self.bar = compiled, machine, None
        if show:
            from tqdm import tqdm

            self.bar = tqdm(total=max(1, len(compiled.commands)), unit="rec", file=sys.stderr, mininterval=0.25,
                            dynamic_ncols=True, leave=False, desc="send")

    def __call__(self, snap) -> None:
        if self.bar is None:
            return
        mm = mm_text(self.machine, snap.position)
        feed = f", feed {snap.override} %" if snap.override != 100 else ""
        feed += f", spindle {snap.spindle} %" if snap.spindle != 100 else ""
        self.bar.set_postfix_str(f"line {line_of(self.compiled, snap.executed)} {mm} mm, queue {snap.queue_records}, "
                                 f"{p.STATE_NAMES.get(snap.state, '?')}{feed}", refresh=False)
        self.bar.update(min(snap.executed, self.bar.total) - self.bar.n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def line_of(compiled, executed: int, outside: bool = False) -> int:
    """The G-code line of the record running when EXECUTED = executed (1-based count);
    outside: the program's line outside any subroutine that ran it (a call's line)."""
    cmds = compiled.commands
    if not cmds:
        return 0
    cmd = cmds[min(max(executed, 1), len(cmds)) - 1]
    return (cmd.origin or cmd.source) if outside else cmd.source


def pause_record(compiled, executed: int, after: int = 0) -> int:
    """The record number (1-based) of the pause (M0, M1, M60; M6's) holding the controller when
    EXECUTED = executed: the pause itself was the last record dispatched, or the one before it
    (the controller dispatches the next record, which then waits for the release).  `after`:
    the number of the pause reported before (each pause holds once, in order); 0 if none."""
    cmds = compiled.commands

    def is_pause(n: int) -> bool:
        cmd = cmds[n - 1] if 1 <= n <= len(cmds) else None
        return cmd is not None and cmd.kind == gc.EVENT and cmd.x == gc.EVENT_CODES["pause"]
    for n in (executed - 1, executed):
        if n > after and is_pause(n):
            return n
    return next((n for n in range(after + 1, min(executed, len(cmds)) + 1) if is_pause(n)), 0)


def tool_of_pause(compiled, n: int) -> str:
    """", tool change to T4" when pause record n is an M6's (its tool change record before it)."""
    cmds = compiled.commands
    before = cmds[n - 2] if 2 <= n <= len(cmds) else None
    if before is not None and before.kind == gc.EVENT and before.x == gc.EVENT_CODES["tool_change"]:
        return f", tool change to T{before.y}"
    return ""


def pause_positions(compiled, start) -> dict[int, tuple[int, int, int]]:
    """Where the machine stands (steps) when each pause record (1-based number) runs, the
    program started at `start`: the ends of the lines and arcs before it (none after a
    curve, whose end is not its record's)."""
    at, out = list(start), {}
    for n, cmd in enumerate(compiled.commands, 1):
        if cmd.kind == CURVE:
            break
        if cmd.kind == gc.LINE:
            at = [a + d for a, d in zip(at, (cmd.x, cmd.y, cmd.z))]
        elif cmd.kind in (gc.ARC_CW, gc.ARC_CCW):
            at = [a + d for a, d in zip(at, to_machine(cmd.plane, cmd.x, cmd.y, cmd.z))]
        elif cmd.kind == gc.EVENT and cmd.x == gc.EVENT_CODES["pause"]:
            out[n] = tuple(at)
    return out


def limit_names(limits: int) -> str:
    return ", ".join(f"{a} limit" for n, a in enumerate("xyz") if limits >> n & 1)


# ---------------- the command ----------------

def refuse_probe(move) -> None:
    raise UsageError(f"line {move.line}: G38.{move.probe - 380}: give the simulated controller's probe a "
                     "touch with --probe-at (e.g. --probe-at Z-1.5)")


PROBE_AT = re.compile(r"([XYZ])([-+]?(?:\d+\.?\d*|\.\d+))", re.IGNORECASE)


def probe_touches(words, machine: Machine) -> list[tuple[int, str, int]]:
    """--probe-at AXIS MM words: (axis, side, steps) of the simulated probe's touches.  The
    simulated machine powers up at machine 0: a touch at MM > 0 is reached at or above it
    ("max"), one below 0 at or below it ("min")."""
    touches = []
    for word in words or []:
        m = PROBE_AT.fullmatch(word.strip())
        axis = AXES.index(m.group(1).lower()) if m else 0
        at = round(float(m.group(2)) * machine.steps_per_mm[axis]) if m else 0
        if at == 0:
            raise UsageError(f"--probe-at {word}: give an axis and a machine position in mm at least a step "
                             "from 0, e.g. Z-1.5")
        if any(axis == a for a, _, _ in touches):
            raise UsageError(f"--probe-at {word}: {AXES[axis].upper()} given twice (one touch per axis)")
        touches.append((axis, "max" if at > 0 else "min", at))
    return touches


def check_for_sim(text: str, machine: Machine, saved: dict, probe: bool = False, file: str | None = None,
                  start_line: int | None = None) -> None:
    """--sim: the program as the run will interpret and compile it (a fresh simulated
    controller stands at 0), so that a G-code error, or a probe move without a simulated
    touch (probe False: no --probe-at), is reported before the simulator is built and started."""
    program = gcode_command.interpret_program(text, machine, (0, 0, 0), saved, probes=[], program=file,
                                              start_line=start_line)
    if program.probe_pending and not probe:
        refuse_probe(program.moves[-1])
    compile_program(program, machine, start_steps=(0, 0, 0))


def cmd_send(args) -> int:
    check_link_args(args)
    machine = load_machine(args.machine, [], None)
    text = read_program(args.file)
    saved = saved_parameters(machine)
    touches = probe_touches(args.probe_at, machine)
    if touches and not args.sim:
        raise UsageError("--probe-at goes with --sim")
    if args.sim:
        check_for_sim(text, machine, saved, probe=bool(touches), file=args.file,
                      start_line=getattr(args, "start_line", None))
    if machine.parameter_file is not None and not args.sim:
        check_writable(machine.parameter_file)      # before the machine moves
    opened = open_or_report(args, machine)
    if opened is None:
        return 1
    transport, baud = opened
    for touch in touches:                   # (--sim only)
        transport.set_touch(*touch)
    keyboard = progress = None
    result = at_end = None
    try:
        driver = Driver(transport, baud=baud)
        make_ready(driver, machine, args.sim)   # (the simulator has no switches to home to)
        # the program starts where the machine is: the controller's position counters
        # (machine coordinates, zero at its reset), as Grbl's and LinuxCNC's programs do;
        # compiled from there (travel limits and arcs depend on the start)
        start = read_position(driver)
        if any(start):
            print(f"interp send: the machine is at {mm_text(machine, start)} mm (machine coordinates): "
                  "the program starts there", file=sys.stderr)
        if describe(saved):
            print(f"interp send: offsets from {machine.parameter_file}: {describe(saved)}", file=sys.stderr)
        warn_of_stop(driver, "interp send")
        interactive = sys.stdin.isatty() and sys.stderr.isatty()
        keyboard = Keyboard(interactive)
        run = ProgramRun(args, driver, machine, text, start, saved, keyboard, interactive)
        try:
            try:
                run.all()
            except UsageError:                  # an (ABORT, ...) between the pieces
                if run.records:
                    switch_off(driver)
                raise
            if run.failure:                     # a probe move that failed
                switch_off(driver)
            try:                                # where the machine stands (POS_X/Y/Z)
                at_end = read_position(driver)
            except LinkError:
                at_end = None
        except KeyboardInterrupt:
            driver.drop_stream()
            driver.write_register("CONTROL", p.CONTROL_ABORT | p.CONTROL_ENABLE)
            raise LinkError("interrupted: the controller was told to abort") from None
        finally:
            run.close()
    except MismatchError as err:
        raise UsageError(str(err)) from None
    except LinkError as err:
        print(f"interp: error: link: {err}", file=sys.stderr)
        return 1
    except NotHomed as err:
        print(f"interp: error: {err}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("interp: interrupted", file=sys.stderr)
        return 1
    finally:
        if progress is not None:
            progress.close()
        if keyboard is not None:
            keyboard.close()
        result = transport.close()
    stats = (f"{driver.frames_sent} frames, {driver.recoveries} retransmissions")
    if run.failure:
        print(f"interp: error: {run.failure}", file=sys.stderr)
        return 1
    outcome, compiled, records = run.outcome, run.compiled, run.records
    stopped_at = line_of(compiled, outcome.executed)
    where = f"record {run.records_before + outcome.executed} of {records}, line {stopped_at}"
    if outcome.status == "error":
        error = MachineError(outcome.error, outcome.limits, outcome.executed, "")
        extra = f", {limit_names(error.limits)}" if error.limits else ""
        print(f"interp: error: controller error {error.code} ({p.error_text(error.code)}{extra}) at {where}",
              file=sys.stderr)
        restart_hint(args, run, line_of(compiled, outcome.executed, outside=True))
        return 1
    if outcome.status == "aborted":
        how = f" ({outcome.message})" if outcome.message else ""
        print(f"interp: aborted at {where}{how}", file=sys.stderr)
        restart_hint(args, run, line_of(compiled, outcome.executed, outside=True))
        return 1
    if outcome.status != "done":
        print(f"interp: error: the run did not end ({where})", file=sys.stderr)
        return 1
    # the simulators count the pulses at the pins; a board reports its position registers
    position = result.get("position") if isinstance(result, dict) else at_end
    end = f", end {tuple(position)} steps" if position is not None else ""
    print(f"sent {records} records ({run.bytes} bytes) in {run.seconds:.3f} s link time at {baud} baud, "
          f"{stats}{end}")
    try:
        save_parameters(args, machine, saved, run.program.saved)
    except UsageError as err:
        print(f"interp: error: {err}; the offsets were: {describe(run.program.saved) or 'none'}", file=sys.stderr)
        return 1
    return 0


def restart_hint(args, run, line: int) -> None:
    """After a stop mid-program: how to run on from the line that was running (run from a
    line; in a subroutine, from its call's line), unless that cannot be (standard input, a
    probe run, a program the run from there refuses)."""
    program = run.program
    if args.file == "-" or run.results or program is None or line < 1 or \
            any(begin <= line <= end for _, begin, end in program.subroutines):
        return
    try:
        gcode_command.interpret_program(run.text, run.machine, run.start, run.saved, program=args.file,
                                        start_line=line)
    except UsageError:
        return
    print(f"interp send: to run on from that line once the machine is ready: "
          f"interp send {shlex.quote(args.file)} --start-line {line} ...", file=sys.stderr)


class ProgramRun:
    """A program on the controller: compiled and run in pieces where it probes.

    Without a probe move (G38.2 .. G38.5) the whole program is one piece, compiled as
    `interp gcode` compiles it.  A probe move is a piece of its own, run with the probe armed
    to stop the machine at the touch; the program is then interpreted again with what the
    probe did (interpret's probes: the touch and where the machine stopped), and the moves
    after it are compiled from where the machine stopped."""

    def __init__(self, args, driver: Driver, machine: Machine, text: str, start, saved: dict, keyboard,
                 interactive: bool):
        self.args, self.driver, self.machine, self.text = args, driver, machine, text
        self.start, self.saved, self.keyboard, self.interactive = start, saved, keyboard, interactive
        self.start_line = getattr(args, "start_line", None)      # --start-line (run from a line)
        self.results: list = []                 # ProbeResult of each probe move run
        self.shown: set[str] = set()            # warnings printed
        self.messages = 0                       # (MSG, ...) messages printed: the first n of the run
        self.records = self.records_before = self.bytes = 0
        self.seconds = 0.0
        self.program = self.compiled = self.outcome = self.progress = None
        self.failure = ""                       # a probe's error: one line
        self.probe_stop = tuple(start)          # steps: where the last probe move stopped
        self.override = None                    # the keys' feed override (FeedOverride), for every piece
        self.spindle = SpindleOverride()        # ... and spindle override

    def close(self) -> None:
        if self.progress is not None:
            self.progress.close()
            self.progress = None

    def show(self, lines, kind: str) -> None:
        """Print what an interpretation adds: each interpretation repeats the one before up to
        its probe move, so the messages are those beyond the count printed (a loop may repeat
        one), the warnings those not printed yet."""
        if kind == "message":
            lines, self.messages = lines[self.messages:], max(self.messages, len(lines))
        for line in lines:
            if kind == "message" or (kind, line) not in self.shown:
                self.shown.add((kind, line))
                print(f"interp: {kind}: {line}", file=sys.stderr)

    def all(self) -> None:
        done, here = 0, tuple(self.start)                 # moves run so far; the machine's position
        while True:
            try:
                self.program = program = gcode_command.interpret_program(self.text, self.machine, self.start,
                                                                         self.saved, probes=self.results,
                                                                         program=self.args.file,
                                                                         start_line=self.start_line)
            except GcodeError as err:           # an (ABORT, ...) after a probe: what it said before, once
                self.show(getattr(err, "messages", []), "message")
                err.messages = []
                raise
            whole = program
            if program.probe_pending and not self.results:
                # the whole program once (each touch at its move's end): G-code errors before anything moves
                whole = gcode_command.interpret_program(self.text, self.machine, self.start, self.saved,
                                                        program=self.args.file, start_line=self.start_line)
            if self.machine.parameter_file is not None and (whole is not program or not program.probe_pending):
                check_lengths(whole.saved)
            if not self.results:
                gcode_command.show_restart(program)
            self.show(program.messages, "message")
            self.show(program.warnings, "warning")
            moves = program.moves[done:]
            probe = moves.pop() if program.probe_pending else None      # (the interpretation's last move)
            if probe is not None and self.args.sim and not self.args.probe_at:
                refuse_probe(probe)
            if moves or (probe is None and self.compiled is None):
                if not self.piece(program, moves, here, last=probe is None):
                    return
                here = self.compiled.end_steps
            if probe is None:
                return
            if not self.probe_piece(program, probe, here):
                return
            here = self.probe_stop
            done = len(program.moves)

    def piece(self, program, moves, here, last: bool, probe: bool = False) -> bool:
        """Compile and run some moves from `here` (steps); False when the run did not end well."""
        compiled = compile_program(dataclasses.replace(program, moves=moves), self.machine, start_steps=here)
        self.show(compiled.warnings, "warning")
        build = compile_build()
        stream = encode_program(compiled.commands, build, codes=compiled)
        if not compiled.commands and last and not self.records and not offsets_changed(self.machine, self.saved,
                                                                                        program.saved):
            print("interp: warning: the program has no command to send", file=sys.stderr)
        if any(c.kind == CURVE for c in compiled.commands):
            check_controller(self.driver, build, self.machine.clock_hz, curves=True)
        configure(self.driver, self.machine.timing(), compiled.settings, compiled)
        if self.interactive and not self.records:
            print(f"interp send: {len(compiled.commands)} records, {len(stream)} bytes; {KEYS_HELP}",
                  file=sys.stderr)
        self.close()
        self.progress = Progress(compiled, self.machine, sys.stderr.isatty())

        last = [0]                              # the record of the pause reported last
        pauses = pause_positions(compiled, here)

        def at_pause(snap) -> bool:             # held by '!', and standing where a pause runs
            n = pause_record(compiled, snap.executed, last[0])
            return n in pauses and pauses[n] == tuple(snap.position)

        def on_pause(snap) -> None:
            how = "press ~ to resume" if self.interactive else f"resuming after {self.args.pause_seconds:g} s"
            last[0] = pause_record(compiled, snap.executed, last[0]) or last[0]
            line = compiled.commands[last[0] - 1].source if last[0] else line_of(compiled, snap.executed)
            lead = "\n" if self.progress.bar is not None else ""      # (below the progress bar)
            tool = tool_of_pause(compiled, last[0])
            print(f"{lead}interp send: program paused at line {line}{tool}: {how}", file=sys.stderr)

        self.records_before = self.records
        self.compiled = compiled
        if self.override is None:               # from the settings' percent
            self.override = FeedOverride(compiled.settings.get("override", 100))
        self.outcome = run_program(self.driver, stream, len(compiled.commands), progress=self.progress,
                                   keys=lambda: typed_keys(self.keyboard()), on_pause=on_pause, at_pause=at_pause,
                                   probe=probe,
                                   override=self.override, spindle=self.spindle,
                                   pause_resume=None if self.interactive else self.args.pause_seconds)
        self.records += len(compiled.commands)
        self.bytes += len(stream)
        self.seconds += self.outcome.seconds
        return self.outcome.status in (("done", "probed") if probe else ("done",))

    def probe_piece(self, program, move, here) -> bool:
        """Run a probe move; its ProbeResult joins self.results.  False: stop the program."""
        name = f"line {move.line}: G38.{move.probe - 380}"
        away = move.probe in PROBE_AWAY
        touching = bool(self.driver.read_register("INPUTS") & p.PROBE_INPUT)
        if touching != away:
            self.failure = (f"{name}: the probe does not touch before the move (it backs away from a touch)"
                            if away else f"{name}: the probe touches already before the move")
            return False
        invert = self.driver.read_register("INPUT_INVERT")
        if away:                                # the probe trips where it loses contact
            self.driver.write_register("INPUT_INVERT", invert ^ p.PROBE_INPUT)
        try:
            ended = self.piece(program, [move], here, last=False, probe=True)
        finally:
            if away:                            # (probe_stop off first: a probe still armed trips
                try:                            # when its polarity is back)
                    self.driver.write_register("CONTROL", p.CONTROL_ENABLE)
                finally:
                    self.driver.write_register("INPUT_INVERT", invert)
        self.driver.write_register("CONTROL", p.CONTROL_ENABLE)       # probe_stop off
        if not ended:
            return False
        touched = self.outcome.status == "probed"
        stop = read_position(self.driver)
        trip = tuple(signed32(self.driver.read_register(f"PROBE_{a}")) for a in "XYZ") if touched else stop
        if not touched and move.probe in PROBE_FAIL:
            self.failure = f"{name}: {PROBE_FAIL[move.probe]}"
            return False
        # in mm as the interpreter's start is (the next piece is compiled from `stop` in steps)
        result = ProbeResult(touched, gc.start_mm(self.machine, trip), gc.start_mm(self.machine, stop))
        self.results.append(result)
        self.probe_stop = stop                              # the next piece starts there
        self.outcome = dataclasses.replace(self.outcome, status="done")
        return True


def warn_of_stop(driver: Driver, who: str) -> None:
    """A warning on stderr when ERROR holds a stop (the next run clears it)."""
    error = driver.read_register("ERROR") & 0xFF
    if error:
        print(f"{who}: warning: the controller stopped on error {error} ({p.error_text(error)}): its "
              "steps stopped at once, so the motors may have lost steps the position counts", file=sys.stderr)


# ERROR codes that stop the steps at once, at speed: motion_top's fault (4) and overrun (10),
# the e-stop, a limit switch, an abort at speed
STOPPED_AT_ONCE = (4, 10, 16, 17, p.ERROR_ABORT_AT_SPEED)


class NotHomed(Exception):
    """homing.required and an axis not homed: one line, exit status 1."""


def make_ready(driver: Driver, machine: Machine, sim: bool, homing_lock: bool = True) -> None:
    """Connect as `interp send`, `home` and `jog` do: the build and clock checked, a controller
    busy with a program refused, the machine file's pin settings written (not to the simulator:
    its pins are ideal) and, with homing_lock, homing.required (NotHomed)."""
    driver.connect()
    check_controller(driver, compile_build(), machine.clock_hz)
    check_idle(driver)
    if not sim:
        apply_pin_settings(driver, machine.pin_settings())
        if homing_lock:
            check_homed(driver, machine)


def check_homed(driver: Driver, machine: Machine) -> None:
    """With homing.required, every axis `interp home` homes must have had its position set
    since the controller's reset (STATUS.position_set), as Grbl locks a machine until $H."""
    if not machine.homing["required"]:
        return
    homed = driver.read_register("STATUS") >> 16 & 7
    missing = [AXES[a].upper() for a in machine.homed_axes() if not homed >> a & 1]
    error = driver.read_register("ERROR") & 0xFF
    if error in STOPPED_AT_ONCE:                 # steps may be lost, as Grbl's alarm
        raise NotHomed(f"the controller stopped on error {error} ({p.error_text(error)}): the motors may have "
                       "lost steps: run interp home (homing.required)")
    if missing:
        raise NotHomed(f"the machine is not homed since the controller's reset ({' '.join(missing)}): "
                        "run interp home (homing.required)")


def offsets_changed(machine: Machine, before: dict, after: dict) -> bool:
    """The program changed the saved parameters (offsets, G92, G28 / G30 positions): a line of
    MDI such as G10 L20 sends no command and still did something."""
    from ..gcode.interpreter import interpret

    return after != interpret("", g28=machine.g28, g30=machine.g30, saved=before).saved


def save_parameters(args, machine: Machine, before: dict, after: dict) -> None:
    """A program that ran to its end leaves its offsets, G92 and G28 / G30 positions in the
    machine's parameter file for the next one (as LinuxCNC's var file and Grbl's settings keep
    them); the file is written only when they changed.  A simulated run (--sim) reads the file
    but leaves it as it is."""
    path = machine.parameter_file
    if path is None or args.sim or not offsets_changed(machine, before, after):
        return
    # the G28 / G30 positions only where G28.1 / G30.1 moved them from the machine file's [home]
    homes = {5161 + a: machine.g28[a] for a in range(3)} | {5181 + a: machine.g30[a] for a in range(3)}
    write_parameters(path, {key: value for key, value in after.items() if homes.get(key) != value})
    print(f"interp send: saved the offsets to {path}" + (f": {describe(after)}" if describe(after) else ""),
          file=sys.stderr)


def add_link_options(p_, sim_help: str, seed: bool = False) -> None:
    import argparse

    p_.add_argument("--port", metavar="DEVICE", help="serial device or pyserial URL (loop://, socket://HOST:PORT)")
    p_.add_argument("--baud", type=int, metavar="B", help=f"bits per second, 115200 .. 3000000 (default {DEFAULT_BAUD}; "
                    "--sim: 3000000, or the fastest the machine's clock makes within the receiver's "
                    "tolerance, at least 4 clocks a bit)")
    p_.add_argument("--sim", action="store_true", help=sim_help)
    p_.add_argument("--machine", metavar="FILE.toml", help="machine file (default: the shipped default machine)")
    if seed:                            # (send only: the line noise's)
        p_.add_argument("--seed", type=int, help="--sim: the line noise's seed (default 1)")
    # the Python model of the controller's link (interp.link.devicemodel), for tests
    p_.add_argument("--sim-model", action="store_true", help=argparse.SUPPRESS)
    p_.add_argument("--sim-model-rate", type=float, default=2000.0, help=argparse.SUPPRESS)
    p_.add_argument("--sim-model-fail", type=int, help=argparse.SUPPRESS)


def add_parser(sub) -> None:
    p_ = sub.add_parser("send", help="send a G-code program to the board controller (UART link)")
    p_.add_argument("file", help="G-code file (RS274NGC, as `interp gcode` reads it); - reads standard input")
    add_link_options(p_, "the Verilator model of the controller instead of a port", seed=True)
    p_.add_argument("--steps", metavar="FILE", help="--sim: CSV of the steps (cycle,dx,dy,dz)")
    p_.add_argument("--line-noise", type=float, metavar="P", help="--sim: bit-flip probability per bit, both ways")
    p_.add_argument("--probe-at", action="append", metavar="AXIS_MM",
                    help="--sim: where the simulated probe touches, e.g. Z-1.5: machine mm (the simulated machine "
                         "powers up at 0), reached at or beyond it as seen from 0; again for another axis (any counts)")
    p_.add_argument("--pause-seconds", type=float, default=0.0, metavar="S",
                    help="a program pause (M0, M1, M6, M60) ends after S seconds when no terminal is attached to "
                         "resume it with ~ (default 0)")
    p_.add_argument("--start-line", type=gcode_command.start_line, metavar="N",
                    help="run from line N, as `interp gcode --start-line` does: the spindle, coolant and outputs "
                         "the lines before it left, then up to the clearance, across and down to where the program "
                         "stood there")
    p_.set_defaults(func=cmd_send)
