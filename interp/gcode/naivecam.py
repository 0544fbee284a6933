# SPDX-License-Identifier: Apache-2.0
"""LinuxCNC's naive CAM detector (G64 P- Q-): a run of straight feed moves that stays within
the tolerance Q of one straight line runs as that line.

CAM programs often cut a straight or gently curved stretch as many short G1 moves; each
junction between them costs the planner a slowdown, and each move costs a record on the
link.  In G64 with a naive-CAM tolerance (Q, or P when Q is not given; G64 alone, Q0,
G61 and G61.1 turn it off), LinuxCNC's canonical layer joins such moves, and so does the
compiler (docs/gcode-cli.md, "Joined moves"):

  * a chain starts at a straight feed move (G1, not a probe) and takes the next move
    while that move is also a straight feed move at the same programmed F, in the same
    path-control mode (the same G64 block), starting where the chain ends, the chain
    holds at most MAX_CHAIN moves, and every end point of the chain lies within the
    tolerance of the segment from the chain's start to the new move's end;
  * anything else (a rapid, an arc, a probe, a dwell, an event: spindle, coolant,
    outputs, pauses, a laser's power) ends the chain; the chain runs as one line from its
    start to its last end point;
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


def naive_tolerance(modes, line: int) -> tuple[int, float]:
    """(the index of the path-control entry in force on `line`, its naive-CAM tolerance in
    mm: Q, else P, for G64; 0 for G61, G61.1, G64 alone or before any entry).  modes: the
    program's path_modes sorted by line, (line, mode, P, Q)."""
    index, tolerance = -1, 0.0
    for k, (at, name, p, q) in enumerate(modes):
        if at > line:
            break
        index = k
        tolerance = (q if q is not None else p if p is not None else 0.0) if name == "G64" else 0.0
    return index, tolerance


def distance_to_segment(point, start, end) -> float:
    """The distance from point to the segment start .. end (to start when it has no length)."""
    m = [e - s for e, s in zip(end, start)]
    d = [p - s for p, s in zip(point, start)]
    mm = sum(c * c for c in m)
    t = 0.0 if mm == 0 else min(1.0, max(0.0, sum(a * b for a, b in zip(m, d)) / mm))
    return math.sqrt(sum((dc - t * mc) ** 2 for dc, mc in zip(d, m)))


def _joinable(move) -> bool:
    return isinstance(move, Line) and move.feed is not None and not move.probe


def collapse(moves, modes) -> tuple[list, int]:
    """(the moves with every chain joined into one line, how many moves the joining removed).
    modes: the program's path_modes sorted by line."""
    out: list = []
    chain: list[Line] = []
    key = None                      # (F, the mode entry) of the chain
    tolerance = 0.0
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
        if not _joinable(move):
            flush()
            out.append(move)
            continue
        index, q = naive_tolerance(modes, move.line)
        this = (move.feed, index)
        if (chain and this == key and q > 0 and len(chain) < MAX_CHAIN and move.start == chain[-1].end
                and all(distance_to_segment(m.end, chain[0].start, move.end) <= tolerance for m in chain)):
            chain.append(move)
            continue
        flush()
        if q > 0:
            chain.append(move)
            key, tolerance = this, q
        else:
            out.append(move)
    flush()
    return out, removed
