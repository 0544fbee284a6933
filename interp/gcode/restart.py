# SPDX-License-Identifier: Apache-2.0
"""Run from a line: a program's moves from a given line on, with the state the lines
before it left and a safe approach to where the machine stood there.

After a broken tool or an e-stop the operator restarts a program part-way, as LinuxCNC's
"run from line" and the Grbl senders' "start from line" do.  The whole program is
interpreted (so modes, offsets, tool length, cutter compensation and loops are as they
were); the moves before the start are dropped, and in their place come:

1. the digital outputs they set (M62 .. M65), and, if they changed the tool (M6), that
   tool change's pause, so that the operator loads the tool before anything moves (not
   when the run itself starts with a tool change);
2. the approach from where the machine is to where the program stood when it reached the
   start, each leg only where it moves: straight up to the clearance (the highest Z the
   machine or the dropped moves reached) and across at that height, as rapids; then the
   spindle (M3 / M4 at its last S) and coolant they left, with the longest dwell that
   followed the spindle's start or a new S (its spin-up); then down as a rapid to the height of the last rapid
   before the start (the program's retract height), and from there at the program's plunge
   feed: its last straight feed move down before the start, else the first feed move from
   the start on, else the last feed move before it.  On a laser (laser mode) the approach
   is all rapids and the beam's M3 / M4 comes after it, just before the first move or
   spindle word from the start on, and no spin-up dwell is kept: the beam stays dark until
   the first feed move.

The run starts at the first move or event that the program's line `line` runs, or a later
one: in the order the program runs them, the first whose line outside any subroutine is
`line` or later (a subroutine's moves count with the line of their call; in a loop: its
first pass).  Refused with one line: a line inside a subroutine's body, a probe move
before the start (what it measured decides the moves after it), and a program whose moves
from the start on depend on where it started (G92 or G10 L20 from where the machine
stood, incremental moves from the start: interpret_program checks that with same_from,
interpreting the program from two other starts).
"""
from __future__ import annotations

from dataclasses import dataclass, replace

from ..cores import UsageError
from .moves import CONTINUOUS, Arc, Dwell, Event, Line, Point, Program

SPINDLE_EVENTS = ("spindle_cw", "spindle_ccw", "spindle_off", "spindle_speed")


@dataclass(frozen=True)
class Restart:
    """What the start line finds: the tool last changed to (None: no M6 dropped; then its
    pause comes first), the spindle ("M3" / "M4" / None), its S and spin-up dwell (s), the
    coolant ("mist", "flood"), the outputs set (P -> on), and the approach's points and
    descent feed (mm/min; None: rapids only)."""
    line: int
    tool: int | None
    spindle: str | None
    speed: float
    spin_up: float
    coolant: tuple[str, ...]
    outputs: dict[int, bool]
    approach: tuple[Point, ...]
    feed: float | None

    def describe(self) -> str:
        """One line for the operator: what was restored and how the machine gets there."""
        parts = []
        if self.tool is not None:
            parts.append(f"tool {self.tool}: the program pauses first for its M6")
        spindle = f"spindle {self.spindle} S{self.speed:g}" if self.spindle else "spindle off"
        parts.append(spindle + (f" and {self.spin_up:g} s to spin up" if self.spindle and self.spin_up else ""))
        parts.append("coolant " + " and ".join(self.coolant) if self.coolant else "coolant off")
        if self.outputs:
            parts.append("outputs " + ", ".join(f"{p} {'on' if on else 'off'}" for p, on in sorted(self.outputs.items())))
        if self.approach:
            x, y, z = self.approach[-1]
            how = f"the last at F{self.feed:g}" if self.feed is not None else "as rapids"
            count = f"{len(self.approach)} move{'s' if len(self.approach) > 1 else ''}"
            parts.append(f"approach in {count} to X{x:g} Y{y:g} Z{z:g} (machine mm), {how}")
        else:
            parts.append("no approach (the machine is there)")
        return f"starting at line {self.line}: " + "; ".join(parts)


def _motion(move) -> bool:
    return isinstance(move, (Line, Arc))


def start_index(program: Program, line: int) -> int | None:
    """The index of the first move the run from `line` keeps (None: none is at or after it)."""
    return next((k for k, m in enumerate(program.moves) if (m.origin or m.line) >= line), None)


def start_at(program: Program, line: int, here: Point, laser: bool = False) -> Program:
    """The program run from `line` on, the machine at `here` (machine mm; laser: the
    machine's laser mode): a Program whose moves are the restored state, the approach and
    the moves from the start on, its `restart` what was done (a Restart), the rest as
    interpreted.  UsageError (one line) for a line below 1, in a subroutine's body or with no
    move at or after it, and for a probe move before it."""
    if line < 1:
        raise UsageError(f"--start-line {line}: lines count from 1")
    for label, begin, end in program.subroutines:
        if begin <= line <= end:
            raise UsageError(f"--start-line {line}: the line is in subroutine {label} (lines {begin} .. {end}); "
                             "start at a line outside it (a call runs it from its first line)")
    moves = program.moves
    first = start_index(program, line)
    if first is None:
        if program.probe_pending:
            _refuse_probe(line, moves[-1])
        last = moves[-1].line if moves else 0
        raise UsageError(f"--start-line {line}: the program has no move or event there or after it "
                         f"(its last is at line {last})")
    state = _Dropped(here)
    for move in moves[:first]:
        if isinstance(move, Line) and move.probe:
            _refuse_probe(line, move)
        state.take(move)
    position = state.position
    feed = state.plunge or next((m.feed for m in moves[first:] if _motion(m) and m.feed is not None), state.fed)
    top = max(state.top, position[2])
    floor = top if state.retract is None else min(top, max(state.retract, position[2]))
    legs = [((here[0], here[1], top), None), ((position[0], position[1], top), None),
            ((position[0], position[1], floor), None), (position, None if laser else feed)]
    control = next((m.path_control for m in moves[first:] if _motion(m)), CONTINUOUS)   # (the mode at the start)
    approach, at = [], tuple(here)
    for point, rate in legs:
        if point != at:
            approach.append(Line(at, point, rate, line, path_control=control))
            at = point
    ups = next((k for k, move in enumerate(approach) if move.end[2] < top), len(approach))     # up and across
    spindle, coolant = state.spindle, tuple(name for name in ("mist", "flood") if getattr(state, name))
    spin_up = state.spin_up if spindle and not laser else 0.0
    spin = []                                                           # spindle, coolant, spin-up
    if spindle:
        spin.append(Event("spindle_cw" if spindle == "M3" else "spindle_ccw", state.speed, line))
    spin += [Event(f"{name}_on", 0.0, line) for name in coolant]
    if spin_up:
        spin.append(Dwell(spin_up, line))
    restored = [Event(f"output_{'on' if on else 'off'}", p, line) for p, on in sorted(state.outputs.items())]
    kept = list(moves[first:])
    changes = next((isinstance(m, Event) and m.name == "tool_change" for m in kept
                    if _motion(m) or isinstance(m, Event) and m.name == "tool_change"), False)
    if state.tool is not None and not changes:  # (a run from an M6 line changes the tool itself)
        restored += [Event("tool_change", float(state.tool), line), Event("pause", 6.0, line)]
    if laser:                               # the beam on where the run moves on from
        at_spin = next((k for k, m in enumerate(kept) if _motion(m) or (isinstance(m, Event)
                                                                          and m.name in SPINDLE_EVENTS)), len(kept))
        run = restored + approach + kept[:at_spin] + spin + kept[at_spin:]
    else:
        run = restored + approach[:ups] + spin + approach[ups:] + kept
    info = Restart(line, None if changes else state.tool, spindle, state.speed, spin_up, coolant, state.outputs,
                   tuple(move.end for move in approach),
                   next((move.feed for move in approach if move.feed is not None), None))
    messages = program.messages
    if len(program.message_origins) == len(messages):   # those the run from the start shows
        messages = [text for text, (made, origin) in zip(messages, program.message_origins)
                    if made > first or (made == first and origin >= line)]
    run = [m if m.origin else replace(m, origin=line) for m in run]    # (the restored state's, the approach's)
    return replace(program, moves=run, restart=info, messages=messages)


def same_from(one: Program, other: Program, line: int, starts: tuple[Point, Point]) -> bool:
    """Whether two interpretations of a program, from the two `starts`, run the same path from
    `line` on: the same point where the run from `line` begins, then the same ends (and arc
    centres), zero-length moves aside; else the run from there depends on where the program
    started.  An axis the program has not yet taken away from its start (one it has not
    programmed yet, a laser's Z) stays where the machine is, as a run from the first line
    would leave it: it is not compared.  True when the run from `line` drops nothing."""
    first = start_index(one, line)
    if not first:
        return True
    return _path(one, line, starts[0]) == _path(other, line, starts[1])


def _path(program: Program, line: int, start: Point) -> list | None:
    """The points the run from `line` passes through (see same_from), or None without one."""
    first = start_index(program, line)
    if first is None:
        return None
    moved, at, points = [False, False, False], (None, None, None), []
    for k, move in enumerate(program.moves):
        if not _motion(move):
            continue
        moved = [was or end != begin for was, end, begin in zip(moved, move.end, start)]
        end = tuple(value if was else None for value, was in zip(move.end, moved))
        if k < first:
            at = end
            continue
        centre = tuple(value if was else None for value, was in zip(move.centre, moved)) \
            if isinstance(move, Arc) else None
        if not points:
            points.append((at, None))
        if centre is not None or end != points[-1][0]:
            points.append((end, centre))
    return points or [(at, None)]


class _Dropped:
    """What the dropped moves leave: tool, spindle and its spin-up dwell (the longest dwell
    right after its start or a new S since it started), coolant, outputs,
    and for the approach the highest Z, the last point, the last rapid's height, the last
    straight feed move down's feed and the last feed."""

    def __init__(self, here: Point):
        self.tool, self.spindle, self.speed, self.spin_up = None, None, 0.0, 0.0
        self.mist = self.flood = self.spinning = False   # spinning: M3 / M4 and nothing moved since
        self.outputs: dict[int, bool] = {}
        self.top, self.position = here[2], tuple(here)
        self.retract = self.plunge = self.fed = None

    def take(self, move) -> None:
        if _motion(move):
            self.top, self.position, self.spinning = max(self.top, move.start[2], move.end[2]), move.end, False
            if isinstance(move, Line) and move.feed is None:
                self.retract = move.end[2]
            self.fed = move.feed if move.feed is not None else self.fed
            if isinstance(move, Line) and move.feed is not None and move.end[2] < move.start[2]:
                self.plunge = move.feed
        elif isinstance(move, Dwell):
            if self.spinning:                       # the longest wait after a start or a new S
                self.spin_up, self.spinning = max(self.spin_up, move.seconds), False
        elif isinstance(move, Event):
            name, value = move.name, move.value
            if name in ("spindle_cw", "spindle_ccw"):
                turning = "M3" if name == "spindle_cw" else "M4"
                if self.spindle != turning:         # a start (not a new S while it turns that way)
                    self.spin_up = 0.0
                self.spindle, self.speed, self.spinning = turning, value, True
            elif name == "spindle_speed":
                self.speed, self.spinning = value, self.spindle is not None
            elif name == "spindle_off":
                self.spindle, self.spinning = None, False
            elif name in ("mist_on", "flood_on"):
                setattr(self, name[:-3], True)
            elif name == "coolant_off":
                self.mist = self.flood = False
            elif name in ("output_on", "output_off"):
                self.outputs[int(value)] = name == "output_on"
            elif name == "tool_change":
                self.tool = int(value)


def _refuse_probe(line: int, move: Line):
    raise UsageError(f"--start-line {line}: line {move.line} probes (G38.{move.probe - 380}) before it, and what "
                     "it measures decides the moves after it; start at the probe or before it")
