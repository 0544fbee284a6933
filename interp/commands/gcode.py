# SPDX-License-Identifier: Apache-2.0
"""`interp gcode FILE`: a G-code program through rtl/motion_top.v (docs/gcode-cli.md).

  interp gcode FILE [--machine FILE.toml] [--set KEY=VALUE]... [--clock-hz HZ]
                    [--check [--json]] [--sim verilator|icarus] [--steps FILE]
                    [--events FILE] [--pause-seconds S] [--max-seconds S]
                    [--vcd FILE] [--plot FILE.png]

The program is read with LinuxCNC RS274NGC semantics (interp.gcode.interpreter),
compiled for the machine (interp.gcode.compile) and, unless --check, simulated:
Verilator through the native harness, Icarus through cocotb.
"""
from __future__ import annotations

import csv
import json
import math
import sys
import tempfile
from pathlib import Path

from ..cores import UsageError
from ..gcode.compile import EVENT_NAMES, Compiled, compile_program, write_commands
from ..gcode.machine import AXES, Machine, load_machine
from ..simulation.output import check_outputs, ensure_dir

SIMS = ("verilator", "icarus")

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

def interpret_program(text: str, machine: Machine):
    """The program's moves in machine mm (interface 1)."""
    from ..gcode.interpreter import interpret

    return interpret(text, g28=machine.g28, g30=machine.g30, tools=machine.tools)


def compile_text(text: str, machine: Machine | None = None, pause_seconds: float = 0.0):
    """(Program, Compiled) of a program's text, as `interp gcode` makes them (default machine)."""
    machine = machine or load_machine()
    program = interpret_program(text, machine)
    return program, compile_program(program, machine, pause_seconds)


def run_simulation(commands_path: str, sim: str, *, steps_path, timing: dict, max_cycles: int,
                   progress, vcd) -> dict:
    """motion_top on the command file (interface 3); the harness's result dict."""
    try:
        from ..simulation import native
    except ImportError as err:
        raise RuntimeError(f"the simulation harness is not available: {err}") from None
    arguments = {"steps_path": steps_path, "timing": (timing["pulse_width"], timing["setup"], timing["hold"]),
                 "max_cycles": max_cycles, "progress": progress, "vcd": vcd}
    if sim == "verilator":
        return native.run_native(commands_path, **arguments)
    return native.run_cocotb_job(commands_path, sim=sim, **arguments)


# ---------------- helpers ----------------

def read_program(path: str) -> str:
    try:
        data = Path(path).read_bytes()
    except IsADirectoryError:
        raise UsageError(f"cannot read {path}: is a folder") from None
    except OSError as err:
        raise UsageError(f"cannot read {path}: {err.strerror or err}") from None
    return data.decode("utf-8", errors="surrogateescape")


def fmt(value: float) -> str:
    return f"{value:.6g}" if value != int(value) else str(int(value))


def summary(program, compiled: Compiled, machine: Machine) -> dict:
    """The --check --json object."""
    return {"end": [round(v, 6) for v in program.end_work], "units": program.units,
            "end_machine_mm": [round(v, 6) for v in program.end_machine],
            "end_steps": list(compiled.end_steps), "moves": compiled.moves, "arcs": compiled.arcs,
            "chord_arcs": compiled.chords, "corrected_arcs": compiled.corrected,
            "events": len(compiled.events), "commands": len(compiled.commands),
            "machine_time_s": round(compiled.machine_time_s, 6), "clock_hz": machine.clock_hz,
            "warnings": program.warnings + compiled.warnings, "messages": list(program.messages)}


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


# ---------------- the command ----------------

def cmd_gcode(args) -> int:
    if args.json and not args.check:
        raise UsageError("--json goes with --check")
    if not args.pause_seconds >= 0 or not math.isfinite(args.pause_seconds):
        raise UsageError("--pause-seconds must be 0 or more")
    if args.max_seconds is not None and not args.max_seconds > 0:
        raise UsageError("--max-seconds must be positive")
    machine = load_machine(args.machine, args.set, args.clock_hz)
    if not args.check:
        check_outputs(args.steps, args.events, args.vcd, args.plot)
    program, compiled = compile_text(read_program(args.file), machine, args.pause_seconds)
    for message in program.messages:
        print(f"interp: message: {message}", file=sys.stderr)
    for warning in program.warnings + compiled.warnings:
        print(f"interp: warning: {warning}", file=sys.stderr)
    if args.check:
        info = summary(program, compiled, machine)
        if args.json:
            print(json.dumps(info))
        else:
            print(f"{Path(args.file).name}: {info['moves']} moves ({info['arcs']} arcs), {info['events']} events, "
                  f"{info['commands']} commands, machine time {compiled.machine_time_s:.3f} s, "
                  f"end {where(program, compiled)}, {len(info['warnings'])} warnings")
        return 0
    return simulate_program(args, program, compiled, machine)


def simulate_program(args, program, compiled: Compiled, machine: Machine) -> int:
    clock = machine.clock_hz
    max_seconds = args.max_seconds if args.max_seconds is not None else 2 * compiled.machine_time_s + 10
    max_cycles = math.ceil(max_seconds * clock)
    progress = Progress(compiled, clock, sys.stderr.isatty())
    with tempfile.TemporaryDirectory(prefix="interp_gcode_") as tmp:
        commands_path = Path(tmp) / "commands.txt"
        write_commands(commands_path, compiled.commands)
        steps_path = args.steps or (str(Path(tmp) / "steps.csv") if args.plot else None)
        try:
            result = run_simulation(str(commands_path), args.sim, steps_path=steps_path,
                                    timing=machine.timing(), max_cycles=max_cycles, progress=progress,
                                    vcd=args.vcd)
        finally:
            progress.close()
        worst = None
        if args.plot:
            worst = plot_program(args.plot, program, read_step_rows(steps_path), machine, Path(args.file).name)
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
        failures.append(f"the RTL ended at {position} steps, the program at {tuple(compiled.end_steps)}{late}")
    if not failures and len(result["events"]) != len(compiled.events):
        failures.append(f"motion_top gave {len(result['events'])} events, the program has {len(compiled.events)}")
    end = where(program, compiled) if position == tuple(compiled.end_steps) else f"{position} steps (stopped early)"
    deviation = f", max deviation {worst:.3f} steps (XY)" if worst is not None else ""
    print(f"{result['steps']} step cycles, end {end}, {cycles} clock cycles, "
          f"{cycles / clock:.6g} s machine time at {clock:g} Hz, {len(result['events'])} events{deviation}")
    for failure in failures:
        print(f"interp: error: {failure}", file=sys.stderr)
    return 1 if failures else 0


def add_parser(sub) -> None:
    p = sub.add_parser("gcode", help="run a G-code program through the motion subsystem RTL")
    p.add_argument("file", help="G-code file (RS274NGC, as LinuxCNC reads it)")
    p.add_argument("--machine", metavar="FILE.toml", help="machine file (default: the shipped default machine)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override one machine-file key, e.g. axis.x.steps_per_mm=80 (repeatable)")
    p.add_argument("--clock-hz", type=float, metavar="HZ", help="shorthand for --set controller.clock_hz=HZ")
    p.add_argument("--check", action="store_true", help="read and compile only; print a summary")
    p.add_argument("--json", action="store_true", help="with --check: one JSON object")
    p.add_argument("--sim", choices=SIMS, default="verilator",
                   help="simulator: verilator (native harness, default) or icarus (cocotb)")
    p.add_argument("--steps", metavar="FILE", help="CSV of steps: cycle,dx,dy,dz")
    p.add_argument("--events", metavar="FILE", help="CSV of events: cycle,event,value")
    p.add_argument("--pause-seconds", type=float, default=0.0, metavar="S",
                   help="machine time of each pause (M0, M1, M6, M60), default 0")
    p.add_argument("--max-seconds", type=float, metavar="S",
                   help="machine-time limit (default 2 x the estimate + 10 s)")
    p.add_argument("--vcd", metavar="FILE", help="waveform file")
    p.add_argument("--plot", metavar="FILE.png", help="PNG of the stepped XY path over the programmed one")
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
                                      "--vcd", str(out / "gcode_demo.vcd"), "--plot", str(out / "gcode_demo.png")])
    if args.func(args):
        raise RuntimeError("the G-code demo failed")
    print(f"gcode demo: {out / 'gcode_demo.png'} {out / 'gcode_demo_steps.csv'} {out / 'gcode_demo.vcd'}")
