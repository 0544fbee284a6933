# SPDX-License-Identifier: Apache-2.0
"""G5 and G5.1 splines as arcs and lines.

LinuxCNC's G5 is a cubic Bézier curve in the XY plane from the current point P0 to
the end P3, with control points P1 = P0 + (I, J) and P2 = P3 + (P, Q); G5.1 is the
quadratic one with P1 = P0 + (I, J).  The hardware has lines and circular arcs, so
`pieces` cuts the curve into them, each within TOLERANCE_MM of the curve:

  * a piece of the parameter range [t0, t1] is checked at SAMPLES points inside it;
  * a line from B(t0) to B(t1) if every sample lies within the tolerance of it;
  * else the circle through B(t0), B((t0 + t1) / 2) and B(t1) if every sample lies
    within the tolerance of it, in order along the arc (no wider than RADIUS_RATIO
    times its chord);
  * else the range is halved (at most DEPTH times; there a line).

The pieces join end to end at points of the curve, so the path is continuous and its
ends are the programmed ones exactly.
"""
from __future__ import annotations

import math

TOLERANCE_MM = 0.001        # every piece stays this close to the curve (at its samples)
SAMPLES = 16                # points checked inside each piece
DEPTH = 30                  # halvings of the parameter range at the most
RADIUS_RATIO = 1000.0       # an arc's radius at most this many chords (else a finer piece)

Point2 = tuple[float, float]


def bezier(control: list[Point2], t: float) -> Point2:
    """The Bézier curve of the control points at t (0 .. 1), by de Casteljau's rule (its ends
    exactly the first and last control points)."""
    if t in (0.0, 1.0):
        return control[0] if t == 0.0 else control[-1]
    points = list(control)
    while len(points) > 1:
        points = [(a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t) for a, b in zip(points, points[1:])]
    return points[0]


def _off_line(p: Point2, a: Point2, b: Point2) -> float:
    """The distance of p from the segment a-b."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    span = dx * dx + dy * dy
    t = 0.0 if span == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / span))
    return math.hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy)


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


def _fits_arc(a: Point2, m: Point2, b: Point2, samples: list[Point2], tolerance: float):
    """(centre, ccw) of the arc a-m-b if every sample lies on it within tolerance, in order."""
    circle = _circle(a, m, b)
    if circle is None:
        return None
    centre, ccw = circle
    radius = math.dist(a, centre)
    if radius > RADIUS_RATIO * math.dist(a, b):
        return None
    sweep = _angle_from(centre, a, b, ccw)
    last = 0.0
    for p in samples:
        if abs(math.dist(p, centre) - radius) > tolerance:
            return None
        angle = _angle_from(centre, a, p, ccw)
        if not last <= angle <= sweep:
            return None
        last = angle
    return centre, ccw


def pieces(control: list[Point2], tolerance: float = TOLERANCE_MM) -> list[tuple]:
    """The curve of the control points (3: quadratic, 4: cubic) as ("line", start, end) and
    ("arc", start, end, centre, ccw) pieces in order, each within tolerance of the curve."""
    out: list[tuple] = []
    todo = [(0.0, 1.0, 0)]                   # a stack: the earlier half on top
    while todo:
        t0, t1, depth = todo.pop()
        a, b = bezier(control, t0), bezier(control, t1)
        samples = [bezier(control, t0 + (t1 - t0) * k / (SAMPLES + 1)) for k in range(1, SAMPLES + 1)]
        if a == b and all(p == a for p in samples):
            continue                            # (a curve that does not move)
        if depth >= DEPTH or all(_off_line(p, a, b) <= tolerance for p in samples):
            out.append(("line", a, b))
            continue
        middle = (t0 + t1) / 2
        arc = _fits_arc(a, bezier(control, middle), b, samples, tolerance)
        if arc is not None:
            out.append(("arc", a, b, *arc))
            continue
        todo += [(middle, t1, depth + 1), (t0, middle, depth + 1)]
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
