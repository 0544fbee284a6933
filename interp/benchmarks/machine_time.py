# SPDX-License-Identifier: Apache-2.0
"""Machine time of the corpus programs: our look-ahead planner against Grbl's.

    python -m interp.benchmarks.machine_time [--machine FILE.toml] [--window K] [--only TEXT]

Every program of the corpus directory (INTERP_GCODE_CORPUS, see gcode_corpus.py) that the
front end accepts is read with the machine file (the default machine unless --machine) and
timed twice:

  * ours: the program's motion commands as the compiler emits them (interp.gcode.compile,
    once it plans its commands; until then segments built here from the moves: lines
    between step-rounded points, arcs and helices exact) planned by interp.gcode.planner
    over the whole program, and with a streaming window of --window segments (default 32),
    each segment a trapezoid at its acceleration, plus the dwells;
  * Grbl: interp.benchmarks.grbl_planner, arcs as chords (arc tolerance 0.002 mm), a
    16-slot buffer in streaming order, plus the dwells.

Both use the same axes (steps/mm, max rate, acceleration) and junction deviation.  The table:
program | ours (s) | ours, window (s) | Grbl (s) | ratio ours/Grbl | arcs exact / Grbl chords;
then the programs, if any, on which we are slower than Grbl and the main reason.
"""
from __future__ import annotations

import argparse
import math
import sys
from dataclasses import dataclass

from ..cores import UsageError
from ..gcode.compile import EXACT_STOP_MODES
from ..gcode.errors import GcodeError
from ..gcode.interpreter import interpret
from ..gcode.machine import Machine, load_machine
from ..gcode.moves import PLANES, Arc, Dwell, Event, Line, Program
from ..gcode.planner import Segment, machine_time, plan
from . import grbl_planner
from .gcode_corpus import CORPUS, corpus_files

STREAM_WINDOW = 32


def arc_geometry(arc: Arc) -> tuple[float, float, tuple, tuple]:
    """(length mm, radius mm, start unit tangent, end unit tangent) of an exact arc/helix."""
    u, v, w = PLANES[arc.plane]
    radius = math.hypot(arc.start[u] - arc.centre[u], arc.start[v] - arc.centre[v])
    travel = grbl_planner.angular_travel(arc)
    rise = arc.end[w] - arc.start[w]
    length = math.hypot(radius * travel, rise)
    start_angle = math.atan2(arc.start[v] - arc.centre[v], arc.start[u] - arc.centre[u])
    turn = math.copysign(1.0, travel)

    def tangent(angle: float) -> tuple:
        vector = [0.0, 0.0, 0.0]
        vector[u] = -math.sin(angle) * turn * radius * abs(travel) / length
        vector[v] = math.cos(angle) * turn * radius * abs(travel) / length
        vector[w] = rise / length
        return tuple(vector)
    return length, radius, tangent(start_angle), tangent(start_angle + travel)


def program_segments(program: Program, machine: Machine, *,
                     exact_stop_modes: tuple[str, ...] = EXACT_STOP_MODES) -> tuple[list[Segment], float]:
    """The program's motion commands as planner segments (lines between points rounded to
    whole steps, zero-step lines dropped; arcs and helices exact), and the dwell seconds.
    Exact stops: the first move, after a dwell or event, and in G61 / G61.1; G64 P sets the
    junction tolerance."""
    steps = machine.steps_per_mm
    rate = tuple(a.max_rate_mm_min / 60.0 for a in machine.axes)
    accel = tuple(a.accel_mm_s2 for a in machine.axes)
    segments: list[Segment] = []
    dwell = 0.0
    stop = True
    position = None

    def rounded(point):
        return tuple(round(c * n) for c, n in zip(point, steps))

    for move in program.moves:
        if isinstance(move, (Dwell, Event)):
            dwell += move.seconds if isinstance(move, Dwell) else 0.0
            stop = True
            continue
        mode, tolerance = move.path_control
        if isinstance(move, Line):
            start = position if position is not None else rounded(move.start)
            end = rounded(move.end)
            delta = tuple((e - s) / n for e, s, n in zip(end, start, steps))
            length = math.sqrt(sum(d * d for d in delta))
            if length == 0.0:
                continue
            unit = tuple(d / length for d in delta)
            feed = grbl_planner.limit_by_axes(rate, unit) if move.feed is None else move.feed / 60.0
            segment = Segment(length, unit, unit, feed, rate, accel)
        else:
            length, radius, start_unit, end_unit = arc_geometry(move)
            u, v, _ = PLANES[move.plane]
            segment = Segment(length, start_unit, end_unit, move.feed / 60.0, rate, accel,
                              radius_mm=radius, plane_axes=(u, v))
            end = rounded(move.end)
        segment.stop_before = stop or (mode in exact_stop_modes and not move.continues)
        segment.tolerance_mm = tolerance if mode == "G64" else None
        segments.append(segment)
        position = end
        stop = False
    return segments, dwell


@dataclass
class Row:
    name: str
    ours_s: float               # the whole-program plan of our commands, with the dwells
    window_s: float             # the same with the streaming window
    grbl_s: float
    arcs: int
    chords: int
    segments: int
    stops: int
    moves_s: float = math.nan   # our plan of segments built from the moves (= ours_s without the compiler)
    source: str = "moves"       # where our segments come from: "compiler" or "moves"

    @property
    def ratio(self) -> float:
        return self.ours_s / self.grbl_s if self.grbl_s else math.nan


def compiled_segments(program: Program, machine: Machine, paced: bool = True) -> list[Segment] | None:
    """Our segments as the compiler emits its move commands (interp.gcode.compile, when its
    commands carry the planner's view of them: `Cmd.motion`), or None with a compiler that
    does not plan; paced=False leaves out the arcs' pacing (their local speed's excess)."""
    from ..gcode import compile as compiler

    if "plans" not in getattr(compiler.Compiled, "__dataclass_fields__", {}):
        return None
    compiled = compiler.compile_program(program, machine)
    rate = tuple(a.max_rate_mm_min / 60.0 for a in machine.axes)
    accel = tuple(a.accel_mm_s2 for a in machine.axes)
    motions = [c.motion for c in compiled.commands if getattr(c, "motion", None) is not None]
    return [compiler.planner_segment(m, motions[n - 1] if n else None, rate, accel, paced=paced)
            for n, m in enumerate(motions)]


def measure(program: Program, machine: Machine, name: str = "", *, window: int = STREAM_WINDOW,
            arc_tolerance_mm: float = grbl_planner.DEFAULT_ARC_TOLERANCE,
            use_compiler: bool = True) -> Row:
    """One program's row: ours from the compiler's commands when the compiler plans (else
    from the moves), Grbl's from the reference."""
    own, dwell = program_segments(program, machine)
    deviation = machine.values["motion"]["junction_deviation_mm"]
    moves_s = machine_time(plan(own, junction_deviation_mm=deviation)) + dwell
    segments = compiled_segments(program, machine) if use_compiler else None
    source = "moves" if segments is None else "compiler"
    segments = own if segments is None else segments
    ours = machine_time(plan(segments, junction_deviation_mm=deviation)) + dwell
    streamed = machine_time(plan(segments, junction_deviation_mm=deviation, window=window)) + dwell
    grbl = grbl_planner.run(program, grbl_planner.GrblSettings.from_machine(
        machine, arc_tolerance_mm=arc_tolerance_mm))
    return Row(name, ours, streamed, grbl.time_s, grbl.arcs, grbl.chords, len(segments),
               sum(s.stop_before for s in own), moves_s, source)


SLOWER = 1e-6           # relative: a difference below this is rounding, not slower


def why_slower(program: Program, machine: Machine, row: Row) -> str:
    """Where the extra seconds against Grbl come from, found by re-planning without each of
    our rules that Grbl does not have, in turn: the compiler's commands (against segments
    built from the moves), the G61 exact stops, then the centripetal bound of the arcs (arcs
    planned like lines of their start tangent); the rest is the path itself (an exact arc is
    longer than Grbl's chords, which cut inside it)."""
    deviation = machine.values["motion"]["junction_deviation_mm"]
    segments, dwell = program_segments(program, machine, exact_stop_modes=())
    no_stops = machine_time(plan(segments, junction_deviation_mm=deviation)) + dwell
    flat = [Segment(s.length_mm, s.start_unit, s.end_unit, s.feed_mm_s, s.axis_rate_mm_s,
                    s.axis_accel_mm_s2, None, None, s.stop_before, s.tolerance_mm) for s in segments]
    unbounded = machine_time(plan(flat, junction_deviation_mm=deviation)) + dwell
    unpaced = compiled_segments(program, machine, paced=False) if row.source == "compiler" else None
    plain = row.ours_s if unpaced is None else machine_time(plan(unpaced, junction_deviation_mm=deviation)) + dwell
    parts = [(row.ours_s - plain, "the arcs' stepped pace (their local speed up to pacing x the mean, "
                                  "within the axes' limits)"),
             (plain - row.moves_s, "the compiler's commands against the moves (step rounding, "
                                   "one-step corrections at arc ends)"),
             (row.moves_s - no_stops, "G61 exact stops (Grbl runs G61 with its junction deviation)"),
             (no_stops - unbounded, "the centripetal bound v^2 <= a_n R on tight arcs (Grbl's chord "
                                    "junctions allow about v^2 = a R delta / arc tolerance)"),
             (unbounded - row.grbl_s, "the rest: exact arc lengths (longer than chords) and junctions")]
    named = [f"{seconds:+.3f} s {what}" for seconds, what in parts if abs(seconds) > 5e-4]
    return f"{row.ours_s - row.grbl_s:+.4f} s: " + ("; ".join(named) or "below a millisecond")


def corpus_rows(machine: Machine, *, window: int = STREAM_WINDOW, only: str | None = None,
                arc_tolerance_mm: float = grbl_planner.DEFAULT_ARC_TOLERANCE,
                progress=None) -> tuple[list[Row], list[str], list[str]]:
    """(rows, refused programs, reasons we are slower) over the corpus; `progress(row)` is
    called after each program."""
    rows: list[Row] = []
    refused: list[str] = []
    reasons: list[str] = []
    for path in corpus_files():
        if only and only not in path.name:
            continue
        text = path.read_text(encoding="utf-8", errors="surrogateescape")
        try:
            program = interpret(text, g28=machine.g28, g30=machine.g30, tools=machine.tools)
        except GcodeError as err:
            refused.append(f"{path.name}: {err}")
            continue
        try:
            row = measure(program, machine, path.name, window=window, arc_tolerance_mm=arc_tolerance_mm)
        except UsageError as err:                       # the compiler refuses it
            refused.append(f"{path.name}: {err}")
            continue
        rows.append(row)
        if row.ours_s > row.grbl_s * (1 + SLOWER):
            reasons.append(f"{row.name} ({row.ratio:.4f}): {why_slower(program, machine, row)}")
        if progress:
            progress(row)
    return rows, refused, reasons


def _cells(row: Row) -> list:
    return [row.name, f"{row.ours_s:.3f}", f"{row.window_s:.3f}", f"{row.grbl_s:.3f}",
            f"{row.ratio:.4f}", f"{row.arcs} / {row.chords}"]


def _total(rows: list[Row]) -> list:
    ours = math.fsum(r.ours_s for r in rows)
    grbl = math.fsum(r.grbl_s for r in rows)
    return [f"**all {len(rows)}**", f"{ours:.3f}", f"{math.fsum(r.window_s for r in rows):.3f}",
            f"{grbl:.3f}", f"{ours / grbl if grbl else math.nan:.4f}",
            f"{sum(r.arcs for r in rows)} / {sum(r.chords for r in rows)}"]


def _header(window: int) -> list[str]:
    return ["program", "ours (s)", f"ours, window {window} (s)", "Grbl (s)", "ours / Grbl",
            "arcs exact / Grbl chords"]


def tables(quick: bool):
    """For `interp bench`: the table with the default machine (quick: the programs whose
    name has "ugs_"), nothing when there is no corpus."""
    rows, _, _ = corpus_rows(load_machine(), only="ugs_" if quick else None)
    if not rows:
        return []
    return [("Machine time: our planner against Grbl's (corpus, default machine)",
             _header(STREAM_WINDOW), [_cells(r) for r in rows] + [_total(rows)])]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m interp.benchmarks.machine_time",
                                     description=__doc__.split("\n")[0])
    parser.add_argument("--machine", help="machine file (default: the shipped default machine)")
    parser.add_argument("--window", type=int, default=STREAM_WINDOW, help="streaming look-ahead (segments)")
    parser.add_argument("--arc-tolerance", type=float, default=grbl_planner.DEFAULT_ARC_TOLERANCE,
                        help="Grbl's arc tolerance in mm (default 0.002)")
    parser.add_argument("--only", help="only programs whose name contains this text")
    args = parser.parse_args(argv)
    if args.window < 1:
        parser.error("--window must be >= 1")
    machine = load_machine(args.machine)
    if not corpus_files():
        print(f"no G-code corpus at {CORPUS} (set INTERP_GCODE_CORPUS)", file=sys.stderr)
        return 1
    print("| " + " | ".join(_header(args.window)) + " |")
    print("|---|---:|---:|---:|---:|---:|")
    rows, refused, reasons = corpus_rows(
        machine, window=args.window, only=args.only, arc_tolerance_mm=args.arc_tolerance,
        progress=lambda row: print("| " + " | ".join(_cells(row)) + " |", flush=True))
    print("| " + " | ".join(_total(rows)) + " |")
    sources = sorted({r.source for r in rows})
    print(f"\nour segments: from the {' and '.join(sources)}"
          + (" (this compiler does not plan its commands yet)" if sources == ["moves"] else ""))
    for line in refused:
        print(f"refused: {line}")
    slower_window = [r for r in rows if r.window_s > r.grbl_s * (1 + SLOWER)]
    print(f"\nwhole-program plan slower than Grbl (by more than {SLOWER:g}) on {len(reasons)} of "
          f"{len(rows)} programs" + (":" if reasons else ""))
    for line in reasons:
        print(f"- {line}")
    print(f"window {args.window} slower than Grbl on {len(slower_window)} of {len(rows)} programs"
          + (": " + ", ".join(r.name for r in slower_window) if slower_window else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
