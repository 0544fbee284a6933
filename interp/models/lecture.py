# SPDX-License-Identifier: Apache-2.0
"""Golden models of the lecture's evaluation-function cores.

Step-level models, written as the lecture's equations (F is the evaluation function):

  standard linear      F >= 0: X step, F -= dY;         F < 0: Y step, F += dX
  accelerated linear   F >= 0: axial,  F -= S;          F < 0: diagonal, F += L - S
  standard circular    F = x^2 + y^2 - R^2, CCW:  F >= 0: x -= 1, F += -2x + 1
                                                  F < 0:  y += 1, F += 2y + 1
  accelerated circular octant x > y (y leads):  F >= 0: diagonal, F < 0: y step
                       octant x <= y (x leads): F >= 0: x step,   F < 0: diagonal

(x, y before the step; CW is the same with the roles of x and y exchanged).
The step counters KOX, KOY end the move: an axis whose counter is 0 gives its
step to the other axis.  The cycle models mirror rtl/lin_std.v, rtl/lin_accel.v
and rtl/circ_quadrant.v register by register.
"""
from __future__ import annotations

from dataclasses import dataclass

from .base import MOTION_OUTPUTS, CycleModel


@dataclass
class Step:
    dx: int
    dy: int
    f: int          # evaluation function after the step


def wrap(value: int, width: int) -> int:
    """Two's-complement wrap of `value` to `width` signed bits."""
    value &= (1 << width) - 1
    return value - (1 << width) if value >> (width - 1) else value


def sign(value: int) -> int:
    return (value > 0) - (value < 0)


def within_half_step(a: int, b: int) -> bool:
    """|sqrt(b) - sqrt(a)| <= 1/2 for squared radii a, b, in integers (the test circle_setup computes)."""
    d, s = abs(a - b), min(a, b)
    return d == 0 or (4 * d - 1) ** 2 <= 16 * s


# ---------------------------------------------------------------- linear

def lin_std_steps(x: int, y: int) -> list[Step]:
    """Standard linear interpolation: one axis per tick, F = 0 at the start."""
    dx, dy = abs(x), abs(y)
    kox, koy, f, out = dx, dy, 0, []
    while kox or koy:
        if (f >= 0 and kox) or not koy:     # X step (or Y finished)
            f -= dy
            kox -= 1
            out.append(Step(sign(x), 0, f))
        else:                               # Y step
            f += dx
            koy -= 1
            out.append(Step(0, sign(y), f))
    return out


def lin_accel_steps(x: int, y: int) -> list[Step]:
    """Accelerated linear interpolation: the leading axis steps every tick."""
    x_leads = abs(x) >= abs(y)
    big, small = max(abs(x), abs(y)), min(abs(x), abs(y))
    f = -1 if big == small and big else 0   # a 45-degree line: all diagonal
    out = []
    for _ in range(big):
        if f >= 0:                          # axial
            f -= small
            d_long, d_short = 1, 0
        else:                               # diagonal
            f += big - small
            d_long, d_short = 1, 1
        dx, dy = (d_long, d_short) if x_leads else (d_short, d_long)
        out.append(Step(dx * sign(x), dy * sign(y), f))
    return out


def line_deviation(x: int, y: int, path) -> float:
    """Largest distance (in steps) from a visited point to the ideal line."""
    if x == 0 and y == 0:
        return 0.0
    px = py = worst = 0
    for s in path:
        px, py = px + s.dx, py + s.dy
        worst = max(worst, abs(px * y - py * x))
    return worst / (x * x + y * y) ** 0.5


class LinStd(CycleModel):
    """Cycle model of rtl/lin_std.v."""

    watch = {**MOTION_OUTPUTS, "f": True, "kox": False, "koy": False, "pos_x": True, "pos_y": True}

    def __init__(self, width: int = 32):
        self.width = width
        self.reset()
        self.pos_x = self.pos_y = 0

    def reset(self) -> None:
        self.busy = self.trig_x = self.trig_y = 0
        self.kox = self.koy = self.reg1 = self.reg2 = self.f = 0
        self.step_x = self.step_y = self.dir_x = self.dir_y = self.done = 0
        self.pos_x = self.pos_y = 0

    def clock(self, inputs) -> None:
        if inputs.get("rst"):
            self.reset()
            return
        load = inputs.get("start") and not self.busy
        finish = self.busy and not self.trig_x and not self.trig_y
        go = self.busy and inputs.get("tick")
        neg = self.f < 0
        xp = int(bool(go and self.trig_x and (not neg or not self.trig_y)))
        yp = int(bool(go and self.trig_y and (neg or not self.trig_x)))
        if load:
            x, y = wrap(inputs["x"], self.width), wrap(inputs["y"], self.width)
            self.kox, self.koy, self.f = abs(x), abs(y), 0
            self.reg1, self.reg2 = abs(x), -abs(y)
            self.trig_x, self.trig_y = int(x != 0), int(y != 0)
            self.dir_x, self.dir_y = int(x < 0), int(y < 0)
        else:
            if xp or yp:
                self.f += self.reg1 if yp else self.reg2
            if xp and self.kox == 1:
                self.trig_x = 0
            if yp and self.koy == 1:
                self.trig_y = 0
            self.kox -= xp
            self.koy -= yp
        if xp:
            self.pos_x = wrap(self.pos_x + (-1 if self.dir_x else 1), self.width)
        if yp:
            self.pos_y = wrap(self.pos_y + (-1 if self.dir_y else 1), self.width)
        self.busy = 1 if load else (0 if finish else self.busy)
        self.step_x, self.step_y, self.done = xp, yp, int(bool(finish))


class LinAccel(CycleModel):
    """Cycle model of rtl/lin_accel.v (f and the counter are internal nets)."""

    watch = {**MOTION_OUTPUTS, "f": True, "kol": False}

    def __init__(self, width: int = 32):
        self.width = width
        self.reset()

    def reset(self) -> None:
        self.busy = self.kol = self.reg1 = self.reg2 = self.f = self.x_leads = 0
        self.step_x = self.step_y = self.dir_x = self.dir_y = self.done = 0

    def clock(self, inputs) -> None:
        if inputs.get("rst"):
            self.reset()
            return
        load = inputs.get("start") and not self.busy
        at_end = self.kol == 0
        finish = self.busy and at_end
        go = self.busy and not at_end and inputs.get("tick")
        axial, diagonal = (int(bool(go and self.f >= 0)), int(bool(go and self.f < 0)))
        if load:
            x, y = wrap(inputs["x"], self.width), wrap(inputs["y"], self.width)
            big, small = max(abs(x), abs(y)), min(abs(x), abs(y))
            self.kol, self.f = big, -1 if big == small and big else 0
            self.reg1, self.reg2 = big - small, -small
            self.x_leads = int(abs(x) >= abs(y))
            self.dir_x, self.dir_y = int(x < 0), int(y < 0)
        elif axial or diagonal:
            self.f += self.reg1 if diagonal else self.reg2
            self.kol -= 1
        long_pulse, short_pulse = axial | diagonal, diagonal
        self.step_x = long_pulse if self.x_leads else short_pulse
        self.step_y = short_pulse if self.x_leads else long_pulse
        self.busy = 1 if load else (0 if finish else self.busy)
        self.done = int(bool(finish))


# ---------------------------------------------------------------- circular, first quadrant

def quadrant_error(x0: int, y0: int, x1: int, y1: int, ccw: bool) -> str | None:
    """Why circ_quadrant rejects the command, or None (rtl/circ_quadrant.v CHECK)."""
    if min(x0, y0, x1, y1) < 0:
        return "a coordinate is negative (first quadrant only)"
    if x0 == 0 and y0 == 0:
        return "the start point is the centre (R = 0)"
    if ccw and (x1 > x0 or y1 < y0):
        return "counter-clockwise in the first quadrant needs x1 <= x0 and y1 >= y0"
    if not ccw and (x1 < x0 or y1 > y0):
        return "clockwise in the first quadrant needs x1 >= x0 and y1 <= y0"
    if not within_half_step(x0 * x0 + y0 * y0, x1 * x1 + y1 * y1):
        return "the end point is more than half a step off the circle through the start point"
    return None


def circ_steps(x0: int, y0: int, x1: int, y1: int, ccw: bool, accel: bool) -> list[Step]:
    """Standard or accelerated circular interpolation in the first quadrant."""
    if quadrant_error(x0, y0, x1, y1, ccw):
        raise ValueError(quadrant_error(x0, y0, x1, y1, ccw))
    x, y, f = x0, y0, 0                                 # F = 0 at the start point
    kox, koy = abs(x1 - x0), abs(y1 - y0)
    ix, iy = (-1, 1) if ccw else (1, -1)                # direction of travel per axis
    out = []
    while kox or koy:
        # "in" moves the point inwards (x for CCW, y for CW), "out" outwards.
        in_coord, out_coord = (x, y) if ccw else (y, x)
        if not accel:
            want_in, want_out = f >= 0, f < 0
        elif in_coord > out_coord:                      # the out axis leads
            want_in, want_out = f >= 0, True
        else:                                           # the in axis leads
            want_in, want_out = True, f < 0
        want_x, want_y = (want_in, want_out) if ccw else (want_out, want_in)
        step_x = bool(kox) and (want_x or not koy)      # a finished axis gives its tick away
        step_y = bool(koy) and (want_y or not kox)
        dx, dy = ix * step_x, iy * step_y
        f += dx * (2 * x + dx) + dy * (2 * y + dy)      # -2x + 1, 2y + 1, -2x + 2y + 2, ...
        x, y = x + dx, y + dy
        kox, koy = kox - step_x, koy - step_y
        out.append(Step(dx, dy, f))
    return out


def radial_deviation(x0: int, y0: int, path, cx: int = 0, cy: int = 0) -> float:
    """Largest |r - R| (in steps) over the visited points; R from the start point."""
    r0 = ((x0 - cx) ** 2 + (y0 - cy) ** 2) ** 0.5
    x, y, worst = x0, y0, 0.0
    for s in path:
        x, y = x + s.dx, y + s.dy
        worst = max(worst, abs(((x - cx) ** 2 + (y - cy) ** 2) ** 0.5 - r0))
    return worst


class CircQuadrant(CycleModel):
    """Cycle model of rtl/circ_quadrant.v (the CLI's circ-std: ACCEL = 0, circ-accel: ACCEL = 1)."""

    IDLE, SETUP, CHECK, RUN = range(4)
    watch = {**MOTION_OUTPUTS, "error": False, "f": True, "half1": True,
             "half2": True, "kox": True, "koy": True}

    def __init__(self, width: int = 32, accel: bool = False):
        self.width, self.accel = width, accel
        self.reset()

    def sample(self, names=None):
        names = self.watch if names is None else names
        return {name: int(getattr(self, name.split(".")[-1])) for name in names}

    @property
    def busy(self) -> int:
        return int(self.state != self.IDLE)

    def reset(self) -> None:
        self.state = self.IDLE
        self.cmd = (0, 0, 0, 0)
        self.ccw = self.a = self.b = self.count = 0
        self.trig_x = self.trig_y = self.half1 = self.half2 = self.kox = self.koy = self.f = 0
        self.step_x = self.step_y = self.dir_x = self.dir_y = self.done = self.error = 0

    def clock(self, inputs) -> None:
        if inputs.get("rst"):
            self.reset()
            return
        act_x = act_y = 0
        at_end = self.state == self.RUN and not self.trig_x and not self.trig_y
        error = 0
        if self.state == self.IDLE:
            if inputs.get("start"):
                self.cmd = tuple(wrap(inputs[k], self.width) for k in ("x0", "y0", "x1", "y1"))
                self.ccw = int(bool(inputs.get("ccw")))
                # The RTL forms the squares with sequential multipliers (as circ_arc):
                # the check is in cycle 2 * WIDTH + 17.
                self.state, self.count = self.SETUP, 2 * self.width + 16
        elif self.state == self.SETUP:
            self.count -= 1
            if self.count == 0:
                x0, y0, x1, y1 = self.cmd
                self.a, self.b = x0 * x0 + y0 * y0, x1 * x1 + y1 * y1
                self.state = self.CHECK
        elif self.state == self.CHECK:
            x0, y0, x1, y1 = self.cmd
            bad = (min(self.cmd) < 0 or self.a == 0 or not within_half_step(self.a, self.b)
                   or (self.ccw and (x1 > x0 or y1 < y0)) or (not self.ccw and (x1 < x0 or y1 > y0)))
            error = int(bad)
            self.state = self.IDLE if bad else self.RUN
            self.dir_x, self.dir_y = self.ccw, 1 - self.ccw
            if bad:
                self.trig_x = self.trig_y = 0
            else:
                self.kox, self.koy = abs(x1 - x0), abs(y1 - y0)
                self.trig_x, self.trig_y = int(self.kox != 0), int(self.koy != 0)
                self.half1, self.half2 = (-x0, y0) if self.ccw else (x0, -y0)
                self.f = 0
        elif self.state == self.RUN:
            half_in, half_out = (self.half1, self.half2) if self.ccw else (self.half2, self.half1)
            trig_in, trig_out = (self.trig_x, self.trig_y) if self.ccw else (self.trig_y, self.trig_x)
            neg = self.f < 0
            if not self.accel:
                want_in, want_out = not neg, neg
            elif half_in + half_out < 0:                         # in > out: out leads
                want_in, want_out = not neg, True
            else:
                want_in, want_out = True, neg
            go = bool(inputs.get("tick"))
            act_in = int(go and trig_in and (want_in or not trig_out))
            act_out = int(go and trig_out and (want_out or not trig_in))
            if act_in or act_out:
                operand = (half_in + half_out) if act_in and act_out else (half_in if act_in else half_out)
                self.f += 2 * operand + (act_in & act_out) + 1
            act_x, act_y = (act_in, act_out) if self.ccw else (act_out, act_in)
            if act_x and self.kox == 1:
                self.trig_x = 0
            if act_y and self.koy == 1:
                self.trig_y = 0
            self.half1 += act_x
            self.half2 += act_y
            self.kox -= act_x
            self.koy -= act_y
            if at_end:
                self.state = self.IDLE
        self.step_x, self.step_y = act_x, act_y
        self.done, self.error = int(at_end), error
