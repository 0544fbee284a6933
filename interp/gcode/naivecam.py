# SPDX-License-Identifier: Apache-2.0
"""LinuxCNC's naive CAM detector (G64 P- Q-): a run of straight feed moves that stays within
the tolerance Q of one straight line runs as that line.

CAM programs often cut a straight or gently curved stretch as many short G1 moves; each
junction between them costs the planner a slowdown, and each move costs a record on the
link.  In G64 with a naive-CAM tolerance (Q, or P when Q is not given; G64 alone, Q0,
G61 and G61.1 turn it off), LinuxCNC's canonical layer joins such moves, and so does the
compiler (docs/gcode-cli.md, "Joined moves"):

  * a chain starts at a straight feed move (G1, not a probe) made under a tolerance and
    takes the next move while that move is also one, at the same feed (mm/min; under G93
    each move's own rate), under the same path-control block with no message between
    them in the order the program runs (the interpreter marks each move: Line.join),
    starting where the chain ends and not ending where it started, the chain holds at
    most MAX_CHAIN moves, and every end point of the chain lies within the tolerance of
    the segment from the chain's start to the new move's end;
  * anything else (a rapid, an arc, a probe, a dwell, an event: spindle, coolant,
    outputs, pauses, a laser's power; a move of a run from a line's approach) ends the
    chain; the chain runs as one line from its start to its last end point;
  * a joined line counts as its first move's line (LinuxCNC reports the last), so an
    error, the progress display and a run from a line name where the line began.

Positions are machine millimetres, as the interpreter gives them; the test is LinuxCNC's
(emccanon.cc linkable()): each end point's distance to the segment, the foot of the
perpendicular clamped to the segment's ends.
"""
from __future__ import annotations

import math
from dataclasses import replace

from .moves import Line

MAX_CHAIN = 101         # LinuxCNC's chain takes no more once it holds more than 100 points


def distance_to_segment(point, start, end) -> float:
    """The distance from point to the segment start .. end (to start when it has no length)."""
    m = [e - s for e, s in zip(end, start)]
    d = [p - s for p, s in zip(point, start)]
    mm = sum(c * c for c in m)
    t = 0.0 if mm == 0 else min(1.0, max(0.0, sum(a * b for a, b in zip(m, d)) / mm))
    return math.sqrt(sum((dc - t * mc) ** 2 for dc, mc in zip(d, m)))


def collapse(moves) -> tuple[list, int]:
    """(the moves with every chain joined into one line, how many moves the joining removed).
    A move may join the chain before it when the interpreter marked it (Line.join: the chain
    count and the tolerance in force when it was made, in the order the program runs)."""
    out: list = []
    chain: list[Line] = []
    removed = 0

    def flush() -> None:
        nonlocal removed
        if len(chain) > 1:
            out.append(replace(chain[0], end=chain[-1].end))
            removed += len(chain) - 1
        elif chain:
            out.append(chain[0])
        chain.clear()

    for move in moves:
        join = getattr(move, "join", None)
        if join is None:
            flush()
            out.append(move)
            continue
        first = chain[0] if chain else None
        if (first is not None and (move.feed, join) == (first.feed, first.join) and len(chain) < MAX_CHAIN
                and move.start == chain[-1].end and move.end != first.start
                and all(distance_to_segment(m.end, first.start, move.end) <= join[1] for m in chain)):
            chain.append(move)
            continue
        flush()
        chain.append(move)
    flush()
    return out, removed
