# SPDX-License-Identifier: Apache-2.0
"""Cutter radius compensation (G41 / G42 and G41.1 / G42.1; G40 ends it) in the plane in force,
as LinuxCNC runs it: the tool's centre keeps `radius` to the left (G41) or the right (G42) of
the programmed path, seen from the positive end of the plane's normal axis (Z for G17, Y for
G18, X for G19).

The interpreter hands the moves it makes to a Compensator while compensation is on; the
compensator gives back the tool's moves.  A move's compensated end depends on the move after
it, so the last XY move waits (with the events, dwells and Z-only moves after it) until the
next XY move or G40:

- each line is shifted sideways by the radius; each arc keeps its centre and takes the
  radius R + r or R - r (an arc on the inside with R <= r is an error);
- an outside corner gets an arc of the tool's radius about the programmed corner; an inside
  corner moves the end of the one move and the start of the next to where their shifted
  paths cross (a move that would then run backwards, or paths that do not cross, is an
  error: the tool does not fit the corner);
- the entry move (the first XY move after G41 / G42, a straight line longer than the radius)
  ends where the tool touches its programmed end point on a line tangent to that circle, as
  LinuxCNC's; the moves after G40 start from where the compensated path ended, and the first
  XY move (the exit move, a straight line) goes to its programmed end.

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

    def __init__(self, side: str, radius: float, tool_xy, line: int, plane: str = "XY"):
        self.side, self.radius, self.line, self.plane = side, radius, line, plane
        self.axes = PLANES[plane]
        self.sign = 1.0 if side == "left" else -1.0
        self.tool = tuple(tool_xy)      # (u, v) where the tool is (the end of the moves handed back)
        self.state = "entering"         # then "on"; after G40 "exiting"; then "done"
        self.pending = None             # the last XY move, compensated, its end not settled yet
        self.pending_turn = (0.0, 0.0)  # ... its programmed direction at its end
        self.pending_corner = (0.0, 0.0)    # ... and its programmed end point
        self.pending_sweep = 0.0        # an arc's sweep before its start or end moved
        self.after: list = []           # moves after it (events, dwells, Z-only lines)

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
        radius = big + r * _dot(self.normal(tangent(move, False)), radial)
        if radius <= CLOSE:
            raise CompensationError(move.line, f"the tool's radius ({r:g} mm) is not less than the arc's "
                                               f"({big:g} mm) on the side it cuts")

        def moved(point):
            ux, uy = _unit(point[0] - move.centre[0], point[1] - move.centre[1])
            return (move.centre[0] + radius * ux, move.centre[1] + radius * uy, point[2])
        return replace(move, start=moved(move.start), end=moved(move.end))

    def _entry(self, move: Line) -> Line:
        """The entry move: from the tool to where it touches the programmed end, tangentially."""
        px, py = _xy(move.end)
        dx, dy = px - self.tool[0], py - self.tool[1]
        distance = math.hypot(dx, dy)
        if distance <= self.radius + CLOSE:
            raise CompensationError(move.line, f"the entry move after G41 / G42 must be longer than the tool's "
                                               f"radius ({self.radius:g} mm): it is {distance:g} mm")
        phi = math.atan2(dy, dx) + self.sign * math.asin(self.radius / distance)
        direction = (math.cos(phi), math.sin(phi))
        nx, ny = self.normal(direction)
        end = (px + self.radius * nx, py + self.radius * ny, move.end[2])
        self.pending_turn, self.pending_corner, self.pending_sweep = direction, (px, py), 0.0
        return replace(move, start=(self.tool[0], self.tool[1], move.start[2]), end=end)

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
            if self.pending is not None:
                self.after.append(move)
                return []
            return [replace(move, start=(*self.tool, move.start[2]), end=(*self.tool, move.end[2]))]
        if self.state in ("entering", "exiting") and isinstance(move, Arc):
            which = "entry move after G41 / G42" if self.state == "entering" else "exit move after G40"
            raise CompensationError(move.line, f"the {which} must be a straight line (G0 or G1), not an arc")
        if self.state == "exiting":
            self.state = "done"
            return [replace(move, start=(*self.tool, move.start[2]))]
        if self.state == "entering":
            self.state = "on"
            self.pending = self._entry(move)
            return []
        return self._join(move)

    def _join(self, move) -> list:
        """The corner between the pending move and the next XY move."""
        before, after = self.pending, self.shifted(move)
        end, start = _xy(before.end), _xy(after.start)
        corner_move = None
        if math.dist(end, start) > CLOSE:
            turn_in, turn_out = self.pending_turn, tangent(move, False)
            turn = _cross(turn_in, turn_out) * self.sign
            outside = turn < -1e-12 or (turn <= 1e-12 and _dot(turn_in, turn_out) < 0)
            if outside:
                corner_move = self._corner(before, after, move)
            else:
                found = self._crossings(self._path(before), self._path(after))
                if not found:
                    raise CompensationError(move.line, self._misfit())
                x, y = min(found, key=lambda p: math.dist(p, self.pending_corner))
                before = replace(before, end=(x, y, before.end[2]))
                after = replace(after, start=(x, y, after.start[2]))
        out = self._settle(before, move.line)
        self.pending = after
        self.pending_turn = tangent(move, True)
        self.pending_corner = _xy(move.end)
        self.pending_sweep = _sweep(self.shifted(move)) if isinstance(move, Arc) else 0.0
        if corner_move is not None:
            out.append(corner_move)
            self.tool = _xy(corner_move.end)
        return out

    def _corner(self, before, after, move):
        """The arc about the programmed corner from the one shifted move to the next."""
        z = after.start[2]
        start, end = (*_xy(before.end), z), after.start
        feed = move.feed if move.feed is not None else before.feed
        if feed is None or math.dist(_xy(start), _xy(end)) < CHORD:
            return Line(start, end, feed, move.line)     # (rapids on both sides: a rapid line)
        return Arc(start, end, (*self.pending_corner, z), "XY", self.side == "right", 1, feed, move.line)

    def _misfit(self) -> str:
        return (f"the tool (radius {self.radius:g} mm) does not fit the inside corner at the start of this move "
                "(the compensated paths do not meet)")

    def _settle(self, move, next_line: int) -> list:
        """The pending move with its end settled -> it and the moves queued after it."""
        if isinstance(move, Line):
            direction = self.pending_turn
            if _dot((move.end[0] - move.start[0], move.end[1] - move.start[1]), direction) < -CLOSE:
                raise CompensationError(next_line, self._misfit_of(move))
        elif self.pending_sweep and _sweep(move) > self.pending_sweep + 1e-9 and self.pending_sweep < 2 * math.pi:
            raise CompensationError(next_line, self._misfit_of(move))
        self.tool = _xy(move.end)
        out = [move] if (math.dist(_xy(move.start), _xy(move.end)) > CLOSE or isinstance(move, Arc)
                         or move.start[2] != move.end[2]) else []
        for queued in self.after:
            if isinstance(queued, Line):
                queued = replace(queued, start=(*self.tool, queued.start[2]), end=(*self.tool, queued.end[2]))
            out.append(queued)
        self.after = []
        return out

    def _misfit_of(self, move) -> str:
        return (f"the tool (radius {self.radius:g} mm) does not fit here: the compensated move of line "
                f"{move.line} would run backwards (an inside corner too tight for it)")

    def off(self) -> list:
        """G40 (or the program's end): the pending move ends at its shifted end point."""
        out = []
        if self.pending is not None:
            out = self._settle(self.pending, self.pending.line)
            self.pending = None
        self.state = "exiting" if self.state == "on" else "done"
        return [self._frame(m, False) for m in out]
