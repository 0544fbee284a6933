# SPDX-License-Identifier: Apache-2.0
"""`interp gcode FILE`: a G-code program through rtl/motion_top.v.

  interp gcode FILE [--sim icarus|verilator] [--scale STEPS_PER_UNIT] --steps FILE
                    [--vcd FILE] [--plot FILE.png] [--rapid FEED] [--pulse-width N]
                    [--setup N] [--hold N]

Understood: G00/G01 (lines), G02/G03 with I/J (centre relative to the start),
G04 P (dwell), G90/G91, G17 and G21 (accepted, no effect), F, X/Y/Z, N
(ignored), comments in ( ) or after ;.  With --clock-hz HZ, F is the path
speed in units per minute and G04 P is in seconds, as on a machine; without
it (simulation-sized numbers), F is in units per 1000 clock cycles and P in
clock cycles.  Anything else is an error naming its line.
"""
from __future__ import annotations

import json
import math
import re
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from ..cores import UsageError
from ..models.motion import ARC_CCW, ARC_CW, DWELL, ERROR_TEXT, LINE, Command
from ..simulation.output import ensure_dir, write_steps
from ..simulation.runner import SIMULATORS

# motion_top as the benches build it (tb/motion_top): the CLI reuses that build.
PARAMETERS = {"W": 16, "QDEPTH": 4, "QLW": 3, "SDEPTH": 2, "TW": 4}
WIDTH, FRAC, FEED_MAX, TIMING_MAX = 16, 16, (1 << 16) - 1, 15
LINE_MAX = (1 << (WIDTH - 1)) - 1           # longest line command; longer moves are split
ARC_LIMIT = 1 << (WIDTH - 3)                # circ_arc: |point - centre| < 2^(W-3) per axis

DEMO = """\
( interp gcode demo: a rounded slot, a 3-axis move and a dwell )
G21 G90 G17
G00 X0 Y0 Z0
G01 X40 Y0 F250          ; a line along X
G03 X50 Y10 I0 J10       ; quarter circle, counter-clockwise
G01 Y30 F150             ; slower
G03 X40 Y40 I-10 J0
G01 X10 Y40 F250
G03 X0 Y30 I0 J-10
G02 X0 Y10 I0 J-10       ; half circle, clockwise
G01 Y0
G04 P40                  ; dwell 40 clock cycles
G91 G01 X5 Y-10 Z6 F200  ; relative, 3 axes
G90 G00 X0 Y0 Z0         ; rapid home
"""

WORD = re.compile(r"([A-Z])\s*([-+]?(?:\d+\.?\d*|\.\d+))")


class GcodeError(UsageError):
    def __init__(self, line: int, text: str):
        super().__init__(f"line {line}: {text}")


@dataclass
class Program:
    commands: list[Command] = field(default_factory=list)
    path: list[list[tuple[float, float]]] = field(default_factory=list)   # programmed XY polylines (steps)
    end: tuple[int, int, int] = (0, 0, 0)                                  # programmed end point, steps
    z_moves: bool = False


def clocks_per_f_unit(clock_hz: float | None) -> float:
    """Clock cycles in F's time unit: a minute at clock_hz, else 1000 cycles."""
    return 60 * clock_hz if clock_hz else 1000


def feed_word(f: float, scale: float, clock_hz: float | None = None) -> int:
    """F (units per minute, or per 1000 clocks) -> motion_top's feed (steps per clock x 2^FRAC)."""
    return round(f * scale / clocks_per_f_unit(clock_hz) * (1 << FRAC))


def words(line: str, number: int) -> list[tuple[str, float]]:
    text = re.sub(r"\(.*?\)", " ", line.split(";", 1)[0]).upper().strip()
    found = WORD.findall(text)
    rest = WORD.sub("", text).strip()
    if rest:
        raise GcodeError(number, f"cannot read {rest!r}")
    return [(letter, float(value)) for letter, value in found]


def parse(text: str, scale: float = 1.0, rapid: int = FEED_MAX, clock_hz: float | None = None) -> Program:
    """G-code -> motion_top commands (relative, in steps) and the programmed path."""
    prog = Program()
    units = [0.0, 0.0, 0.0]             # programmed position in units
    here = (0, 0, 0)                    # the same in steps (rounded once, no drift)
    mode, relative, feed = 0, False, None
    for number, line in enumerate(text.splitlines(), 1):
        if line.strip() in ("", "%"):
            continue
        ws = words(line, number)
        values: dict[str, float] = {}
        dwell = False
        for letter, value in ws:
            if letter == "G":
                g = int(value) if value == int(value) else None
                if g in (0, 1, 2, 3):
                    mode = g
                elif g in (90, 91):
                    relative = g == 91
                elif g == 4:
                    dwell = True
                elif g not in (17, 21):
                    raise GcodeError(number, f"unsupported G-code G{value:g}")
            elif letter in "XYZIJFPN":
                if letter in values:
                    raise GcodeError(number, f"{letter} given twice")
                values[letter] = value
            else:
                raise GcodeError(number, f"unsupported word {letter}{value:g}")
        if "F" in values:
            if values["F"] <= 0 or feed_word(values["F"], scale, clock_hz) == 0:
                raise GcodeError(number, f"feed F{values['F']:g} is 0 at this scale (feed 0)")
            if feed_word(values["F"], scale, clock_hz) > FEED_MAX:
                top = FEED_MAX * clocks_per_f_unit(clock_hz) / scale / (1 << FRAC)
                raise GcodeError(number, f"feed F{values['F']:g} is above the maximum F{top:.6g} (1 step per clock)")
            feed = feed_word(values["F"], scale, clock_hz)
        if dwell:
            p = values.get("P", 0)
            cycles = round(p * clock_hz) if clock_hz else p
            if cycles < 0 or cycles != int(cycles) or cycles > LINE_MAX:
                raise GcodeError(number, f"dwell P{p:g}: want 0 .. {LINE_MAX} whole clock cycles")
            prog.commands.append(Command(DWELL, 0, int(cycles), source=number))
            continue
        if "P" in values:
            raise GcodeError(number, "P without G04")
        moves = any(a in values for a in "XYZ")
        if mode in (2, 3) and not moves and any(a in values for a in "IJ"):
            moves = True                                    # full circle
        if not moves:
            if any(a in values for a in "IJ"):
                raise GcodeError(number, "I/J without an arc")
            continue
        for k, a in enumerate("XYZ"):
            if a in values:
                units[k] = units[k] + values[a] if relative else values[a]
        target = tuple(round(u * scale) for u in units)
        delta = tuple(t - h for t, h in zip(target, here))
        if mode in (0, 1):
            if any(a in values for a in "IJ"):
                raise GcodeError(number, "I/J on a line move")
            if mode == 1 and feed is None:
                raise GcodeError(number, "G01 without a feed rate (F)")
            f = rapid if mode == 0 else feed
            pieces = max(1, math.ceil(max(abs(d) for d in delta) / LINE_MAX))
            done = (0, 0, 0)
            for p in range(1, pieces + 1):
                part = tuple(round(d * p / pieces) for d in delta)
                step = tuple(a - b for a, b in zip(part, done))
                prog.commands.append(Command(LINE, f, *step, source=number))
                done = part
            prog.path.append([here[:2], target[:2]])
        else:
            if feed is None:
                raise GcodeError(number, f"G0{mode} without a feed rate (F)")
            if delta[2]:
                raise GcodeError(number, "helical arcs (Z on G02/G03) are not supported")
            ci, cj = round(values.get("I", 0) * scale), round(values.get("J", 0) * scale)
            r0 = math.hypot(ci, cj)
            r1 = math.hypot(delta[0] - ci, delta[1] - cj)
            if r0 == 0:
                raise GcodeError(number, "arc centre is the start point (radius 0)")
            if abs(r1 - r0) > 0.5:
                raise GcodeError(number, f"arc with inconsistent centre: start radius {r0:.3f}, "
                                 f"end radius {r1:.3f} steps (more than half a step apart)")
            if max(abs(ci), abs(cj), abs(delta[0] - ci), abs(delta[1] - cj)) >= ARC_LIMIT:
                raise GcodeError(number, f"arc too large for the arc core (radius limit {ARC_LIMIT} steps)")
            ccw = mode == 3
            prog.commands.append(Command(ARC_CCW if ccw else ARC_CW, feed, delta[0], delta[1], 0,
                                         ci, cj, source=number))
            prog.path.append(arc_points(here, delta, (ci, cj), ccw))
        prog.z_moves |= delta[2] != 0
        here = target
    prog.end = here
    return prog


def arc_points(start, delta, centre, ccw: bool, n: int = 96):
    cx, cy = start[0] + centre[0], start[1] + centre[1]
    a0 = math.atan2(start[1] - cy, start[0] - cx)
    a1 = math.atan2(start[1] + delta[1] - cy, start[0] + delta[0] - cx)
    sweep = (a1 - a0) % (2 * math.pi) if ccw else -((a0 - a1) % (2 * math.pi))
    if sweep == 0:
        sweep = 2 * math.pi if ccw else -2 * math.pi
    r = math.hypot(start[0] - cx, start[1] - cy)
    n = max(n, math.ceil(abs(sweep) / math.sqrt(0.008 / max(r, 1))))     # chords within 0.001 step
    return [(cx + r * math.cos(a0 + sweep * k / n), cy + r * math.sin(a0 + sweep * k / n)) for k in range(n + 1)]


UNIT = "mm"         # G21 (the only units accepted); plots are drawn in program units


def ideal_path(prog: Program) -> list[tuple[float, float]]:
    """The programmed XY path as one polyline, in steps."""
    return [pt for piece in prog.path for pt in piece]


def plot_program(path, prog: Program, rows, scale: float, name: str) -> float | None:
    """PNG of a program's steps over its programmed XY path, in program units."""
    from ..plots.paths import plot_path

    return plot_path(path, rows, ideal_path(prog), unit=UNIT, scale=scale,
                     title=f"interp gcode {name}: motion_top, {scale:g} step{'s' * (scale != 1)}/{UNIT}")


def simulate(commands: list[Command], sim: str, timing: dict, vcd: str | None = None,
             max_cycles: int = 5_000_000) -> dict:
    """Run the commands through motion_top; the driver's result (pulses, errors, position)."""
    from ..simulation.runner import run_cocotb

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "result.json"
        job = {"commands": [c.ports() for c in commands], "timing": timing, "out": str(out),
               "max_cycles": max_cycles}
        run_cocotb(toplevel="motion_top", test_module="interp.simulation.motion_driver", sim=sim,
                   parameters=PARAMETERS, env={"INTERP_JOB": json.dumps(job)}, waves=vcd,
                   name="motion_top", test_dir=Path(tmp), quiet=True)
        return json.loads(out.read_text())


def step_rows(result: dict, axes: str) -> list[tuple[int, ...]]:
    rows = []
    for cycle, step, dirs in result["pulses"]:
        rows.append((cycle, *[(-1 if dirs >> k & 1 else 1) if step >> k & 1 else 0
                              for k in range(len(axes))]))
    return rows


def run_program(text: str, args) -> int:
    prog = parse(text, args.scale, args.rapid, args.clock_hz)
    timing = {"pulse_width": args.pulse_width, "setup": args.setup, "hold_time": args.hold}
    result = simulate(prog.commands, args.sim, timing, args.vcd)
    axes = "xyz" if prog.z_moves else "xy"
    rows = step_rows(result, axes)
    write_steps(args.steps, rows, axes)
    if args.plot:
        plot_program(args.plot, prog, rows, args.scale, Path(args.file).name)
    for cycle, code in result["errors"]:        # the front end's checks should leave none
        print(f"interp: motion_top error at cycle {cycle}: code {code}, {ERROR_TEXT.get(code, '?')}")
    if result["errors"]:
        return 1
    if tuple(result["position"]) != prog.end:
        raise RuntimeError(f"end position {result['position']} != programmed {prog.end}")
    print(f"{len(prog.commands)} commands, {len(rows)} step cycles, {result['cycles']} clock cycles, "
          f"end position {tuple(result['position'])}")
    return 0


def cmd_gcode(args) -> int:
    if args.scale <= 0:
        raise UsageError("--scale must be positive")
    if not 1 <= args.rapid <= FEED_MAX:
        raise UsageError(f"--rapid must be 1 .. {FEED_MAX}")
    for name in ("pulse_width", "setup", "hold"):
        if not 0 <= getattr(args, name) <= TIMING_MAX:
            raise UsageError(f"--{name.replace('_', '-')} must be 0 .. {TIMING_MAX} clock cycles")
    try:
        text = Path(args.file).read_text()
    except OSError as err:
        raise UsageError(f"cannot read {args.file}: {err.strerror}") from None
    return run_program(text, args)


def add_parser(sub) -> None:
    p = sub.add_parser("gcode", help="run a G-code program through the motion subsystem RTL")
    p.add_argument("file", help="G-code file")
    p.add_argument("--sim", choices=SIMULATORS, default="icarus", help="simulator (default icarus)")
    p.add_argument("--scale", type=float, default=1.0, help="steps per unit (default 1: coordinates in steps)")
    p.add_argument("--clock-hz", type=float, help="clock frequency: F in units/minute, G04 P in seconds "
                   "(default: F in units per 1000 clocks, P in clocks)")
    p.add_argument("--steps", required=True, metavar="FILE", help="CSV of steps: cycle,dx,dy[,dz]")
    p.add_argument("--vcd", metavar="FILE", help="waveform file")
    p.add_argument("--plot", metavar="FILE", help="PNG of the stepped path over the programmed one")
    p.add_argument("--rapid", type=int, default=FEED_MAX,
                   help=f"feed word for G00 (steps per clock x 2^{FRAC}; default {FEED_MAX})")
    p.add_argument("--pulse-width", type=int, default=1, help="step pulse width, clock cycles (default 1)")
    p.add_argument("--setup", type=int, default=0, help="dir setup time, clock cycles (default 0)")
    p.add_argument("--hold", type=int, default=0, help="dir hold time, clock cycles (default 0)")
    p.set_defaults(func=cmd_gcode)


def demo(out, sim: str) -> None:
    """`interp demo`: the built-in program through the RTL."""
    out = ensure_dir(out)
    src = out / "gcode_demo.nc"
    src.write_text(DEMO)
    from ..cli import build_parser

    args = build_parser().parse_args(["gcode", str(src), "--sim", sim, "--steps", str(out / "gcode_demo_steps.csv"),
                                      "--vcd", str(out / "gcode_demo.vcd"), "--plot", str(out / "gcode_demo.png")])
    args.func(args)
    print(f"gcode demo: {out / 'gcode_demo.png'} {out / 'gcode_demo_steps.csv'} {out / 'gcode_demo.vcd'}")
