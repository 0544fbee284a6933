# SPDX-License-Identifier: Apache-2.0
"""Run from a line: a program's moves from a given line on, with the state the lines
before it left and a safe approach to where the machine stood there.

After a broken tool or an e-stop the operator restarts a program part-way, as LinuxCNC's
"run from line" and the Grbl senders' "start from line" do.  The whole program is
interpreted (so modes, offsets, tool length, cutter compensation and loops are as they
were); the moves before the start are dropped, and in their place come:

1. the state they left: the spindle (M3 / M4 with its S), coolant (M7, M8) and the
   digital outputs they changed (M62 .. M65);
2. the approach from where the machine is to where the program stood when it reached the
   start: straight up to the clearance (the highest Z the machine or the dropped moves
   reached), across at that height, down as a rapid to the height of the last rapid before
   the start (the program's retract height), and from there down at the program's plunge
   feed (its last feed move down before the start; else the first feed move from the start
   on, else the last one before it); each leg only where it moves.

The run starts at the first move, in the order the program runs, whose line is the start
line or a later one (in a loop: its first pass).  Dropped probe moves are refused: what they
measured decides the moves after them.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

from ..cores import UsageError
from .moves import Arc, Event, Line, Point, Program


@dataclass(frozen=True)
class Restart:
    """What the start line finds: the tool last changed to (None: no M6 dropped), the
    spindle ("M3" / "M4" / None) and its S, the coolant ("mist", "flood"), the outputs
    set (P -> on), and the approach's points and feed (mm/min; None: rapid)."""
    line: int
    tool: int | None
    spindle: str | None
    speed: float
    coolant: tuple[str, ...]
    outputs: dict[int, bool]
    approach: tuple[Point, ...]
    feed: float | None

    def describe(self) -> str:
        """One line for the operator: what was restored and how the machine gets there."""
        parts = []
        if self.tool is not None:
            parts.append(f"tool {self.tool} (the last M6 before it: load it first)")
        parts.append(f"spindle {self.spindle} S{self.speed:g}" if self.spindle else "spindle off")
        parts.append("coolant " + " and ".join(self.coolant) if self.coolant else "coolant off")
        if self.outputs:
            parts.append("outputs " + ", ".join(f"{p} {'on' if on else 'off'}" for p, on in sorted(self.outputs.items())))
        if self.approach:
            x, y, z = self.approach[-1]
            how = f"at F{self.feed:g}" if self.feed is not None else "as rapids"
            parts.append(f"approach in {len(self.approach)} moves to X{x:g} Y{y:g} Z{z:g} (machine mm) {how}")
        else:
            parts.append("no approach (the machine is there)")
        return f"starting at line {self.line}: " + "; ".join(parts)


def _motion(move) -> bool:
    return isinstance(move, (Line, Arc))


def start_at(program: Program, line: int, here: Point) -> Program:
    """The program run from `line` on, the machine at `here` (machine mm): a Program whose
    moves are the restored state, the approach and the moves from the start on, its
    `restart` what was done (a Restart), the rest as interpreted.  UsageError (one line) when no move is at or after
    the line, or when a probe move comes before it."""
    if line < 1:
        raise UsageError(f"--start-line {line}: lines count from 1")
    moves = program.moves
    first = next((k for k, move in enumerate(moves) if move.line >= line), None)
    if first is None:
        if program.probe_pending:
            _refuse_probe(line, moves[-1])
        last = moves[-1].line if moves else 0
        raise UsageError(f"--start-line {line}: the program has no move or event there or after it "
                         f"(its last is at line {last})")
    tool, spindle, speed, mist, flood, outputs = None, None, 0.0, False, False, {}
    top, position, fed, plunge, retract = here[2], tuple(here), None, None, None
    for move in moves[:first]:
        if isinstance(move, Line) and move.probe:
            _refuse_probe(line, move)
        if _motion(move):
            top, position = max(top, move.start[2], move.end[2]), move.end
            if isinstance(move, Line) and move.feed is None:
                retract = move.end[2]                       # the last rapid's height
            fed = move.feed if move.feed is not None else fed
            if isinstance(move, Line) and move.feed is not None and move.end[2] < move.start[2]:
                plunge = move.feed
        elif isinstance(move, Event):
            name, value = move.name, move.value
            if name in ("spindle_cw", "spindle_ccw"):
                spindle, speed = ("M3" if name == "spindle_cw" else "M4"), value
            elif name == "spindle_speed":
                speed = value
            elif name == "spindle_off":
                spindle = None
            elif name == "mist_on":
                mist = True
            elif name == "flood_on":
                flood = True
            elif name == "coolant_off":
                mist = flood = False
            elif name in ("output_on", "output_off"):
                outputs[int(value)] = name == "output_on"
            elif name == "tool_change":
                tool = int(value)
    feed = plunge or next((m.feed for m in moves[first:] if _motion(m) and m.feed is not None), fed)
    top = max(top, position[2])
    floor = top if retract is None else min(top, max(retract, position[2]))
    legs = [((here[0], here[1], top), None), ((position[0], position[1], top), None),
            ((position[0], position[1], floor), None), (position, feed)]
    approach, at = [], tuple(here)
    for point, rate in legs:                # up, across and down to the retract height as rapids
        if point != at:
            approach.append(Line(at, point, rate, line))
            at = point
    points = [move.end for move in approach]
    restored = [Event(f"output_{'on' if on else 'off'}", p, line) for p, on in sorted(outputs.items())]
    if spindle:
        restored.append(Event("spindle_cw" if spindle == "M3" else "spindle_ccw", speed, line))
    restored += [Event(name, 0.0, line) for name, on in (("mist_on", mist), ("flood_on", flood)) if on]
    descent = next((move.feed for move in approach if move.feed is not None), None)
    info = Restart(line, tool, spindle, speed, tuple(name for name, on in (("mist", mist), ("flood", flood)) if on),
                   outputs, tuple(points), descent)
    return replace(program, moves=restored + approach + list(moves[first:]), restart=info,
                   messages=[m for m in program.messages if _line_of(m) >= line])


def _refuse_probe(line: int, move: Line):
    raise UsageError(f"--start-line {line}: line {move.line} probes (G38.{move.probe - 380}) before it, and what "
                     "it measures decides the moves after it; start at the probe or before it")


def _line_of(text: str) -> int:
    head = text.split(":", 1)[0]
    return int(head[5:]) if head.startswith("line ") and head[5:].isdigit() else 0

