# SPDX-License-Identifier: Apache-2.0
"""Golden models of the production arc core rtl/circ_arc.v.

Step-level model (`arc_steps`), relative to the centre, P = (u, v), F = u^2 + v^2 - R^2
with R^2 = |start - centre|^2 (F = 0 at the start point, as in the lecture):

  tangent t = (-v, u) for CCW, (v, -u) for CW; leading axis = its larger component
  (on a diagonal |u| = |v|: the leading axis of the octant ahead);
  a = unit step along the leading axis, sign of t;  b = unit step along the other
  axis, sign of t (0 there: towards the centre);
  midpoint M = P + a + b/2: pick the candidate (P + a or P + a + b) on the far side
  of the circle from M: the outer one when F(M) < 0, the inner one otherwise.
  End: when the next point would reach or pass the ray from the centre through the
  end point, the last step goes to the end point.

`CircArc` is the cycle model: the registers the bench compares (E, u, v) as in the
RTL, cross and dot as plain integers (the RTL keeps C = turn * cross - 1 and
D = dot - 1 as a high and a low part; only their signs are used), and the set-up
as a count of cycles (the RTL forms its products with sequential multipliers).
"""
from __future__ import annotations

from .base import MOTION_OUTPUTS, CycleModel
from .lecture import Step, sign, within_half_step, wrap


def arc_error(cx: int, cy: int, x0: int, y0: int, x1: int, y1: int, width: int = 32) -> str | None:
    """Why circ_arc rejects the command, or None."""
    limit = 1 << (width - 3)
    rel = (x0 - cx, y0 - cy, x1 - cx, y1 - cy)
    if any(not -limit < r < limit for r in rel):
        return f"a point is {limit} or more steps from the centre along an axis (WIDTH = {width} limit)"
    u0, v0, u1, v1 = rel
    if u0 == 0 and v0 == 0:
        return "the start point is the centre (R = 0)"
    if not within_half_step(u0 * u0 + v0 * v0, u1 * u1 + v1 * v1):
        return "the end point is more than half a step off the circle through the start point"
    return None


def _octant(u: int, v: int, ccw: bool):
    """(x_major, a, b): leading axis and the unit steps along it (a) and across (b)."""
    tx, ty = (-v, u) if ccw else (v, -u)
    x_major = abs(v) > abs(u) or (abs(v) == abs(u) and ((u * v > 0) == ccw))
    if x_major:
        return True, (sign(tx), 0), (0, sign(ty) or -sign(v))
    return False, (0, sign(ty)), (sign(tx) or -sign(u), 0)


def arc_steps(cx, cy, x0, y0, x1, y1, ccw: bool, full: bool = False) -> list[Step]:
    """The step sequence of an arc; Step.f is F = u^2 + v^2 - R^2 after the step."""
    u, v, u1, v1 = x0 - cx, y0 - cy, x1 - cx, y1 - cy
    r2 = u * u + v * v
    out: list[Step] = []
    if (u, v) == (u1, v1) and not full:
        return out
    turn = 1 if ccw else -1
    while True:
        _, (ax, ay), (bx, by) = _octant(u, v, ccw)
        mid = (u + ax + bx / 2) ** 2 + (v + ay + by / 2) ** 2 - r2          # F(M)
        diag_is_outer = (u + ax + bx) ** 2 + (v + ay + by) ** 2 > (u + ax) ** 2 + (v + ay) ** 2
        take_diagonal = (mid < 0) == diag_is_outer
        dx, dy = (ax + bx, ay + by) if take_diagonal else (ax, ay)
        ahead = turn * (u * v1 - v * u1) > 0                                 # end still ahead
        reached = turn * ((u + dx) * v1 - (v + dy) * u1) <= 0
        if ahead and reached and (u + dx) * u1 + (v + dy) * v1 > 0:
            dx, dy = u1 - u, v1 - v                                          # last step: the end
            if max(abs(dx), abs(dy)) > 1:
                raise AssertionError(f"end point {(x1, y1)} is {dx, dy} away at the ray")
        u, v = u + dx, v + dy
        out.append(Step(dx, dy, u * u + v * v - r2))
        if (u, v) == (u1, v1) and (ahead and reached):
            return out


def arc_setup_cycles(width: int = 32) -> int:
    """Cycles from `start` to the check of rtl/circ_arc.v: load, two multiplier
    rounds (seq_mult at WIDTH + 1 bits: WIDTH + 4 cycles each) and three
    two-cycle sums; the check is in cycle 2 * WIDTH + 17, the first step is taken five
    cycles later (the stepper registers `run`, then loads its loop in three cycles) and its
    strobes come a cycle after it."""
    return 2 * width + 17


RELOAD_CYCLES = 6       # after a step into a new octant, no step (rtl/arc_stepper.v)
START_CYCLES = 3        # after `run` is registered, no step: reload cycles 4 to 6

STEP_OUTPUTS = {"step_x": False, "step_y": False, "dir_x": False, "dir_y": False}


class ArcStepper(CycleModel):
    """Cycle model of rtl/arc_stepper.v, circ_arc's run loop.

    `run` is registered: what follows holds from the cycle after it.
    While `run` is low the point follows the inputs (u0, v0) and E = 0.  With `run`, one
    step of `arc_steps` per tick from the third cycle on (the loop loads in the first two);
    a step into a new octant is followed by six reload
    cycles, which take no step (`tick` is an enable, as the synchronization buffer's ~STOP).
    The decision is taken a cycle before the step is out: the strobes, dir levels, `fin`
    and the point and E they lead to show a cycle after the tick that took the step.
    """

    watch = {**STEP_OUTPUTS, "fin": False, "u": True, "v": True, "e": True}

    def __init__(self):
        self.reset()

    def reset(self) -> None:
        self.u = self.v = self.e = 0
        self.step_x = self.step_y = self.dir_x = self.dir_y = self.fin = 0
        self.point = (0, 0, 0)                  # the decision's point and E, a cycle ahead
        self.pending = (0, 0, 0, 0, 0)          # its step: act_x, act_y, neg_x, neg_y, fin
        self.reload = 0
        self.done = False                       # the last step is decided
        self.run_q = 0                          # `run`, registered

    def clock(self, inputs) -> None:
        if inputs.get("rst"):                     # control reset; the point follows the inputs
            self.reset()
            self.u, self.v = inputs.get("u0", 0), inputs.get("v0", 0)
            self.point = (self.u, self.v, 0)
            return
        run, tick = self.run_q, inputs.get("tick")
        self.run_q = int(bool(inputs.get("run")))
        go = run and not self.done and not self.reload and tick
        act_x = act_y = neg_x = neg_y = fin = 0
        reload = max(self.reload - 1, 0)        # reload cycles left after this one
        shown = self.point                      # the point the step stage shows next
        if not run:
            self.point = shown = (inputs["u0"], inputs["v0"], 0)
            self.done = False
            reload = START_CYCLES               # a start: the loop's last three reload cycles
        elif go:
            (u, v, e), u1, v1, ccw = self.point, inputs["u1"], inputs["v1"], inputs["ccw"]
            octant = _octant(u, v, ccw)
            _, (ax, ay), (bx, by) = octant
            pa, pb = u * ax + v * ay, u * bx + v * by
            axial_e = e + 2 * pa + 1
            take_diagonal = (axial_e + pb < 0) == (pb >= 0)          # T = E + 2 P.a + P.b + 1
            sx, sy = (ax + bx, ay + by) if take_diagonal else (ax, ay)
            turn = 1 if ccw else -1
            ahead = turn * (u * v1 - v * u1) > 0
            reached = turn * ((u + sx) * v1 - (v + sy) * u1) <= 0
            last = ahead and reached and (u + sx) * u1 + (v + sy) * v1 > 0
            if last:
                sx, sy = sign(u1 - u), sign(v1 - v)
            act_x, act_y, neg_x, neg_y = int(sx != 0), int(sy != 0), int(sx < 0), int(sy < 0)
            self.point = (u + sx, v + sy, axial_e + (2 * pb + 1 if take_diagonal else 0))
            fin = int(last)
            self.done = last
            reload = RELOAD_CYCLES if not last and _octant(u + sx, v + sy, ccw) != octant else 0
        self.u, self.v, self.e = shown
        p_act_x, p_act_y, p_neg_x, p_neg_y, p_fin = self.pending
        if p_act_x:
            self.dir_x = p_neg_x
        if p_act_y:
            self.dir_y = p_neg_y
        self.step_x, self.step_y, self.fin = p_act_x, p_act_y, p_fin
        self.pending = (act_x, act_y, neg_x, neg_y, fin)
        self.reload = reload


class CircArc(CycleModel):
    """Cycle model of rtl/circ_arc.v: the set-up as a count of cycles, then ArcStepper."""

    IDLE, SETUP, CHECK, RUN, LAST = range(5)
    watch = {**MOTION_OUTPUTS, "error": False, "e": True, "pos_u": True, "pos_v": True}

    def __init__(self, width: int = 32):
        self.width = width
        self.stepper = ArcStepper()
        self.reset()

    @property
    def busy(self) -> int:
        return int(self.state != self.IDLE)

    def __getattr__(self, name):            # the stepper's outputs, as circ_arc shows them
        names = {"step_x": "step_x", "step_y": "step_y", "dir_x": "dir_x", "dir_y": "dir_y",
                 "e": "e", "pos_u": "u", "pos_v": "v"}
        if name in names:
            return getattr(self.__dict__["stepper"], names[name])
        raise AttributeError(name)

    def reset(self) -> None:
        self.state = self.IDLE
        self.u0 = self.v0 = self.u1 = self.v1 = self.ccw = self.full = 0
        self.a = self.b = self.count = 0
        self.done = self.error = 0

    def clock(self, inputs) -> None:
        fin = self.stepper.fin
        stepper_inputs = {"rst": inputs.get("rst"), "tick": inputs.get("tick"), "u0": self.u0,
                          "v0": self.v0, "u1": self.u1, "v1": self.v1, "ccw": self.ccw}
        # The stepper registers `run`: RUN of this cycle, until the last step is out.
        run = int(self.state == self.RUN and not fin)
        self.update(inputs, fin)
        self.stepper.clock({**stepper_inputs, "run": run})

    def update(self, inputs, fin) -> None:
        if inputs.get("rst"):
            self.reset()
            return
        error = 0
        w = self.width
        state = self.state
        if state == self.IDLE:                  # the command follows the inputs; `start` keeps it
            cx, cy = wrap(inputs["cx"], w), wrap(inputs["cy"], w)
            self.u0, self.v0 = wrap(inputs["x0"], w) - cx, wrap(inputs["y0"], w) - cy
            self.u1, self.v1 = wrap(inputs["x1"], w) - cx, wrap(inputs["y1"], w) - cy
            self.ccw, self.full = int(bool(inputs.get("ccw"))), int(bool(inputs.get("full")))
            if inputs.get("start"):
                self.state, self.count = self.SETUP, arc_setup_cycles(w) - 1
        elif state == self.SETUP:
            self.count -= 1
            if self.count == 0:
                u, v, u1, v1 = self.u0, self.v0, self.u1, self.v1
                self.a, self.b = u * u + v * v, u1 * u1 + v1 * v1
                self.state = self.CHECK
        elif state == self.CHECK:
            limit = 1 << (w - 3)
            fits = all(-limit < r < limit for r in (self.u0, self.v0, self.u1, self.v1))
            bad = not fits or self.a == 0 or not within_half_step(self.a, self.b)
            error = int(bad)
            at_start = (self.u0, self.v0) == (self.u1, self.v1)
            self.state = self.IDLE if bad else self.LAST if at_start and not self.full else self.RUN
        elif state == self.RUN and fin:
            self.state = self.IDLE
        elif state == self.LAST:
            self.state = self.IDLE
        self.done, self.error = int(state == self.LAST or (state == self.RUN and fin)), error
