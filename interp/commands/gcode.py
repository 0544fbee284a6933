# SPDX-License-Identifier: Apache-2.0
"""`interp gcode FILE`: a G-code program through rtl/motion_top.v (docs/gcode-cli.md).

  interp gcode FILE [--machine FILE.toml] [--set KEY=VALUE]... [--clock-hz HZ]
                    [--profile trapezoid|scurve] [--check [--json]]
                    [--sim verilator|icarus] [--steps FILE] [--events FILE]
                    [--pause-seconds S] [--max-seconds S] [--vcd FILE] [--plot FILE.png]
                    [--hold-at S --resume-at S]... [--override PERCENT[@S]]...
                    [--plot-speed FILE.png]

The program is read with LinuxCNC RS274NGC semantics (interp.gcode.interpreter),
compiled for the machine (interp.gcode.compile: the look-ahead plan and the speed
profile's fields) and, unless --check, simulated: Verilator through the native
harness, Icarus through cocotb, with the feed holds and overrides asked for; the
motion monitor (interp.simulation.monitor) then checks the run's speeds.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import sys
import tempfile
from pathlib import Path

from ..cores import UsageError
from ..gcode.compile import EVENT_NAMES, Compiled, compile_program, write_commands
from ..gcode.machine import AXES, Machine, load_machine
from ..link.records import unpack_interval
from ..simulation.output import check_outputs, ensure_dir

SIMS = ("verilator", "icarus")
PROFILES = ("trapezoid", "scurve")

# `interp demo`'s program: real units (mm, F in mm/min), the default machine file.  It runs
# with a 50 kHz clock (DEMO_OPTIONS): the same steps as at 50 MHz, in a thousandth of the cycles.
DEMO = """\
( interp gcode demo: a line, arcs in G17 and G18, a helix, spindle on and off )
G21 G90 G17
G00 X0 Y0 Z1
M3 S12000                    ; spindle on, clockwise
G01 Z0 F1500
G01 X10 F3000                ; a line along X
G03 X15 Y5 I0 J5             ; quarter circle, counter-clockwise
G03 X10 Y10 Z-1 I-5 J0       ; a quarter turn of a helix, 1 mm down
G01 X0
G18 G02 X-4 Z-1 I-2 K0       ; half circle in the ZX plane
G17 G01 Y0
G00 Z1
M5                           ; spindle off
G04 P0.01                    ; dwell 10 ms
G00 X0 Y0
M2
"""
DEMO_OPTIONS = ["--clock-hz", "50000"]


# ---------------- the layers below, behind small functions (tests replace them) ----------------

def saved_parameters(machine: Machine) -> dict[int, float]:
    """The parameters the machine's parameter file keeps ({} with none or before its first run)."""
    from ..gcode.parameter_file import read_parameters

    path = machine.parameter_file
    return read_parameters(path) if path is not None else {}


def interpret_program(text: str, machine: Machine, start_steps=(0, 0, 0), saved=None, probes=None,
                      program: str | None = None, start_line: int | None = None):
    """The program's moves in machine mm (interface 1), from start_steps (the machine's
    position), with the saved parameters (default: the machine's parameter file) and what its
    probe moves did (interpret's probes; None: each touches at its end).  program: the
    program's file ("-": standard input), whose folder has its subroutine files.  start_line:
    run from that line (restart.start_at: the state before it restored, an approach to it)."""
    from ..gcode.compile import start_mm
    from ..gcode.errors import GcodeError
    from ..gcode.interpreter import interpret
    from ..gcode.restart import same_from, start_at

    def run(at):
        return interpret(text, g28=machine.g28, g30=machine.g30, tools=machine.tools, start=at,
                         saved=saved_parameters(machine) if saved is None else saved, probes=probes,
                         folders=machine.subroutine_folders(program))

    here = start_mm(machine, start_steps)
    moves = run(here)
    if start_line is None:
        return moves
    restarted = start_at(moves, start_line, here, laser=bool(machine.values["spindle"]["laser"]))
    starts = tuple(tuple(v + shift for v, shift in zip(here, away)) for away in ANCHOR_SHIFTS_MM)
    try:
        anchored = not same_from(run(starts[0]), run(starts[1]), start_line, starts)
        why = ""
    except GcodeError as err:
        anchored, why = True, f" (from another start it fails: {err})"
    if anchored:
        raise UsageError(f"--start-line {start_line}: the moves from there depend on where the program started "
                         "(G92 or G10 L20 from where the machine stood, or incremental moves from its start): "
                         f"run from here they would be shifted; run it from its first line where it started{why}")
    return restarted


# --start-line: two more interpretations from these starts, from the machine's (odd values that
# no program's word meets, so that an axis it programs is never taken for one still at its start)
ANCHOR_SHIFTS_MM = ((0.0123457, 0.0234571, 0.0345713), (-0.0457131, 0.0571313, -0.0713137))


def compile_text(text: str, machine: Machine | None = None, pause_seconds: float = 0.0,
                 profile: str | None = None, costs: str = "true", start_steps=(0, 0, 0), saved=None,
                 program: str | None = None, start_line: int | None = None):
    """(Program, Compiled) of a program's text (program: its file, for its subroutine files;
    start_line: run from that line), as `interp gcode` makes them (default machine),
    from start_steps: the machine's position in steps (`interp send`: the controller's POS_X/Y/Z;
    a fresh controller is at 0), with the saved parameters (default: the machine's parameter
    file; `Program.saved` has the program's end values)."""
    machine = machine or load_machine()
    moves = interpret_program(text, machine, start_steps, saved, program=program, start_line=start_line)
    return moves, compile_program(moves, machine, pause_seconds, profile=profile, costs=costs,
                                  start_steps=start_steps)


def run_simulation(commands_path: str, sim: str, *, steps_path, timing: dict, max_cycles: int,
                   progress, vcd, settings: dict, controls: list, push_interval: int = 1) -> dict:
    """motion_top on the command file (interface 3) with the profile settings and the
    hold / resume / override schedule [(cycle, kind, value)], a command pushed at least
    push_interval cycles after the previous one; the harness's result dict."""
    try:
        from ..simulation import native
    except ImportError as err:
        raise RuntimeError(f"the simulation harness is not available: {err}") from None
    arguments = {"steps_path": steps_path, "timing": (timing["pulse_width"], timing["setup"], timing["hold"]),
                 "max_cycles": max_cycles, "progress": progress, "vcd": vcd, "settings": settings,
                 "controls": controls, "push_interval": push_interval}
    if sim == "verilator":
        return native.run_native(commands_path, **arguments)
    return native.run_cocotb_job(commands_path, sim=sim, **arguments)


# ---------------- helpers ----------------

VCD_BYTES_PER_CLOCK = 3300         # motion_top's waveform, measured (every net, a change each clock)
MAX_PROGRAM_BYTES = 1 << 28        # 256 MiB, far above any CAM program


def read_program(path: str) -> str:
    """The program's text; "-" reads standard input (`echo "G91 G0 X10" | interp send - ...`).
    A device (a serial port given as the program by mistake, /dev/zero) is refused, and so is
    a program above MAX_PROGRAM_BYTES."""
    from ..gcode.language import read_source

    if path != "-":
        return read_source(path, MAX_PROGRAM_BYTES)
    data = sys.stdin.buffer.read(MAX_PROGRAM_BYTES + 1)
    if len(data) > MAX_PROGRAM_BYTES:
        raise UsageError(f"{path}: a program of more than {MAX_PROGRAM_BYTES >> 20} MiB")
    return data.decode("utf-8", errors="surrogateescape")


def show_restart(program) -> None:
    """--start-line: what the start line found and the approach, one line for the operator."""
    if program.restart is not None:
        print(f"interp: {program.restart.describe()}", file=sys.stderr)


def start_line(text: str) -> int:
    """--start-line's value: a line number from 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a line number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value}: lines count from 1")
    return value


def fmt(value: float) -> str:
    return str(int(value)) if value == int(value) and abs(value) < 1e15 else f"{value:.6g}"


def summary(program, compiled: Compiled, machine: Machine) -> dict:
    """The --check --json object."""
    return {"end": [round(v, 6) for v in program.end_work], "units": program.units,
            "end_machine_mm": [round(v, 6) for v in program.end_machine],
            "end_steps": list(compiled.end_steps), "moves": compiled.moves, "arcs": compiled.arcs,
            "joined_moves": compiled.joined,
            "chord_arcs": compiled.chords, "corrected_arcs": compiled.corrected,
            "events": len(compiled.events), "commands": len(compiled.commands),
            "machine_time_s": round(compiled.machine_time_s, 6), "clock_hz": machine.clock_hz,
            "step_events": compiled.step_events, "profile": compiled.profile, "settings": dict(compiled.settings),
            "warnings": program.warnings + compiled.warnings, "messages": list(program.messages),
            "warning_count": len(program.warnings) + compiled.warning_count}


def where(program, compiled: Compiled) -> str:
    unit = "mm" if program.units == "mm" else "in"
    work = " ".join(f"{a.upper()}{fmt(round(v, 4))}" for a, v in zip(AXES, program.end_work))
    return f"{work} {unit} (work) = {tuple(compiled.end_steps)} steps"


def write_events(path, events, compiled: Compiled) -> None:
    with open(path, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["cycle", "event", "value"])
        for n, (cycle, code, value) in enumerate(events):
            name = EVENT_NAMES.get(code, f"code{code}")
            if n < len(compiled.events) and compiled.events[n][0] == name:
                value = compiled.events[n][1]
            out.writerow([cycle, name, fmt(value)])


def ideal_xy(program, machine: Machine) -> list[tuple[float, float]]:
    """The programmed XY path in steps (X's steps per mm on both axes, for the plot)."""
    from ..gcode.moves import PLANES, Arc, Line

    s = machine.steps_per_mm[0]
    pts = []
    for m in program.moves:
        if isinstance(m, Line):
            pts += [(m.start[0] * s, m.start[1] * s), (m.end[0] * s, m.end[1] * s)]
        elif isinstance(m, Arc):
            iu, iv, _ = PLANES[m.plane]
            r = math.hypot(m.start[iu] - m.centre[iu], m.start[iv] - m.centre[iv])
            a0 = math.atan2(m.start[iv] - m.centre[iv], m.start[iu] - m.centre[iu])
            a1 = math.atan2(m.end[iv] - m.centre[iv], m.end[iu] - m.centre[iu])
            part = (a1 - a0) % (2 * math.pi) if m.ccw else -((a0 - a1) % (2 * math.pi))
            if part == 0:
                part = 2 * math.pi if m.ccw else -2 * math.pi
            sweep = part + math.copysign(2 * math.pi * (max(m.turns, 1) - 1), part)
            # chords within 0.001 step of the arc, so the deviations measured are the steps' own
            n = max(8, min(20000, math.ceil(abs(sweep) / math.sqrt(0.008 / max(r * s, 1)))))
            for k in range(n + 1):
                a, t = a0 + sweep * k / n, k / n
                p = [m.start[j] + (m.end[j] - m.start[j]) * t for j in range(3)]
                p[iu], p[iv] = m.centre[iu] + r * math.cos(a), m.centre[iv] + r * math.sin(a)
                pts.append((p[0] * s, p[1] * s))
    return pts


def plot_program(path, program, rows, machine: Machine, name: str) -> float | None:
    """PNG of a run's XY steps over the programmed path, drawn in mm; the largest deviation (steps)."""
    from ..plots.paths import plot_path

    scale = machine.steps_per_mm[0]
    return plot_path(path, rows, ideal_xy(program, machine), unit="mm", scale=scale,
                     title=f"interp gcode {name}: motion_top, {scale:g} steps/mm")


def read_step_rows(path) -> list[tuple[int, ...]]:
    with open(path, newline="") as f:
        rows = csv.reader(f)
        next(rows, None)
        return [tuple(int(v) for v in row) for row in rows]


class Progress:
    """The tqdm bar (stderr, only on a terminal) and the dispatch history for error lines."""

    def __init__(self, compiled: Compiled, clock_hz: float, show: bool):
        self.compiled, self.history = compiled, []
        self.bar = None
        if show:
            from tqdm import tqdm

            total = max(1, int(compiled.machine_time_s * clock_hz))
            self.bar = tqdm(total=total, unit="cyc", unit_scale=True, file=sys.stderr, mininterval=0.5,
                            dynamic_ncols=True, leave=False, desc="motion_top")

    def line_of(self, dispatched: int) -> int:
        cmds = self.compiled.commands
        return cmds[min(max(dispatched, 1), len(cmds)) - 1].source if cmds else 0

    def __call__(self, cycle: int, steps: int, dispatched: int) -> None:
        self.history.append((cycle, dispatched))
        if self.bar is not None:
            self.bar.set_postfix_str(f"steps {steps}, line {self.line_of(dispatched)}", refresh=False)
            self.bar.update(min(cycle, self.bar.total) - self.bar.n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()

    def line_at(self, cycle: int) -> str:
        before = [d for c, d in self.history if c <= cycle]
        return f"line {self.line_of(before[-1])}" if before else "an unknown line"


def _seconds(value: float, flag: str) -> float:
    if not (math.isfinite(value) and value >= 0):
        raise UsageError(f"{flag} needs a finite time in seconds >= 0 (got {value:g})")
    return value


def check_plot_format(path: str | None, flag: str) -> None:
    """Refuse, before anything runs, a plot file whose extension matplotlib cannot write."""
    if path is None:
        return
    from matplotlib.backend_bases import FigureCanvasBase

    formats = FigureCanvasBase.get_supported_filetypes()
    suffix = Path(path).suffix.lower().lstrip(".")
    if suffix not in formats:
        got = f"'.{suffix}'" if suffix else "no extension"
        raise UsageError(f"{flag} {path}: {got} is not a plot format; use one of "
                         f"{', '.join('.' + f for f in sorted(formats))}")


def parse_override(text: str) -> tuple[int, float | None]:
    """--override PERCENT[@SECONDS] -> (percent 1..200, seconds or None = from the start)."""
    percent, at, seconds = text.partition("@")
    try:
        value = int(percent)
    except ValueError:
        try:
            float(percent)
        except ValueError:
            raise UsageError(f"--override {text}: give PERCENT or PERCENT@SECONDS, e.g. 150@2.5") from None
        raise UsageError(f"--override {text}: the percentage must be a whole number 1 .. 200") from None
    try:
        when = float(seconds) if at else None
    except ValueError:
        raise UsageError(f"--override {text}: give PERCENT or PERCENT@SECONDS, e.g. 150@2.5") from None
    if not 1 <= value <= 200:
        raise UsageError(f"--override {text}: the percentage must be a whole number 1 .. 200")
    if when is not None and not (math.isfinite(when) and when >= 0):
        raise UsageError(f"--override {text}: the time after @ must be a finite number of seconds >= 0")
    return value, when


def controls_of(args, clock_hz: float) -> tuple[int, list[tuple[int, str, int]], list[tuple[float, float | None]]]:
    """(initial override %, the harness's schedule [(cycle, kind, value)] sorted by cycle,
    the hold intervals in seconds) from --hold-at / --resume-at / --override."""
    holds = [_seconds(h, "--hold-at") for h in args.hold_at]
    resumes = [_seconds(r, "--resume-at") for r in args.resume_at]
    if len(resumes) > len(holds):
        raise UsageError("--resume-at without a --hold-at before it (give them in pairs, in order)")
    pairs = [(h, resumes[k] if k < len(resumes) else None) for k, h in enumerate(holds)]
    for k, (h, r) in enumerate(pairs):
        if r is not None and r <= h:
            raise UsageError(f"--resume-at {r:g} is not after its --hold-at {h:g}")
        if k + 1 < len(pairs) and (r is None or pairs[k + 1][0] < r):
            raise UsageError(f"--hold-at {pairs[k + 1][0]:g} overlaps the hold from {h:g} s "
                             f"({'never resumed' if r is None else f'resumed at {r:g} s'})")
    for k in range(1, len(pairs)):
        previous, hold = pairs[k - 1][1], pairs[k][0]
        if _round_cycle(hold, clock_hz) <= _round_cycle(previous, clock_hz):
            raise UsageError(f"--hold-at {hold:g} must come after the previous --resume-at {previous:g} "
                             f"(at {clock_hz:g} Hz both are clock cycle {_round_cycle(previous, clock_hz)} "
                             "or the hold is earlier)")
    initial, schedule = 100, []
    for text in args.override:
        percent, when = parse_override(text)
        if when is None:
            initial = percent
        else:
            schedule.append((_round_cycle(when, clock_hz), "override", percent))
    for h, r in pairs:
        schedule.append((_round_cycle(h, clock_hz), "hold", 0))
        if r is not None:
            schedule.append((_round_cycle(r, clock_hz), "resume", 0))
    order = {"hold": 0, "override": 1, "resume": 2}
    schedule.sort(key=lambda c: (c[0], order[c[1]]))
    return initial, schedule, pairs


def _round_cycle(seconds: float, clock_hz: float) -> int:
    return math.floor(seconds * clock_hz + 0.5)


def hold_lines(holds, stops, controls, step_cycles, cycles: int, clock: float) -> list[str]:
    """One line per hold: when the steps stopped after it (the last step of the steps CSV
    before its resume, so an S-curve's filter tail counts) and how many steps left after it;
    a warning for a hold after the program's end."""
    hold_cycles = [c for c, kind, _ in controls if kind == "hold"]
    resume_cycles = [c for c, kind, _ in controls if kind == "resume"]
    out = []
    for k, (h, r) in enumerate(holds):
        h_cycle = hold_cycles[k] if k < len(hold_cycles) else _round_cycle(h, clock)
        r_cycle = resume_cycles[k] if k < len(resume_cycles) else None
        if h_cycle >= cycles:
            print(f"interp: warning: --hold-at {h:g}: after the program's end ({cycles / clock:.6g} s), "
                  "it had no effect", file=sys.stderr)
            continue
        after = [c for c in step_cycles if c >= h_cycle and (r_cycle is None or c < r_cycle)]
        stop = stops[k] if k < len(stops) else None
        stopped = stop is not None and stop[1] is not None
        if stopped:
            last = max([stop[1]] + after)
            when = f"stopped {(last - h_cycle) / clock:.6g} s later"
        elif r_cycle is not None:
            when = "did not stop before its resume"
        else:
            when = "did not stop before the run's end"
        out.append(f"hold at {h:g} s: {when}, {len(after)} steps after it")
    return out


# ---------------- the command ----------------

def cmd_gcode(args) -> int:
    if args.json and not args.check:
        raise UsageError("--json goes with --check")
    if not args.pause_seconds >= 0 or not math.isfinite(args.pause_seconds):
        raise UsageError(f"--pause-seconds {args.pause_seconds:g}: give a finite number of seconds >= 0")
    if args.max_seconds is not None and not args.max_seconds > 0:
        raise UsageError("--max-seconds must be positive")
    if args.push_interval is not None and not 1 <= args.push_interval <= 65536:
        raise UsageError("--push-interval must be 1 .. 65536")
    machine = load_machine(args.machine, args.set, args.clock_hz)
    override, controls, holds = controls_of(args, machine.clock_hz)
    if args.check and (controls or args.plot_speed or override != 100):
        raise UsageError("--hold-at, --resume-at, --override and --plot-speed go with a simulation, not --check")
    if args.check and any(v is not None for v in (args.steps, args.events, args.vcd, args.plot)):
        raise UsageError("--steps, --events, --vcd and --plot are written by a simulation, not --check")
    check_plot_format(args.plot, "--plot")
    check_plot_format(args.plot_speed, "--plot-speed")
    if not args.check:
        check_outputs(args.steps, args.events, args.vcd, args.plot, args.plot_speed, inputs=(args.file, args.machine))
    program, compiled = compile_text(read_program(args.file), machine, args.pause_seconds, args.profile,
                                     program=args.file, start_line=args.start_line)
    compiled.settings["override"] = override
    show_restart(program)
    for message in program.messages:
        print(f"interp: message: {message}", file=sys.stderr)
    for warning in program.warnings + compiled.warnings:
        print(f"interp: warning: {warning}", file=sys.stderr)
    if args.check:
        info = summary(program, compiled, machine)
        if args.json:
            print(json.dumps(info))
        else:
            joined = f", {compiled.joined} joined (naive CAM)" if compiled.joined else ""
            print(f"{Path(args.file).name}: {info['moves']} moves ({info['arcs']} arcs{joined}), {info['events']} events, "
                  f"{info['commands']} commands, {info['step_events']} step events, {compiled.profile} profile, "
                  f"machine time {compiled.machine_time_s:.3f} s, end {where(program, compiled)}, "
                  f"{info['warning_count']} warnings")
        return 0
    return simulate_program(args, program, compiled, machine, controls, holds)


def simulate_program(args, program, compiled: Compiled, machine: Machine, controls=(), holds=()) -> int:
    from ..simulation.monitor import monitor, read_rows, verdict

    clock = machine.clock_hz
    slowest = min([compiled.settings.get("override", 100)] + [v for _, k, v in controls if k == "override"])
    held = sum((r if r is not None else 0) - h for h, r in holds if r is not None)
    if args.max_seconds is not None:
        max_seconds = args.max_seconds
    else:
        max_seconds = 2 * compiled.machine_time_s * 100 / slowest + held + 10
        if any(r is None for _, r in holds):            # held to the end: a second after the hold
            max_seconds = min(max_seconds, max(h for h, _ in holds) + 1 + compiled.machine_time_s * 0.01)
    max_cycles = math.ceil(max_seconds * clock)
    if args.vcd is not None:
        gigabytes = compiled.machine_time_s * clock * VCD_BYTES_PER_CLOCK / 1e9
        if gigabytes >= 1:
            print(f"interp: warning: --vcd {args.vcd}: about {gigabytes:.0f} GB for {compiled.machine_time_s:.3g} s of "
                  f"machine time at {clock:g} Hz (--max-seconds cuts it short)", file=sys.stderr)
    progress = Progress(compiled, clock, sys.stderr.isatty())
    with tempfile.TemporaryDirectory(prefix="interp_gcode_") as tmp:
        commands_path = Path(tmp) / "commands.txt"
        write_commands(commands_path, compiled.commands)
        steps_path = args.steps or str(Path(tmp) / "steps.csv")
        try:
            result = run_simulation(str(commands_path), args.sim, steps_path=steps_path,
                                    timing=machine.timing(), max_cycles=max_cycles, progress=progress,
                                    vcd=args.vcd, settings=dict(compiled.settings), controls=list(controls),
                                    push_interval=args.push_interval or unpack_interval())
        finally:
            progress.close()
        worst = None
        rows = read_rows(steps_path)
        step_cycles = rows[:, 0].tolist()
        if args.plot:
            worst = plot_program(args.plot, program, [tuple(r) for r in rows.tolist()], machine,
                                 Path(args.file).name)
        report = monitor(rows, compiled, machine, controls=controls)
        if args.plot_speed:
            from ..plots.speed import plot_speed

            plot_speed(args.plot_speed, report, title=f"interp gcode {Path(args.file).name}: path and axis speeds "
                       f"({compiled.profile}, {clock:g} Hz)")
    if args.events:
        write_events(args.events, result["events"], compiled)
    cycles = result["cycles"]
    failures = []
    for cycle, code in result["errors"]:
        from ..models.motion import ERROR_TEXT

        failures.append(f"motion_top error {code} ({ERROR_TEXT.get(code, 'unknown')}) at cycle {cycle}, "
                        f"{progress.line_at(cycle)}")
    position = tuple(result["position"])
    if not failures and position != tuple(compiled.end_steps):
        late = " (--max-seconds reached)" if cycles >= max_cycles else ""
        if any(r is None for _, r in holds):
            late = " (held by --hold-at without --resume-at)"
        failures.append(f"the RTL ended at {position} steps, the program at {tuple(compiled.end_steps)}{late}")
    if not failures and len(result["events"]) != len(compiled.events):
        failures.append(f"motion_top gave {len(result['events'])} events, the program has {len(compiled.events)}")
    end = where(program, compiled) if position == tuple(compiled.end_steps) else f"{position} steps (stopped early)"
    deviation = f", max deviation {worst:.3f} steps (XY)" if worst is not None else ""
    print(f"{result['steps']} step cycles, end {end}, {cycles} clock cycles, "
          f"{cycles / clock:.6g} s machine time at {clock:g} Hz, {len(result['events'])} events{deviation}")
    for line in hold_lines(holds, result.get("hold_stops", []), controls, step_cycles, cycles, clock):
        print(line)
    print(verdict(report))
    if not report.ok and not failures:
        failures.append(f"the motion monitor found {len(report.violations)} violations (see above)")
    for failure in failures:
        print(f"interp: error: {failure}", file=sys.stderr)
    return 1 if failures else 0


def add_parser(sub) -> None:
    p = sub.add_parser("gcode", help="run a G-code program through the motion subsystem RTL")
    p.add_argument("file", help="G-code file (RS274NGC, as LinuxCNC reads it); - reads standard input")
    p.add_argument("--machine", metavar="FILE.toml", help="machine file (default: the shipped default machine)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override one machine-file key, e.g. axis.x.steps_per_mm=80 (repeatable)")
    p.add_argument("--clock-hz", type=float, metavar="HZ", help="shorthand for --set controller.clock_hz=HZ")
    p.add_argument("--check", action="store_true", help="read and compile only; print a summary")
    p.add_argument("--start-line", type=start_line, metavar="N",
                   help="run from line N: the spindle, coolant and outputs the lines before it left, then up to "
                        "the clearance, across and down to where the program stood there (docs/gcode-cli.md)")
    p.add_argument("--json", action="store_true", help="with --check: one JSON object")
    p.add_argument("--sim", choices=SIMS, default="verilator",
                   help="simulator: verilator (native harness, default) or icarus (cocotb)")
    p.add_argument("--steps", metavar="FILE", help="CSV of steps: cycle,dx,dy,dz")
    p.add_argument("--events", metavar="FILE", help="CSV of events: cycle,event,value")
    p.add_argument("--pause-seconds", type=float, default=0.0, metavar="S",
                   help="machine time of each pause (M0, M1, M6, M60), default 0")
    p.add_argument("--max-seconds", type=float, metavar="S",
                   help="machine-time limit (default 2 x the estimate / the slowest override, + the holds + 10 s)")
    p.add_argument("--vcd", metavar="FILE", help="waveform file")
    p.add_argument("--push-interval", type=int, metavar="N",
                   help="clocks from one command's push into motion_top to the next, at least (default: "
                        "RECORD_BYTES + 8 + DERIVE_CLOCKS, 424: the controller's record unpacker on the link's "
                        "compact records; "
                        "1: motion_top fed directly)")
    p.add_argument("--plot", metavar="FILE.png", help="PNG of the stepped XY path over the programmed one")
    p.add_argument("--profile", choices=PROFILES, help="speed profile (default: the machine file's motion.profile)")
    p.add_argument("--hold-at", action="append", type=float, default=[], metavar="S",
                   help="feed hold at this machine time in seconds: decelerate to a stop (repeatable)")
    p.add_argument("--resume-at", action="append", type=float, default=[], metavar="S",
                   help="release the hold before it at this machine time (repeatable, paired in order)")
    p.add_argument("--override", action="append", default=[], metavar="PERCENT[@S]",
                   help="feed override 1..200 %% from the start, or from S seconds on (repeatable)")
    p.add_argument("--plot-speed", metavar="FILE.png",
                   help="PNG of the path and axis speeds against time, with the limits")
    p.set_defaults(func=cmd_gcode)


def demo(out, sim: str) -> None:
    """`interp demo`: the built-in program through the RTL."""
    from ..cli import build_parser

    out = ensure_dir(out)
    src = out / "gcode_demo.nc"
    src.write_text(DEMO)
    sim = sim if sim in SIMS else "icarus"
    args = build_parser().parse_args(["gcode", str(src), *DEMO_OPTIONS, "--sim", sim,
                                      "--steps", str(out / "gcode_demo_steps.csv"),
                                      "--events", str(out / "gcode_demo_events.csv"),
                                      "--vcd", str(out / "gcode_demo.vcd"), "--plot", str(out / "gcode_demo.png"),
                                      "--plot-speed", str(out / "gcode_demo_speed.png")])
    if args.func(args):
        raise RuntimeError("the G-code demo failed")
    print(f"gcode demo: {out / 'gcode_demo.png'} {out / 'gcode_demo_speed.png'} {out / 'gcode_demo_steps.csv'} "
          f"{out / 'gcode_demo.vcd'}")
