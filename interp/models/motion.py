"""Golden models of the motion subsystem (SPEC §5: speed-setting block,
synchronization buffer; issue 6: step/dir stage, segment queue).

Step level, written like the lecture's rules:
  * `interval_costs`: the interval after a step on n axes is sqrt(n) times
    the axial one (fixed point, 2^FRAC = one axial step);
  * `line_steps`: a 2- or 3-axis line is two SU 1571551 lines that share the
    leading axis (each step of the leading axis is one tick of both);
  * `released`: what the drive sees, step by step.
Cycle level: `SyncFifo`, `StepSync`, `FeedRate`, `StepDir` mirror the
registers of rtl/sync_fifo.v, step_sync.v, feed_rate.v, step_dir.v; their
combinational outputs are properties of the current state and inputs.
"""
from __future__ import annotations

import math
from typing import Mapping

from .base import CycleModel
from .su1571551 import steps as su_steps

AXES = "xyz"


def interval_costs(frac: int) -> dict[int, int]:
    """Cost of a step on n axes in units of 2^-FRAC axial steps (rounded sqrt(n))."""
    one = 1 << frac
    return {0: one, 1: one, 2: int(math.sqrt(2) * one + 0.5), 3: int(math.sqrt(3) * one + 0.5)}


def line_order(d: tuple[int, int, int]) -> tuple[int, int, int]:
    """(leading axis, first minor, second minor): the longest axis leads, x first on ties."""
    lead = max(range(3), key=lambda k: (abs(d[k]), -k))
    minors = [k for k in range(3) if k != lead]
    return lead, minors[0], minors[1]


def line_steps(dx: int, dy: int, dz: int = 0) -> list[tuple[int, int, int]]:
    """Steps (sx, sy, sz) of a line: core A runs (L, minor 1), core B (L, minor 2)."""
    d = (dx, dy, dz)
    lead, m1, m2 = line_order(d)
    big = abs(d[lead])
    sign = -1 if d[lead] < 0 else 1
    a, b = su_steps(big, d[m1]), su_steps(big, d[m2])
    out = []
    for sa, sb in zip(a, b):
        step = [0, 0, 0]
        step[lead], step[m1], step[m2] = sa.dx * sign, sa.dy, sb.dy
        out.append(tuple(step))
    return out


def path_length(steps) -> float:
    return sum(math.sqrt(sum(abs(c) for c in s)) for s in steps)


class SyncFifo(CycleModel):
    """rtl/sync_fifo.v (entries as integers; stale entries stay visible on dout)."""

    watch = {"dout": False, "valid": False, "full": False, "level": False, "overflow": False}

    def __init__(self, width: int, depth: int, lw: int):
        self.width, self.depth, self.lw = width, depth, lw
        self.reset()

    def reset(self) -> None:
        self.mem = [0] * (1 << self.lw)
        self.rd = self.wr = self.level = 0
        self.inputs: Mapping[str, int] = {}

    def _next(self, p: int) -> int:
        return 0 if p == self.depth - 1 else p + 1

    @property
    def valid(self) -> int:
        return int(self.level != 0)

    @property
    def full(self) -> int:
        return int(self.level == self.depth)

    @property
    def dout(self) -> int:
        return self.mem[self.rd]

    def transfer(self, push: int, pop: int) -> tuple[bool, bool]:
        take = bool(pop) and self.valid
        put = bool(push) and (not self.full or take)
        return put, take

    @property
    def overflow(self) -> int:
        put, _ = self.transfer(self.inputs.get("push", 0), self.inputs.get("pop", 0))
        return int(bool(self.inputs.get("push", 0)) and not put)

    def clock(self, inputs: Mapping[str, int]) -> None:
        if inputs.get("rst"):
            self.reset()
            return
        put, take = self.transfer(inputs.get("push", 0), inputs.get("pop", 0))
        if put:
            self.mem[self.wr] = inputs["din"] & ((1 << self.width) - 1)
            self.wr = self._next(self.wr)
        if take:
            self.rd = self._next(self.rd)
        self.level += int(put) - int(take)
        self.inputs = dict(inputs)      # `overflow` shows these inputs on the new state


def pack(step: int, dirs: int, data: int, axes: int) -> int:
    return step | (dirs << axes) | (data << (2 * axes))


class StepSync(CycleModel):
    """rtl/step_sync.v: a SyncFifo of {data, dir, step} plus STOP with ticks in flight."""

    watch = {"stop": False, "out_valid": False, "out_step": False, "out_dir": False,
             "out_data": False, "level": False, "overflow": False}

    def __init__(self, axes: int = 3, depth: int = 2, latency: int = 1, data_w: int = 1, lw: int = 2):
        self.axes, self.depth, self.latency, self.data_w = axes, depth, latency, data_w
        self.store = SyncFifo(data_w + 2 * axes, depth, lw)
        self.reset()

    def reset(self) -> None:
        self.store.reset()
        self.given = [0] * self.latency     # newest first
        self.overflow = 0

    @property
    def stop(self) -> int:
        return int(self.store.level + sum(self.given) >= self.depth)

    @property
    def out_valid(self) -> int:
        return self.store.valid

    @property
    def level(self) -> int:
        return self.store.level

    def _head(self, shift: int, bits: int) -> int:
        return (self.store.dout >> shift) & ((1 << bits) - 1)

    @property
    def out_step(self) -> int:
        return self._head(0, self.axes)

    @property
    def out_dir(self) -> int:
        return self._head(self.axes, self.axes)

    @property
    def out_data(self) -> int:
        return self._head(2 * self.axes, self.data_w)

    def clock(self, inputs: Mapping[str, int]) -> None:
        if inputs.get("rst"):
            self.reset()
            return
        push, pop = int(bool(inputs["in_step"])), inputs["tick"]
        put, _ = self.store.transfer(push, pop)
        if push and not put:
            self.overflow = 1
        self.given = [1 - self.stop] + self.given[:-1]
        self.store.clock({"push": push, "pop": pop,
                          "din": pack(inputs["in_step"], inputs["in_dir"], inputs["in_data"], self.axes)})


class FeedRate(CycleModel):
    """rtl/feed_rate.v: phase accumulator, a leaving step costs sqrt(axes) * 2^FRAC."""

    watch = {"tick": False, "acc": True}

    def __init__(self, frac: int = 16):
        self.costs = interval_costs(frac)
        self.reset()

    def reset(self) -> None:
        self.acc = self.feed_q = 0

    @property
    def tick(self) -> int:
        return int(self.acc >= 0)

    def clock(self, inputs: Mapping[str, int]) -> None:
        if inputs.get("rst"):
            self.reset()
        elif inputs["take"] and self.tick:
            phase = self.acc if inputs["feed"] == self.feed_q else 0   # a new feed starts at phase 0
            self.acc = phase + inputs["feed"] - self.costs[inputs["axes"]]
            self.feed_q = inputs["feed"]
        elif not self.tick:
            self.acc += self.feed_q


IDLE, HOLD, SETUP, PULSE = range(4)


class StepDir(CycleModel):
    """rtl/step_dir.v: pulse width, direction setup and hold in clock cycles."""

    watch = {"ready": False, "step": False, "dir": False, "state": False}

    def __init__(self, axes: int = 3, tw: int = 8):
        self.axes, self.tw = axes, tw
        self.reset()

    def reset(self) -> None:
        self.state, self.count = IDLE, 0
        self.since_fall = (1 << self.tw) - 1
        self.pend_step = self.pend_dir = self.step = self.dir = 0

    @property
    def ready(self) -> int:
        return int(self.state == IDLE)

    def clock(self, i: Mapping[str, int]) -> None:
        if i.get("rst"):
            self.reset()
            return
        width = i["pulse_width"] or 1
        start_pulse = False
        since = min(self.since_fall + 1, (1 << self.tw) - 1)
        if self.state == IDLE and i["valid"]:
            self.pend_step, self.pend_dir = i["step_in"], i["dir_in"]
            if i["step_in"] & (i["dir_in"] ^ self.dir):
                self.state = HOLD
            else:
                start_pulse = True
        elif self.state == HOLD and self.since_fall + 1 >= i["hold"]:
            self.dir = (self.dir & ~self.pend_step) | (self.pend_dir & self.pend_step)
            if i["setup"] == 0:
                start_pulse = True
            else:
                self.count, self.state = i["setup"], SETUP
        elif self.state == SETUP:
            if self.count == 1:
                start_pulse = True
            else:
                self.count -= 1
        elif self.state == PULSE:
            if self.count == 1:
                self.step, since, self.state = 0, 0, IDLE
            else:
                self.count -= 1
        if start_pulse:
            self.step, self.count, self.state = self.pend_step, width, PULSE
        self.since_fall = since


class TimingMonitor:
    """Checks a driver's timing on every sampled cycle, per axis.

    width: each high run lasts exactly `pulse` samples; setup: a rise comes
    >= setup samples after the axis' last dir change; hold: a dir change comes
    >= hold samples after the axis' last fall; dir never changes while high.
    Counts the pulses per axis and direction (position).
    """

    def __init__(self, axes: int, pulse: int, setup: int, hold: int):
        self.axes, self.pulse, self.setup, self.hold = axes, max(pulse, 1), setup, hold
        self.cycle = 0
        self.prev_step = self.prev_dir = 0
        self.rise = [None] * axes
        self.fall = [-10**9] * axes
        self.change = [-10**9] * axes
        self.position = [0] * axes
        self.pulses = []            # (cycle, step bits, dir bits) at each rising edge

    def sample(self, step: int, dirs: int) -> None:
        c = self.cycle
        rising = 0
        for a in range(self.axes):
            s, d = step >> a & 1, dirs >> a & 1
            ps, pd = self.prev_step >> a & 1, self.prev_dir >> a & 1
            if ps and not s:
                assert c - self.rise[a] == self.pulse, \
                    f"cycle {c} axis {a}: pulse width {c - self.rise[a]} != {self.pulse}"
                self.fall[a] = c
            if d != pd:
                assert not (s and ps), f"cycle {c} axis {a}: dir changed while step high"
                assert c - self.fall[a] >= self.hold, \
                    f"cycle {c} axis {a}: hold {c - self.fall[a]} < {self.hold}"
                self.change[a] = c
            if s and not ps:
                assert c - self.change[a] >= self.setup, \
                    f"cycle {c} axis {a}: setup {c - self.change[a]} < {self.setup}"
                self.rise[a] = c
                self.position[a] += -1 if d else 1
                rising |= 1 << a
        if rising:
            self.pulses.append((c, rising, dirs & rising))
        self.prev_step, self.prev_dir = step, dirs
        self.cycle += 1
