# SPDX-License-Identifier: Apache-2.0
"""Cutter radius compensation (G41 / G42 and G41.1 / G42.1; G40 ends it) in the plane in force,
as LinuxCNC runs it: the tool's centre keeps `radius` to the left (G41) or the right (G42) of
the programmed path, seen from the positive end of the plane's normal axis (Z for G17, Y for
G18, whose frame is (Z, X) as LinuxCNC's).

The interpreter hands the moves it makes to a Compensator while compensation is on; the
compensator gives back the tool's moves.  A move's compensated end depends on the move after
it, so the last XY move waits (with the events, dwells and Z-only moves after it) until the
next XY move or G40:

- each line is shifted sideways by the radius; each arc keeps its centre and takes the
  radius R + r or R - r (an arc on the inside with R <= r is an error);
- a bend of less than BEND between two moves joins them as they are (a line starts where the
  move before ended); a larger outside bend, or a reversal, gets an arc of the tool's radius
  about the programmed corner (a straight rapid before a G0); an inside bend moves the end of
  the one move and the start of the next to where their paths meet (a move that then runs
  backwards, or paths that do not meet, is an error: the tool does not fit the corner);
- the entry move (the first XY move after G41 / G42, longer than the radius) is LinuxCNC's:
  a line ends at the radius from its programmed end, square to the line from the tool to
  that end; an arc ends at the radius from its programmed end along its radius, about a
  centre moved so that it stays an arc;
- the moves after G40 start from where the compensated path ended, and the first XY move
  (the exit move, a straight line) goes to its programmed end.

All positions are machine millimetres; only the plane's two axes are changed (the third
follows the program).  Below, the plane's axes (u, v, w) are called x, y, z: the compensator
turns each move into that frame and its own moves back.
"""
from __future__ import annotations

import math
from dataclasses import replace

from .moves import PLANES, Arc, Dwell, Event, Line

CLOSE = 1e-6            # mm: points closer than this are the same point
CHORD = 1e-3            # mm: a corner shorter than this is a straight line, not an arc
BEND = 0.05             # rad: a smaller bend joins two moves as they are (LinuxCNC's concave tolerance)
GOUGE_NEIGHBOURS = 6    # programmed moves a compensated move is checked against (the gouge warning)
GOUGE_TOLERANCE = 0.005     # mm: below, no warning (an arc's end radius may differ by as much)


class CompensationError(Exception):
    """A move compensation cannot run: `line` (the program's line) and `text`."""

    def __init__(self, line: int, text: str):
        super().__init__(text)
        self.line, self.text = line, text


def _unit(x: float, y: float) -> tuple[float, float]:
    n = math.hypot(x, y)
    return (x / n, y / n) if n > 0 else (0.0, 0.0)


def _cross(u, v) -> float:
    return u[0] * v[1] - u[1] * v[0]


def _dot(u, v) -> float:
    return u[0] * v[0] + u[1] * v[1]


def _xy(point) -> tuple[float, float]:
    return (point[0], point[1])


def _moves_in_xy(move) -> bool:
    return math.dist(_xy(move.start), _xy(move.end)) > CLOSE or isinstance(move, Arc)


def tangent(move, at_end: bool) -> tuple[float, float]:
    """The programmed direction of an XY move at its start or end (a unit vector)."""
    if isinstance(move, Line):
        return _unit(move.end[0] - move.start[0], move.end[1] - move.start[1])
    point = move.end if at_end else move.start
    rx, ry = point[0] - move.centre[0], point[1] - move.centre[1]
    return _unit(-ry, rx) if move.ccw else _unit(ry, -rx)


def _points(move, count: int = 16) -> list[tuple[float, float]]:
    """Points along a Line or Arc (XY), its ends included."""
    if isinstance(move, Line):
        return [(move.start[0] + (move.end[0] - move.start[0]) * k / count,
                 move.start[1] + (move.end[1] - move.start[1]) * k / count) for k in range(count + 1)]
    a0, sweep = _angle(move.start, move.centre), _sweep(move) * (1 if move.ccw else -1)
    radius = math.dist(_xy(move.start), _xy(move.centre))
    return [(move.centre[0] + radius * math.cos(a0 + sweep * k / count),
             move.centre[1] + radius * math.sin(a0 + sweep * k / count)) for k in range(count + 1)]


def _distance(point, move) -> float:
    """The distance from a point to a Line or Arc (XY)."""
    a, b = _xy(move.start), _xy(move.end)
    if isinstance(move, Line):
        ab = (b[0] - a[0], b[1] - a[1])
        length = _dot(ab, ab)
        t = 0.0 if length == 0 else max(0.0, min(1.0, _dot((point[0] - a[0], point[1] - a[1]), ab) / length))
        return math.dist(point, (a[0] + t * ab[0], a[1] + t * ab[1]))
    centre = _xy(move.centre)
    turn = (_angle(point, centre) - _angle(a, centre)) * (1 if move.ccw else -1) % (2 * math.pi)
    if turn <= _sweep(move):
        return abs(math.dist(point, centre) - math.dist(a, centre))
    return min(math.dist(point, a), math.dist(point, b))


def _segment_gap(one: Line, two: Line) -> float:
    """The distance between two line segments (XY): 0 where they cross."""
    a, b, c, d = _xy(one.start), _xy(one.end), _xy(two.start), _xy(two.end)

    def side(p, q, r) -> float:
        return _cross((q[0] - p[0], q[1] - p[1]), (r[0] - p[0], r[1] - p[1]))
    if side(a, b, c) * side(a, b, d) < 0 and side(c, d, a) * side(c, d, b) < 0:
        return 0.0
    return min(_distance(a, two), _distance(b, two), _distance(c, one), _distance(d, one))


def _angle(point, centre) -> float:
    return math.atan2(point[1] - centre[1], point[0] - centre[0])


def _sweep(arc: Arc) -> float:
    """The angle an arc turns through in its direction, in (0, 2 pi] (start = end: a whole turn)."""
    turn = _angle(arc.end, arc.centre) - _angle(arc.start, arc.centre)
    if not arc.ccw:
        turn = -turn
    turn %= 2 * math.pi
    return turn if turn > 1e-12 else 2 * math.pi


class Compensator:
    """Compensation from one G41 / G42 to its exit move (see the module's text)."""

    def __init__(self, side: str, radius: float, tool_xy, plane: str = "XY"):
        self.side, self.radius, self.plane = side, radius, plane
        self.axes = PLANES[plane]
        self.sign = 1.0 if side == "left" else -1.0
        self.tool = tuple(tool_xy)      # (u, v) where the tool is (the end of the moves handed back)
        self.state = "entering"         # then "on"; after G40 "exiting"; then "done"
        self.pending = None             # the last XY move, compensated, its end not settled yet
        self.pending_turn = (0.0, 0.0)  # ... its programmed direction at its end
        self.pending_corner = (0.0, 0.0)    # ... and its programmed end point
        self.pending_shifted = None     # ... as it was before an inside corner moved its start
        self.trimmed = False            # ... its start was moved back at an inside corner
        self.after: list = []           # moves after it (events, dwells, Z-only lines)
        self.entered = False            # the pending move is not the entry move
        self.programmed: list = []      # the last programmed moves (the gouge check's neighbours)
        self.unchecked: list = []       # (move made, joins to wait): checked two moves on
        self.bends: list = []           # (length, bend joined as it is at its start) of the last moves
        self.warnings: list[tuple[int, str]] = []   # (line, text): gouges found, for the interpreter
        self.warned: set[int] = set()

    # ---- geometry ----------------------------------------------------------------
    def normal(self, direction) -> tuple[float, float]:
        """The unit vector from the path to the tool's centre, for a path direction."""
        return (-self.sign * direction[1], self.sign * direction[0])

    def shifted(self, move):
        """A programmed XY move as the tool's centre runs it (not yet met with its neighbours)."""
        r = self.radius
        if isinstance(move, Line):
            nx, ny = self.normal(tangent(move, False))
            return replace(move, start=(move.start[0] + r * nx, move.start[1] + r * ny, move.start[2]),
                           end=(move.end[0] + r * nx, move.end[1] + r * ny, move.end[2]))
        radial = _unit(move.start[0] - move.centre[0], move.start[1] - move.centre[1])
        big = math.dist(_xy(move.start), _xy(move.centre))
        change = r * _dot(self.normal(tangent(move, False)), radial)       # + r or - r
        if big + change <= CLOSE:
            raise CompensationError(move.line, f"the tool's radius ({r:g} mm) is not less than the arc's "
                                               f"({big:g} mm) on the side it cuts")

        def moved(point):                       # (each end by its own radius)
            ux, uy = _unit(point[0] - move.centre[0], point[1] - move.centre[1])
            radius = math.dist(_xy(point), _xy(move.centre)) + change
            return (move.centre[0] + radius * ux, move.centre[1] + radius * uy, point[2])
        return replace(move, start=moved(move.start), end=moved(move.end))

    def _entry(self, move):
        """The entry move (LinuxCNC's): a line ends at the tool's radius from its programmed end,
        square to the line from the tool to that end; an arc ends at the tool's radius from
        its programmed end along its radius, about a centre moved so that it is an arc."""
        px, py = _xy(move.end)
        distance = math.hypot(px - self.tool[0], py - self.tool[1])
        if distance <= self.radius:
            raise CompensationError(move.line, f"the entry move after G41 / G42 must be longer than the tool's "
                                               f"radius ({self.radius:g} mm): it is {distance:g} mm")
        start = (*self.tool, move.start[2])
        if isinstance(move, Line):
            direction = _unit(px - self.tool[0], py - self.tool[1])
            nx, ny = self.normal(direction)
            self.pending_turn = direction
            return replace(move, start=start, end=(px + self.radius * nx, py + self.radius * ny, move.end[2]))
        cx, cy = _xy(move.centre)
        towards = _unit(cx - px, cy - py)
        nx, ny = self.normal(tangent(move, True))
        side = 1.0 if nx * towards[0] + ny * towards[1] > 0 else -1.0      # tool inside the arc: towards
        ex, ey = px + side * self.radius * towards[0], py + side * self.radius * towards[1]
        chord = (self.tool[0] - ex, self.tool[1] - ey)
        bx, by = _unit(cx - ex, cy - ey)
        cosine = _dot(_unit(*chord), (bx, by))
        reach = math.hypot(*chord) / 2 / cosine if abs(cosine) > 1e-9 else -1.0
        if reach <= CLOSE:
            raise CompensationError(move.line, f"the entry arc cannot run with the tool's radius ({self.radius:g} mm)")
        self.pending_turn = tangent(move, True)
        return replace(move, start=start, end=(ex, ey, move.end[2]),
                       centre=(ex + reach * bx, ey + reach * by, move.start[2]))

    @staticmethod
    def _path(move):
        """A compensated move's path: ("line", point, direction) or ("circle", centre, radius)."""
        if isinstance(move, Line):
            return ("line", _xy(move.start), _unit(move.end[0] - move.start[0], move.end[1] - move.start[1]))
        return ("circle", _xy(move.centre), math.dist(_xy(move.start), _xy(move.centre)))

    @staticmethod
    def _crossings(one, two) -> list[tuple[float, float]]:
        if one[0] == "circle" and two[0] == "line":
            one, two = two, one
        if one[0] == "line" and two[0] == "line":
            (p, u), (q, v) = one[1:], two[1:]
            det = _cross(u, v)
            if abs(det) < 1e-12:
                return []
            t = _cross((q[0] - p[0], q[1] - p[1]), v) / det
            return [(p[0] + t * u[0], p[1] + t * u[1])]
        if one[0] == "line":
            (p, u), (c, radius) = one[1:], two[1:]
            w = (p[0] - c[0], p[1] - c[1])
            b, k = _dot(u, w), _dot(w, w) - radius * radius
            disc = b * b - k
            if disc < 0:
                return []
            root = math.sqrt(disc)
            return [(p[0] + t * u[0], p[1] + t * u[1]) for t in (-b - root, -b + root)]
        (c1, r1), (c2, r2) = one[1:], two[1:]
        d = math.dist(c1, c2)
        if d < 1e-12 or d > r1 + r2 or d < abs(r1 - r2):
            return []
        a = (r1 * r1 - r2 * r2 + d * d) / (2 * d)
        h = math.sqrt(max(r1 * r1 - a * a, 0.0))
        ux, uy = (c2[0] - c1[0]) / d, (c2[1] - c1[1]) / d
        mx, my = c1[0] + a * ux, c1[1] + a * uy
        return [(mx - h * uy, my + h * ux), (mx + h * uy, my - h * ux)]

    # ---- the plane's frame ---------------------------------------------------------
    def plane_point(self, point) -> tuple[float, float, float]:
        """Machine (x, y, z) -> the plane's (u, v, w)."""
        return tuple(point[a] for a in self.axes)

    def _frame(self, move, inward: bool):
        """A Line or Arc into the plane's frame (inward) or back into the machine's."""
        if not isinstance(move, (Line, Arc)) or self.plane == "XY":
            return move
        if inward:
            turn = self.plane_point
        else:
            def turn(point):
                out = [0.0, 0.0, 0.0]
                for value, axis in zip(point, self.axes):
                    out[axis] = value
                return tuple(out)
        if isinstance(move, Line):
            return replace(move, start=turn(move.start), end=turn(move.end))
        return replace(move, start=turn(move.start), end=turn(move.end), centre=turn(move.centre),
                       plane="XY" if inward else self.plane)

    # ---- the moves ---------------------------------------------------------------
    def held(self) -> int:
        """Moves taken and not handed back yet: the pending move and what waits after it."""
        return (self.pending is not None) + len(self.after)

    def take(self, move) -> list:
        """A move the interpreter made -> the tool's moves that are settled now."""
        return [self._frame(m, False) for m in self._take(self._frame(move, True))]

    def _take(self, move) -> list:
        if isinstance(move, (Event, Dwell)):
            if self.pending is not None:
                self.after.append(move)
                return []
            return [move]
        if not _moves_in_xy(move):                  # Z only: where the tool is in XY
            if self.state == "entering":            # (before the entry move: as programmed)
                self.tool = _xy(move.end)
                return [move]
            if self.pending is not None:
                self.after.append(move)
                return []
            return [replace(move, start=(*self.tool, move.start[2]), end=(*self.tool, move.end[2]))]
        if self.state == "exiting":
            if isinstance(move, Arc):
                raise CompensationError(move.line, "the exit move after G40 must be a straight line (G0 or G1), "
                                                   "not an arc")
            self.state = "done"
            return [replace(move, start=(*self.tool, move.start[2]))]
        if self.state == "entering":
            self.state = "on"
            self.pending, self.trimmed = self._entry(move), False
            self.pending_shifted, self.pending_corner = self.pending, _xy(move.end)
            return []
        return self._join(move)

    def _join(self, move) -> list:
        """The corner between the pending move and the next move in the plane, as LinuxCNC
        takes it: a bend of less than BEND (rad) either way joins the moves as they are; a
        larger outside bend (or a turn within BEND of a reversal) gets a corner, an inside one
        moves the end of the one and the start of the other to where their paths meet."""
        shifted = self.shifted(move)
        before, after = self.pending, shifted
        turn_in, turn_out = self.pending_turn, tangent(move, False)
        angle = math.atan2(_cross(turn_in, turn_out), _dot(turn_in, turn_out))
        bend = -self.sign * angle                   # > 0: an outside corner
        corner_move, trimmed = None, False
        if abs(angle) > math.pi - BEND or bend > BEND:          # (a reversal: round the outside)
            if math.dist(_xy(before.end), _xy(after.start)) > CLOSE:
                corner_move = self._corner(before, after, move)
        elif bend < -BEND:
            x, y = self._meet(before, after, turn_in, abs(angle), move.line)
            before = replace(before, end=(x, y, before.end[2]))
            after = replace(after, start=(x, y, after.start[2]))
            trimmed = True
        if corner_move is None and _xy(before.end) != _xy(after.start):   # joined as they are
            if isinstance(after, Line):
                after = replace(after, start=(*_xy(before.end), after.start[2]))
            else:
                corner_move = Line((*_xy(before.end), after.start[2]), after.start, move.feed, move.line,
                                   origin=move.origin)
        self._curvature(move, -bend if abs(bend) <= BEND else 0.0)
        if trimmed or self.trimmed:
            self._check_forward(before, move.line)
        self.programmed = (self.programmed + [move])[-GOUGE_NEIGHBOURS:]
        for made, later in self.unchecked:
            if later == 1:
                self._gouge(made)
        self.unchecked = [(made, later - 1) for made, later in self.unchecked if later > 1] + \
            [(made, 2) for made in ([before] if self.entered else []) + ([corner_move] if corner_move else [])]
        self.entered = True
        out = self._settle(before)
        self.pending, self.pending_shifted, self.trimmed = after, shifted, trimmed
        self.pending_turn = tangent(move, True)
        self.pending_corner = _xy(move.end)
        if corner_move is not None:
            out.append(corner_move)
            self.tool = _xy(corner_move.end)
        return out

    def _meet(self, before, after, turn_in, angle: float, line: int) -> tuple[float, float]:
        """Where the paths of two compensated moves meet at an inside corner: between two lines,
        the one's end moved back along its direction by r tan(angle / 2) (LinuxCNC's); else
        where the paths cross, nearest the programmed corner."""
        if isinstance(before, Line) and isinstance(after, Line):
            back = self.radius * math.tan(angle / 2)
            return before.end[0] - back * turn_in[0], before.end[1] - back * turn_in[1]
        found = self._crossings(self._path(before), self._path(after))
        if not found:
            raise CompensationError(line, f"the tool (radius {self.radius:g} mm) does not fit the inside corner at "
                                          "the start of this move (the compensated paths do not meet)")
        return min(found, key=lambda p: math.dist(p, self.pending_corner))

    def _check_forward(self, move, line: int, which: str = "before this one") -> None:
        """The pending move, its start or end moved at an inside corner, must not run backwards
        (a line) or further round than before (an arc): else the tool does not fit there."""
        shifted = self.pending_shifted
        if isinstance(move, Line):
            backwards = _dot((move.end[0] - move.start[0], move.end[1] - move.start[1]),
                             (shifted.end[0] - shifted.start[0], shifted.end[1] - shifted.start[1])) < 0
        else:
            full = _sweep(shifted)
            backwards = move.turns <= 1 and full < 2 * math.pi and _sweep(move) > full + 1e-9
        if backwards:
            raise CompensationError(line, f"the tool (radius {self.radius:g} mm) does not fit here: the compensated "
                                          f"move {which} would run backwards (an inside corner too tight for it)")

    def _corner(self, before, after, move):
        """An arc about the programmed corner from the one compensated move to the next, at the
        next move's feed; before a rapid a straight rapid (LinuxCNC's)."""
        z = after.start[2]
        start, end = (*_xy(before.end), z), after.start
        if move.feed is None or math.dist(_xy(start), _xy(end)) < CHORD:
            return Line(start, end, move.feed, move.line, origin=move.origin)
        return Arc(start, end, (*self.pending_corner, z), "XY", self.side == "right", 1, move.feed, move.line,
                   origin=move.origin)

    def _curvature(self, move, inside: float) -> None:
        """Bends joined as they are (`inside`: the bend at this move's start towards the tool,
        0 for a corner met or rounded exactly) add up like a curve's turning: where the last
        tool's radius of programmed path turns more than 1 / r per mm towards the tool (plus
        BEND), the tool is bigger than that inside curve and the joins carry it to the far
        side: a warning."""
        length = math.dist(_xy(move.start), _xy(move.end)) if isinstance(move, Line) else \
            _sweep(move) * math.dist(_xy(move.start), _xy(move.centre))
        self.bends.append((length, inside))
        while len(self.bends) > 1 and sum(b[0] for b in self.bends[1:]) >= self.radius:
            self.bends.pop(0)
        total = sum(b[0] for b in self.bends)
        turned = sum(b[1] for b in self.bends[1:])          # (the bends between them)
        if self.radius > 0 and turned > total / self.radius + BEND and move.line not in self.warned:
            self.warned.add(move.line)
            self.warnings.append((move.line, f"cutter compensation: the tool (radius {self.radius:g} mm) is bigger "
                                             f"than the inside curve here ({turned:.3g} rad in {total:.3g} mm): "
                                             "it cuts into the far side"))

    def _gouge(self, move) -> None:
        """Each corner is decided from the two moves that meet there, as LinuxCNC does; a
        compensated move that still comes nearer the programmed path of its neighbours than
        the radius (a small arc after a long line, a narrow slot) is a gouge: a warning, once
        per line.  (Bends joined as they are may come r (1 - cos BEND) nearer.)"""
        length = math.dist(_xy(move.start), _xy(move.end)) if isinstance(move, Line) else \
            _sweep(move) * math.dist(_xy(move.start), _xy(move.centre))
        points = _points(move, min(16, 2 + int(4 * length / max(self.radius, CHORD))))

        def gap(other) -> float:
            if isinstance(move, Line) and isinstance(other, Line):
                return _segment_gap(move, other)
            return min(_distance(point, other) for point in points)
        near, cut = min((gap(other), other.line) for other in self.programmed)
        depth = self.radius - near
        if depth > self.radius * (1 - math.cos(BEND)) + GOUGE_TOLERANCE and move.line not in self.warned:
            self.warned.add(move.line)
            self.warnings.append((move.line, f"cutter compensation: the tool (radius {self.radius:g} mm) cuts "
                                             f"{depth:.4g} mm into the programmed path of line {cut}"))

    def _settle(self, move) -> list:
        """The pending move with its end settled -> it and the moves queued after it."""
        self.tool = _xy(move.end)
        out = [move] if (math.dist(_xy(move.start), _xy(move.end)) > CLOSE or isinstance(move, Arc)
                         or move.start[2] != move.end[2]) else []
        for queued in self.after:
            if isinstance(queued, Line):
                queued = replace(queued, start=(*self.tool, queued.start[2]), end=(*self.tool, queued.end[2]))
            out.append(queued)
        self.after = []
        return out

    def off(self) -> list:
        """G40 (or the program's end): the pending move ends at its shifted end point; the next
        move in the plane is the exit move (a second G40 changes nothing)."""
        out = []
        if self.pending is not None:
            if self.trimmed:
                self._check_forward(self.pending, self.pending.line, "of this line")
            for made in [m for m, _ in self.unchecked] + ([self.pending] if self.entered else []):
                self._gouge(made)
            self.unchecked = []
            out = self._settle(self.pending)
            self.pending = None
        self.state = "exiting" if self.state in ("on", "exiting") else "done"
        return [self._frame(m, False) for m in out]
