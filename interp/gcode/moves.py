# SPDX-License-Identifier: Apache-2.0
"""What the G-code interpreter hands to the compiler: moves in machine coordinates.

Every position is in millimetres in the machine frame (work offsets, G92, tool
length and units already applied), as (x, y, z).  Feeds are path speeds in
mm/min (G93 inverse time is already turned into one per move); `feed=None`
on a Line means a rapid (G0): the compiler uses the axes' maximum rates.
`line` is the 1-based line number of the block in the source file, for messages.
"""
from __future__ import annotations

from dataclasses import dataclass, field

Point = tuple[float, float, float]
# a move's origin: the program's line outside any subroutine that made it (run from a line);
# not part of a move's value (equality, hash, repr)
def _origin():
    return field(default=0, compare=False, repr=False)


# a motion's path-control mode: ("G61" | "G61.1" | "G64", G64's P corner tolerance in mm or
# None), the mode in force when the program ran its block (in run order: a subroutine's or a
# loop's G64 holds for the moves made after it); not part of a move's value
CONTINUOUS = ("G64", None)


def _path_control():
    return field(default=CONTINUOUS, compare=False, repr=False)


# a piece of the programmed move before it (a G5 curve's arcs and lines after its first):
# no exact stop before it under G61 / G61.1; not part of a move's value
def _continues():
    return field(default=False, compare=False, repr=False)


# Arc planes as RS274NGC defines them: (u, v) is the plane, w its normal;
# counter-clockwise turns from +u towards +v.
PLANES = {"XY": (0, 1, 2), "ZX": (2, 0, 1), "YZ": (1, 2, 0)}      # G17, G18, G19


@dataclass(frozen=True)
class Line:
    start: Point
    end: Point
    feed: float | None          # mm/min; None = rapid
    line: int
    probe: int = 0              # 382 .. 385: a G38.2 .. G38.5 probe move (stops where the probe trips)
    origin: int = _origin()     # (all moves) the program's line outside any subroutine that made it
    # a G1 move made under a naive-CAM tolerance (interp.gcode.naivecam): (the chain it may
    # join: a count the interpreter advances at every path-control block and message, the
    # tolerance in mm), in the order the program runs; None: it joins nothing
    join: tuple[int, float] | None = field(default=None, compare=False, repr=False)
    path_control: tuple[str, float | None] = _path_control()
    continues: bool = _continues()


@dataclass(frozen=True)
class ProbeResult:
    """What a probe move did on the machine: touched (the probe tripped: it touched, or for
    G38.4 / G38.5 lost contact), where (the probe's latch) and where the machine came to rest
    (machine mm)."""
    touched: bool
    trip: Point
    stop: Point


@dataclass(frozen=True)
class Arc:
    start: Point
    end: Point                  # the normal coordinate may differ from start's: a helix
    centre: Point               # the normal coordinate equals start's
    plane: str                  # "XY" (G17), "ZX" (G18), "YZ" (G19)
    ccw: bool                   # G3
    turns: int                  # P word: 1 = up to one revolution; n > 1 adds n - 1 full turns
    feed: float
    line: int
    origin: int = _origin()
    path_control: tuple[str, float | None] = _path_control()
    continues: bool = _continues()


@dataclass(frozen=True)
class Dwell:
    seconds: float
    line: int
    origin: int = _origin()


# Event names and what their value is (the compiler gives each a hardware code):
EVENTS = {
    "spindle_cw": "S (rpm or laser power)",        # M3
    "spindle_ccw": "S",                            # M4
    "spindle_off": "0",                            # M5
    "spindle_speed": "S",                          # S changed while the spindle runs
    "mist_on": "0",                                # M7
    "flood_on": "0",                               # M8
    "coolant_off": "0",                            # M9
    "output_on": "P (output number)",              # M62 / M64
    "output_off": "P",                             # M63 / M65
    "pause": "0 (M0), 1 (M1), 6 (M6 tool change), 60 (M60)",
    "tool_change": "T (the tool selected)",        # M6, before its pause
    "program_end": "2 (M2) or 30 (M30)",
    "laser_mode": "1 on, 0 off (sent by the compiler in laser mode, not programmed)",
}


@dataclass(frozen=True)
class Event:
    name: str                   # a key of EVENTS
    value: float
    line: int
    origin: int = _origin()


Move = Line | Arc | Dwell | Event


@dataclass
class Program:
    moves: list[Move] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)       # "line N: ..." each
    messages: list[str] = field(default_factory=list)       # (MSG, ...) texts, "line N: text"
    end_work: Point = (0.0, 0.0, 0.0)     # final position in work coordinates, program units
    units: str = "mm"                     # the units in force at the end: "mm" or "inch"
    end_machine: Point = (0.0, 0.0, 0.0)  # final position in machine coordinates, mm
    # the persistent parameters at the end (#5161.. G28, #5181.. G30, #5210.. G92, #5220 the
    # coordinate system, #5221.. G54..G59.3), machine mm: what a parameter file keeps
    saved: dict[int, float] = field(default_factory=dict)
    # interpretation stopped after a probe move whose result is not known yet (interpret's probes)
    probe_pending: bool = False
    # run from a line (restart.start_at): for each message, the program's line outside any
    # subroutine that ran it (a call's line for a subroutine's; each move carries its own
    # origin); the program's own subroutines as (label, first line, last line); what the
    # start line found
    message_origins: list[tuple[int, int]] = field(default_factory=list)    # (moves before it, line)
    subroutines: list[tuple[str, int, int]] = field(default_factory=list)
    restart: object = None
