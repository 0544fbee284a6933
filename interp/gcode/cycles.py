# SPDX-License-Identifier: Apache-2.0
"""Canned cycles G73, G81, G82, G83, G85, G86, G89, expanded into rapids, feeds, dwells and
(G86) spindle stops.

The expansion follows LinuxCNC's interpreter (RS274NGC).  Everything here is in
machine millimetres along the cycle's axes: `aa` and `bb` are the plane's first
and second axes (X and Y under G17, Z and X under G18, Y and Z under G19), `cc`
the axis normal to it (Z, Y, X), the axis the tool drills along.

Per repeat (L word), the tool first moves in the plane to the hole: on the first
repeat at its current height if that is above the R plane, otherwise at the
clearance height (R under G99, the initial level under G98), and then straight
down to R.  Then the cycle itself:

G81  feed to the bottom, rapid out to the clearance height.
G82  feed to the bottom, dwell P seconds, rapid out.
G83  peck: feed down by Q, rapid out to R, rapid back down to 0.254 mm
     (0.010 inch) above the depth reached, feed on by Q; at the bottom rapid out.
G73  chip break: feed down by Q, rapid back 0.254 mm (0.010 inch), feed on by Q;
     at the bottom rapid out.
G85  feed to the bottom, feed back to R, rapid to the clearance height.
G86  feed to the bottom, dwell P seconds, stop the spindle, rapid out, start the spindle
     again in the direction it turned.
G89  feed to the bottom, dwell P seconds, feed out to the clearance height.
"""
from __future__ import annotations

from collections.abc import Iterator

# LinuxCNC 2.9's G83_RAPID_DELTA, 0.010 inch, in mm (used for both G73 and G83).
PECK_CLEARANCE_MM = 0.254

CYCLES = (73, 81, 82, 83, 85, 86, 89)


def expand(code: int, *, axes: tuple[int, int, int], start: tuple[float, float, float],
           holes: list[tuple[float, float]], r: float, bottom: float, clear: float,
           q: float = 0.0, p: float = 0.0) -> Iterator[tuple[str, object]]:
    """Yield ("rapid", point), ("feed", point), ("dwell", seconds) and ("spindle", on) steps.

    axes: the machine axis indices of (aa, bb, cc); start: the machine position
    before the cycle (after any rise to R); holes: (aa, bb) of each repeat;
    r, bottom, clear: cc heights of the R plane, the hole's bottom and the
    retract height.
    """
    ia, ib, ic = axes
    position = list(start)

    def point(a: float, b: float, c: float) -> tuple[float, float, float]:
        result = list(position)
        result[ia], result[ib], result[ic] = a, b, c
        return tuple(result)

    for repeat, (a, b) in enumerate(holes):
        current = position[ic]
        if repeat == 0 and current > r:
            yield "rapid", point(a, b, current)
            yield "rapid", point(a, b, r)
        else:
            yield "rapid", point(a, b, clear)
            if clear > r:
                yield "rapid", point(a, b, r)
        if code == 81:
            yield "feed", point(a, b, bottom)
            yield "rapid", point(a, b, clear)
        elif code == 82:
            yield "feed", point(a, b, bottom)
            yield "dwell", p
            yield "rapid", point(a, b, clear)
        elif code in (73, 83):
            depth = r - q
            while depth > bottom:
                yield "feed", point(a, b, depth)
                if code == 83:
                    yield "rapid", point(a, b, r)
                yield "rapid", point(a, b, depth + PECK_CLEARANCE_MM)
                depth -= q
            yield "feed", point(a, b, bottom)
            yield "rapid", point(a, b, clear)
        elif code == 85:
            yield "feed", point(a, b, bottom)
            yield "feed", point(a, b, r)
            yield "rapid", point(a, b, clear)
        elif code == 86:
            yield "feed", point(a, b, bottom)
            yield "dwell", p
            yield "spindle", False
            yield "rapid", point(a, b, clear)
            yield "spindle", True
        elif code == 89:
            yield "feed", point(a, b, bottom)
            yield "dwell", p
            yield "feed", point(a, b, clear)
        else:
            raise ValueError(f"not a canned cycle: G{code}")
        position[ia], position[ib], position[ic] = a, b, clear
