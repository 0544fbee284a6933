# SPDX-License-Identifier: Apache-2.0
"""G5 and G5.1 splines as arcs and lines.

LinuxCNC's G5 is a cubic Bézier curve in the XY plane from the current point P0 to
the end P3, with control points P1 = P0 + (I, J) and P2 = P3 + (P, Q); G5.1 is the
quadratic one with P1 = P0 + (I, J).  The hardware has lines and circular arcs, so
`pieces` cuts the curve into them, each within TOLERANCE_MM of the curve:

  * a piece of the parameter range [t0, t1] becomes a line from B(t0) to B(t1) if the
    curve there stays within the tolerance of that segment: checked exactly (the
    curve's distance from the chord's line and its travel along it are polynomials in
    t, whose extremes are at the ends or where their derivatives vanish);
  * else the circle through B(t0), B((t0 + t1) / 2) and B(t1) if the curve lies within
    the tolerance of it at SAMPLES points (checked against ARC_MARGIN of the tolerance,
    so that it holds between them) and turns one way along it (no wider than
    RADIUS_RATIO times its chord);
  * else the range is halved (at most DEPTH times; there a line).

The pieces join end to end at points of the curve, so the path is continuous and its
ends are the programmed ones exactly.  A curve that needs more than MAX_PIECES pieces
(control points far beyond any machine's travel) raises SplineError.
"""
from __future__ import annotations

import math

TOLERANCE_MM = 0.001        # every piece stays this close to the curve
SAMPLES = 32                # points checked inside each arc piece
ARC_MARGIN = 0.9            # ... against this share of the tolerance
DEPTH = 30                  # halvings of the parameter range at the most
RADIUS_RATIO = 1000.0       # an arc's radius at most this many chords (else a finer piece)
MAX_PIECES = 20_000         # pieces of one curve at the most

Point2 = tuple[float, float]


class SplineError(ValueError):
    """The curve needs more than MAX_PIECES pieces."""


def bezier(control: list[Point2], t: float) -> Point2:
    """The Bézier curve of the control points at t (0 .. 1), by de Casteljau's rule (its ends
    exactly the first and last control points)."""
    if t in (0.0, 1.0):
        return control[0] if t == 0.0 else control[-1]
    points = list(control)
    while len(points) > 1:
        points = [(a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t) for a, b in zip(points, points[1:])]
    return points[0]


def power_basis(control: list[Point2]) -> list[Point2]:
    """The curve as a polynomial: B(t) = sum of c[k] t^k (c[k] = C(n, k) times the k-th
    forward difference of the control points)."""
    n = len(control) - 1
    return [tuple(math.comb(n, k) * sum((-1) ** (k - i) * math.comb(k, i) * control[i][axis] for i in range(k + 1))
                  for axis in range(2)) for k in range(n + 1)]


def _extremes(coefficients: list[float], t0: float, t1: float) -> list[float]:
    """The values of the polynomial (coefficients by power) at t0, t1 and where its derivative
    vanishes between them."""
    def value(t):
        return sum(c * t ** k for k, c in enumerate(coefficients))
    d = [k * c for k, c in enumerate(coefficients)][1:] + [0.0, 0.0]      # derivative, padded
    c0, c1, c2 = d[0], d[1], d[2]
    disc = c1 * c1 - 4 * c2 * c0
    roots = []
    if disc >= 0 and (c1 != 0 or c2 != 0):
        # the stable form: q = -(c1 + sign(c1) sqrt(disc)) / 2, roots q / c2 and c0 / q (a
        # nearly vanishing c2, as rounding leaves it, then still gives the linear root)
        q = -0.5 * (c1 + math.copysign(math.sqrt(disc), c1))
        if c2 != 0:
            roots.append(q / c2)
        if q != 0:
            roots.append(c0 / q)
    return [value(t) for t in [t0, t1] + [r for r in roots if t0 < r < t1]]


def _fits_line(basis: list[Point2], t0: float, t1: float, a: Point2, b: Point2, tolerance: float) -> bool:
    """The curve on [t0, t1] stays within tolerance of the segment a-b (exactly)."""
    length = math.dist(a, b)
    if length == 0:
        return False
    ux, uy = (b[0] - a[0]) / length, (b[1] - a[1]) / length
    along = [c[0] * ux + c[1] * uy for c in basis]          # (B(t) - a) . u, as a polynomial
    across = [-c[0] * uy + c[1] * ux for c in basis]        # (B(t) - a) x u
    along[0] -= a[0] * ux + a[1] * uy
    across[0] -= -a[0] * uy + a[1] * ux
    side = max(abs(v) for v in _extremes(across, t0, t1))
    travel = _extremes(along, t0, t1)
    beyond = max(0.0, max(travel) - length, -min(travel))     # past an end of the segment
    return math.hypot(side, beyond) <= tolerance            # (a bound on the distance from it)


def _circle(a: Point2, m: Point2, b: Point2) -> tuple[Point2, bool] | None:
    """(centre, ccw) of the circle from a through m to b, None if the three are in a line."""
    d = 2 * ((m[0] - a[0]) * (b[1] - a[1]) - (m[1] - a[1]) * (b[0] - a[0]))
    if d == 0:
        return None
    am, ab = (m[0] - a[0]) ** 2 + (m[1] - a[1]) ** 2, (b[0] - a[0]) ** 2 + (b[1] - a[1]) ** 2
    cx = a[0] + ((b[1] - a[1]) * am - (m[1] - a[1]) * ab) / d
    cy = a[1] + ((m[0] - a[0]) * ab - (b[0] - a[0]) * am) / d
    return (cx, cy), d > 0                 # (a left turn from a through m to b: counter-clockwise)


def _angle_from(centre: Point2, start: Point2, p: Point2, ccw: bool) -> float:
    """The angle swept from start to p about centre, in the arc's direction, 0 .. 2 pi."""
    a = math.atan2(p[1] - centre[1], p[0] - centre[0]) - math.atan2(start[1] - centre[1], start[0] - centre[0])
    return (a if ccw else -a) % (2 * math.pi)


def _fits_arc(control: list[Point2], t0: float, t1: float, a: Point2, b: Point2, tolerance: float):
    """(centre, ccw) of the arc from a through the middle of the piece to b if the curve lies on
    it within tolerance at the samples and turns one way along it, else None."""
    circle = _circle(a, bezier(control, (t0 + t1) / 2), b)
    if circle is None:
        return None
    centre, ccw = circle
    radius = math.dist(a, centre)
    if radius > RADIUS_RATIO * math.dist(a, b):
        return None
    sweep = _angle_from(centre, a, b, ccw)
    last = 0.0
    for k in range(1, SAMPLES + 1):
        p = bezier(control, t0 + (t1 - t0) * k / (SAMPLES + 1))
        if abs(math.dist(p, centre) - radius) > ARC_MARGIN * tolerance:
            return None
        angle = _angle_from(centre, a, p, ccw)
        if not last <= angle <= sweep:
            return None
        last = angle
    return centre, ccw


def pieces(control: list[Point2], tolerance: float = TOLERANCE_MM) -> list[tuple]:
    """The curve of the control points (3: quadratic, 4: cubic) as ("line", start, end) and
    ("arc", start, end, centre, ccw) pieces in order, each within tolerance of the curve."""
    basis = power_basis(control)
    if all(p == control[0] for p in control):
        return []                               # (a curve that does not move)
    out: list[tuple] = []
    todo = [(0.0, 1.0, 0)]                      # a stack: the earlier half on top
    while todo:
        t0, t1, depth = todo.pop()
        a, b = bezier(control, t0), bezier(control, t1)
        if depth >= DEPTH or _fits_line(basis, t0, t1, a, b, tolerance):
            if a != b:
                out.append(("line", a, b))
        else:
            arc = _fits_arc(control, t0, t1, a, b, tolerance)
            if arc is not None:
                out.append(("arc", a, b, *arc))
            else:
                todo += [((t0 + t1) / 2, t1, depth + 1), (t0, (t0 + t1) / 2, depth + 1)]
        if len(out) + len(todo) > MAX_PIECES:
            raise SplineError(f"the curve needs more than {MAX_PIECES} arcs and lines within "
                              f"{tolerance:g} mm: are its control points (I J P Q) that far?")
    return out


def length(parts: list[tuple]) -> float:
    """The path length of the pieces."""
    total = 0.0
    for part in parts:
        if part[0] == "line":
            total += math.dist(part[1], part[2])
        else:
            _kind, a, b, centre, ccw = part
            total += math.dist(a, centre) * _angle_from(centre, a, b, ccw)
    return total
