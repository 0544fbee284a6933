# SPDX-License-Identifier: Apache-2.0
"""Exact step-event counts of motion_top's commands, without running the models.

The speed block paces step EVENTS (a step on one, two or three axes at once is
one event), so the host needs N, the exact number of events of each command:

  * a LINE (two SU 1571551 lines sharing the leading axis): N = max |d|;
  * an ARC (rtl/circ_arc.v, model interp.models.arc.arc_steps): every step moves
    the leading axis of its octant by one, so N is the travel of the leading
    coordinate summed over the octants.  Inside an octant, away from its
    diagonals, the core's point is (u, round(sqrt(R^2 - u^2))) exactly (R^2 is an
    integer: the start is on the circle; the midpoint test never ties, so the
    midpoint choice IS that rounding while the ideal minor coordinate moves by
    under one per step).  `arc_count` therefore jumps over each octant's
    interior in one step and runs the core's own step rule (integers) only
    near the diagonals and near the end ray: a full circle of any radius costs
    a few dozen rule steps and a few integer square roots.  `arc_events` also
    counts the diagonal (two-axis) steps, for the lecture's step costs;
  * a HELIX (rtl/arc_plane.v): line core A spreads the w travel over `count`
    ticks, one per arc step, and the w travel left at the arc's end follows one
    step per event: N = (arc steps) + (w travel) - (w steps that coincide with
    arc steps); with count = the exact arc step count that is max(arc, |w|).

Every function is checked against the models (tests/test_gcode_compile.py).
"""
from __future__ import annotations

from math import isqrt

SMALL_R2 = 64           # radii below 8 steps: the rule step by step


def rounded_root(n: int) -> int:
    """round(sqrt(n)) for n >= 0 (no ties: sqrt(n) is never k + 1/2)."""
    r = isqrt(n)
    return r + 1 if n - r * r > r else r


def _sign(value: int) -> int:
    return (value > 0) - (value < 0)


def _octant(u: int, v: int, ccw: bool):
    """As interp.models.arc._octant: (x_major, a, b)."""
    tx, ty = (-v, u) if ccw else (v, -u)
    x_major = abs(v) > abs(u) or (abs(v) == abs(u) and ((u * v > 0) == ccw))
    if x_major:
        return True, (_sign(tx), 0), (0, _sign(ty) or -_sign(v))
    return False, (0, _sign(ty)), (_sign(tx) or -_sign(u), 0)


def _rule(u: int, v: int, u1: int, v1: int, r2: int, ccw: bool) -> tuple[int, int, bool]:
    """One step of the arc core from (u, v) (relative to the centre): the next point and
    whether it is the last (the core's rule in integers: 4 F(M) = (2u + 2a + b)^2 + ...)."""
    _, (ax, ay), (bx, by) = _octant(u, v, ccw)
    mid4 = (2 * (u + ax) + bx) ** 2 + (2 * (v + ay) + by) ** 2 - 4 * r2
    diag_is_outer = (u + ax + bx) ** 2 + (v + ay + by) ** 2 > (u + ax) ** 2 + (v + ay) ** 2
    dx, dy = (ax + bx, ay + by) if (mid4 < 0) == diag_is_outer else (ax, ay)
    turn = 1 if ccw else -1
    ahead = turn * (u * v1 - v * u1) > 0
    reached = turn * ((u + dx) * v1 - (v + dy) * u1) <= 0
    if ahead and reached and (u + dx) * u1 + (v + dy) * v1 > 0:
        return u1, v1, True
    return u + dx, v + dy, False


def _cross(turn: int, u: int, v: int, u1: int, v1: int) -> int:
    return turn * (u * v1 - v * u1)


def arc_count(ci: int, cj: int, x: int, y: int, ccw: bool) -> int:
    """Exact number of steps of the arc core for the command start (0, 0), centre (ci, cj),
    end (x, y) (a full circle when the end is the start), as interp.models.arc.arc_steps
    (the end within half a step of the circle: the core refuses the rest)."""
    return arc_events(ci, cj, x, y, ccw)[0]


def arc_events(ci: int, cj: int, x: int, y: int, ccw: bool) -> tuple[int, int]:
    """(steps, diagonal steps) of the arc core, as arc_count: a jump through an octant's
    interior moves the major coordinate by one a step and the minor one by 0 or 1, so its
    diagonal steps are the minor coordinate's travel (up to the axis and back down when
    the jump crosses it)."""
    u, v, u1, v1 = -ci, -cj, x - ci, y - cj
    r2 = u * u + v * v
    if r2 == 0:
        return 0, 0
    turn = 1 if ccw else -1
    n = diagonal = 0
    limit = isqrt(r2 // 2) - 3          # |major| <= limit: at least 2 from the diagonals
    while True:
        if r2 >= SMALL_R2:
            jump = _jump(u, v, u1, v1, r2, ccw, turn, limit)
            if jump:
                k, u, v, minor_travel = jump
                n += k
                diagonal += minor_travel
                continue
        nu, nv, last = _rule(u, v, u1, v1, r2, ccw)
        n += 1
        diagonal += nu != u and nv != v
        u, v = nu, nv
        if last:
            return n, diagonal


def _jump(u, v, u1, v1, r2, ccw, turn, limit):
    """(steps, u, v, the minor coordinate's travel) of a jump through the interior of the
    current octant, or None."""
    x_major, (ax, ay), _ = _octant(u, v, ccw)
    # (major, minor) coordinates and the unit step along the major one
    if x_major:
        major, minor, step = u, v, ax
    else:
        major, minor, step = v, u, ay
    if abs(major) > limit or minor == 0 or abs(minor) != rounded_root(r2 - major * major):
        return None
    s = _sign(minor)

    def point(m: int) -> tuple[int, int]:
        w = s * rounded_root(r2 - m * m)
        return (m, w) if x_major else (w, m)

    target = step * limit
    if (target - major) * step < 4:
        return None
    tu, tv = point(target)
    if _cross(turn, u, v, u1, v1) > 0 and _cross(turn, tu, tv, u1, v1) <= 0:
        # the end ray is within: the first point on or past it, by bisection (the cross
        # product changes sign once over the octant's interior)
        lo, hi = major, target                  # cross > 0 at lo, <= 0 at hi
        while abs(hi - lo) > 1:
            mid = (lo + hi) // 2
            pu, pv = point(mid)
            if _cross(turn, pu, pv, u1, v1) > 0:
                lo = mid
            else:
                hi = mid
        target = hi - 3 * step
        if (target - major) * step < 1:
            return None
        tu, tv = point(target)
    # |minor| = round(sqrt(r2 - m^2)) rises to m = 0 and falls after it
    height = rounded_root(r2 - major * major), rounded_root(r2 - target * target)
    if min(major, target) < 0 < max(major, target):
        travel = 2 * rounded_root(r2) - height[0] - height[1]
    else:
        travel = abs(height[1] - height[0])
    return (target - major) * step, tu, tv, travel


def helix_count(arc_steps: int, travel: int, count: int) -> int:
    """Events of a helix: `arc_steps` arc steps, w travel `travel`, core A's lead `count`."""
    w = abs(travel)
    if w == 0:
        return arc_steps
    lead = max(count, 0)
    ticks = min(arc_steps, max(lead, w))          # core A's steps that ride on arc steps
    together = spread_minor(lead, w, ticks)
    return arc_steps + w - together


def spread_minor(lead: int, travel: int, ticks: int) -> int:
    """w steps in the first `ticks` steps of su_steps(lead, travel) (travel >= 0)."""
    big, small = max(lead, travel), min(lead, travel)
    if big == 0 or ticks <= 0:
        return 0
    ticks = min(ticks, big)
    if travel >= lead:                          # w is the long axis: a step every tick
        return ticks
    # diagonals after j steps of expression (5), exact mode: the smallest d with
    # big - 2 small - 2 small j + 2 big d >= -2 small, i.e. d = ceil((2 small j - big) / 2 big)
    return max(0, -((big - 2 * small * ticks) // (2 * big)))


def line_count(dx: int, dy: int, dz: int) -> int:
    """Events of a LINE command."""
    return max(abs(dx), abs(dy), abs(dz))
