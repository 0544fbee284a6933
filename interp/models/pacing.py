# SPDX-License-Identifier: Apache-2.0
"""Golden models of the path-speed profile's S-curve filter and step pacer.

The speed-setting block of the lecture ("БЗС") becomes three parts: a virtual
trapezoid (rtl/speed_ramp.v), the S-curve filter (rtl/jerk_filter.v) and the
step pacer (rtl/step_pacer.v).  This module holds the last two.

Readable equations (what the cycle models must agree with):

  * `moving_sum(speeds, m, b)`: the S-curve.  F(t) = sum over j < m of
    v(t - j b), the virtual speed v summed over the last m = 2^jerk_shift
    blocks of b = 2^block_shift clocks.  Its sum over time is exactly m times
    the sum of v (each v(t) is counted by m clocks' F), so the step domain
    travels m times the virtual distance in units m times smaller: the
    same path.  m = 1 is the trapezoid (F = v, infinite jerk).
  * `pace(sums, steps, shift, frac)`: the step domain.  phase += F every
    clock; the waiting step leaves when phase >= cost << shift and the output
    stage is ready, then phase -= cost << shift.  No distance is ever lost:
    phase = sum of F so far - (sum of the costs of the steps gone) << shift.

Cycle level: `JerkFilter`, `StepPacer` mirror the registers of
rtl/jerk_filter.v (with its delay line rtl/code_delay.v) and rtl/step_pacer.v;
their combinational outputs are properties of the current state and inputs.
"""
from __future__ import annotations

from typing import Iterable, Mapping, Sequence

from .base import CycleModel
from .motion import interval_costs


# ---------------------------------------------------------------- equations
def moving_sum(speeds: Sequence[int], m: int, b: int = 1) -> list[int]:
    """F(t) = sum_{j<m} v(t - j b) for every clock t of `speeds` (v = 0 before t = 0)."""
    return [sum(speeds[t - j * b] for j in range(m) if t - j * b >= 0) for t in range(len(speeds))]


def pace(sums: Iterable[int], steps: Sequence[int], shift: int = 0,
         ready: Iterable[int] | None = None) -> tuple[list[int], int]:
    """Clocks at which the steps (their costs, in order) leave, and the final phase.

    Every step waits from clock 0; `ready` (default always) is the output
    stage's ready per clock.  One step per clock at most.
    """
    phase, k, fired = 0, 0, []
    ready = iter(ready) if ready is not None else None
    for t, f in enumerate(sums):
        ok = next(ready) if ready is not None else 1
        if k < len(steps) and ok and phase >= steps[k] << shift:
            phase -= steps[k] << shift
            fired.append(t)
            k += 1
        phase += f
    return fired, phase


def lecture_cost(axes: int, frac: int) -> int:
    """Cost of a step on `axes` axes when cmd_cost = 0: 1, sqrt2, sqrt3 x 2^FRAC, rounded."""
    return interval_costs(frac)[axes]


# ---------------------------------------------------------------- cycle models
def code_of(up: int, down: int, pending: int = 0) -> int:
    """The 2-bit code of a block: up - down - pending (a drop made inside the block),
    in two's complement (-2 .. +1 quanta)."""
    return (int(bool(up)) - int(bool(down)) - int(bool(pending))) & 3


def code_value(code: int) -> int:
    """The quanta of a code: -2 .. +1."""
    return code - 4 if code & 2 else code


class JerkFilter(CycleModel):
    """rtl/jerk_filter.v: moving sum of the block speeds over 2^jerk_shift blocks.

    State: D = v_now - v_delayed and F (sum), both updated on block ticks only:
    D += A (c_now - c_delayed), F += D (the new D).  The codes go through a
    delay line of 2^MW entries (c_delayed = the code written 2^J ticks ago);
    `count` (entries written since the last restart, saturating at 2^MW)
    masks entries older than the restart.  jerk_shift is latched into `shift`
    only while empty; a new value restarts the line.  A `down` without `block`
    (the last drop of a stop, inside a block) is `pending` until the block's
    end; meanwhile the filter books A << shift per clock into `owed` and pays
    it back from F: sum = F - min(owed, F).
    """

    watch = {"sum": False, "empty": False, "shift": False, "delta": True, "total": False,
             "owed": False, "pending": False}

    def __init__(self, feed_w: int = 16, mw: int = 6):
        self.feed_w, self.mw = feed_w, mw
        self.sum_w = feed_w + mw
        self.depth = 1 << mw
        self.mem = [0] * self.depth       # the RAM is not reset; `count` masks it
        self.reset()

    def reset(self, jerk_shift: int = 0) -> None:
        self.delta = self.total = 0       # D (signed) and F
        self.count = self.wp = self.q = self.c_last = 0
        self.pending = self.owed = 0
        self.shift = min(jerk_shift, self.mw)
        self.inputs: Mapping[str, int] = {}

    # combinational outputs on the current state and inputs
    @property
    def empty(self) -> int:
        return int(self.total == 0 and self.delta == 0 and self.inputs.get("speed", 0) == 0
                   and self.owed == 0 and not self.pending)

    @property
    def pay(self) -> int:
        return 0 if self.shift == 0 else min(self.owed, self.total)

    @property
    def sum(self) -> int:
        return self.inputs.get("speed", 0) if self.shift == 0 else self.total - self.pay

    def set_inputs(self, inputs: Mapping[str, int]) -> None:
        """Show combinational outputs for these inputs before the edge."""
        self.inputs = dict(inputs)

    def clock(self, i: Mapping[str, int]) -> None:
        self.inputs = dict(i)
        if i.get("rst"):
            self.reset(i.get("jerk_shift", 0))
            self.inputs = dict(i)
            return
        m = 1 << self.shift
        empty = self.empty
        a = i["speed_quantum"]
        pay, accrue = self.pay, (a << self.shift if self.pending and self.shift else 0)
        c_now = code_of(i["up"], i["down"], self.pending)
        self.owed += accrue - pay
        self.pending = int(not i["block"] and bool(self.pending or i["down"]))
        if i["block"]:
            if m == 1:
                c_del = self.c_last if self.count >= 1 else 0
            else:
                c_del = self.q if self.count >= m else 0
            self.delta += a * (code_value(c_now) - code_value(c_del))
            self.total += self.delta
            self.q = self.mem[(self.wp + 1 - m) % self.depth]     # read before the write
            self.mem[self.wp] = c_now
            self.c_last = c_now
            self.wp = (self.wp + 1) % self.depth
            self.count = min(self.count + 1, self.depth)
        new_shift = min(i["jerk_shift"], self.mw)
        if empty and new_shift != self.shift:
            self.shift = new_shift
            self.count = 1 if i["block"] else 0


class StepPacer(CycleModel):
    """rtl/step_pacer.v: phase += sum every clock; a step leaves at phase >= cost << shift."""

    watch = {"fire": False, "due": False, "phase": False, "overrun": False}

    def __init__(self, feed_w: int = 16, frac: int = 16, mw: int = 6, guard: int = 8):
        self.feed_w, self.frac, self.mw, self.guard = feed_w, frac, mw, guard
        self.cost_w = max(feed_w, frac + 1)
        self.phase_w = self.cost_w + mw + guard
        self.costs = interval_costs(frac)
        self.reset()

    def reset(self) -> None:
        self.phase = self.overrun = 0
        self.inputs: Mapping[str, int] = {}

    def need(self, i: Mapping[str, int]) -> int:
        cost = i.get("step_cost", 0) or self.costs[i.get("step_axes", 0)]
        return cost << min(i.get("jerk_shift", 0), self.mw)

    @property
    def due(self) -> int:
        return int(self.phase >= self.need(self.inputs))

    @property
    def fire(self) -> int:
        i = self.inputs
        return int(bool(i.get("step_valid")) and bool(i.get("drive_ready")) and self.due)

    def set_inputs(self, inputs: Mapping[str, int]) -> None:
        self.inputs = dict(inputs)

    def clock(self, i: Mapping[str, int]) -> None:
        self.inputs = dict(i)
        if i.get("rst"):
            self.reset()
            self.inputs = dict(i)
            return
        nxt = (self.phase - self.need(i) if self.fire else self.phase) + i["sum"]
        top = (1 << self.phase_w) - 1
        if nxt > top:
            nxt, self.overrun = top, 1
        self.phase = nxt
