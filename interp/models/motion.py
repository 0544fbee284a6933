# SPDX-License-Identifier: Apache-2.0
"""Golden models of the motion subsystem (the lecture's speed-setting block and
synchronization buffer; the step/dir stage and the segment queue).

Step level, written like the lecture's rules:
  * `interval_costs`: the interval after a step on n axes is sqrt(n) times
    the axial one (fixed point, 2^FRAC = one axial step);
  * `line_steps`: a 2- or 3-axis line is two SU 1571551 lines that share the
    leading axis (each step of the leading axis is one tick of both);
  * `released`: what the drive sees, step by step.
  * `helix_steps`, `to_machine`: an arc in its plane's (u, v) with the helix
    axis w spread by a line (N, travel) over its steps, mapped to (x, y, z).
Cycle level: `SyncFifo`, `StepSync`, `FeedRate`, `StepDir`, `ArcPlane`,
`MotionTop` mirror the registers of rtl/sync_fifo.v, step_sync.v, feed_rate.v,
step_dir.v, arc_plane.v, motion_top.v (motion_cores.v and line_pair.v inline in MotionTop; the
speed-setting block rtl/path_profile.v is interp.models.profile.PathProfile); their
combinational outputs are properties of the current state and inputs.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping

from .base import CycleModel
from .speed_ramp import BLOCK_SHIFT_MIN
from .su1571551 import steps as su_steps

AXES = "xyz"


def rounded_root(n: int) -> int:
    """round(sqrt(n)) for an integer n, exactly (as feed_rate.v's constant function)."""
    r = math.isqrt(n)
    return r + 1 if n - r * r > r else r


def interval_costs(frac: int) -> dict[int, int]:
    """Cost of a step on n axes in units of 2^-FRAC axial steps (sqrt(n) 2^FRAC, rounded)."""
    one = 1 << frac
    return {0: one, 1: one, 2: rounded_root(2 << 2 * frac), 3: rounded_root(3 << 2 * frac)}


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
    """rtl/sync_fifo.v (entries as integers; dout is zero while empty)."""

    watch = {"dout": False, "valid": False, "full": False, "level": False, "overflow": False}

    def __init__(self, width: int, depth: int, lw: int):
        self.width, self.depth, self.lw = width, depth, lw
        self.reset()

    def reset(self) -> None:
        self.mem = [0] * (1 << self.lw)             # stale after a reset in the RTL, never shown
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
        return self.mem[self.rd] if self.valid else 0

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
        if c == 0:                          # the levels the run starts from
            self.prev_step, self.prev_dir = step, dirs
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


# ---------------- segment queue (rtl/motion_top.v), step level ----------------

LINE, ARC_CW, ARC_CCW, CURVE, DWELL, EVENT = range(6)
E_KIND, E_FEED, E_RANGE, E_CORE, E_QUEUE, E_SYNC, E_PLANE, E_PROFILE, E_LATE, E_OVERRUN = range(1, 11)
ERROR_TEXT = {E_KIND: "unknown command kind", E_FEED: "feed 0", E_RANGE: "coordinate out of range",
              E_CORE: "the core refused the command (a fault: motion stopped)", E_QUEUE: "queue overflow",
              E_SYNC: "step buffer overflow", E_PLANE: "arc in plane 3",
              E_PROFILE: "bad profile (rate 0 or above 2^PF, length 0, limit below feed, block_shift below 2)",
              E_LATE: "a segment ended above its target speed (too short for the look-ahead set-up)",
              E_OVERRUN: "the steps were asked faster than the output stage makes them until the pacer "
                         "overran (distance lost: motion stopped)"}
PROFILE_FIELDS = ("limit", "exit", "rate", "cost", "length", "budget")
FIELDS = ("x", "y", "z", "i", "j", "k", "l")
PLANES = {0: "XY", 1: "ZX", 2: "YZ"}
# plane -> the machine axes (0 x, 1 y, 2 z) of u, v, w
PLANE_AXES = {0: (0, 1, 2), 1: (2, 0, 1), 2: (1, 2, 0)}


def to_machine(plane: int, u: int, v: int, w: int) -> tuple[int, int, int]:
    """A step (u, v, w) in the arc's plane as (x, y, z)."""
    out = [0, 0, 0]
    for axis, value in zip(PLANE_AXES[plane], (u, v, w)):
        out[axis] = value
    return tuple(out)


def helix_steps(arc: list[tuple[int, int]], travel: int, count: int) -> list[tuple[int, int, int]]:
    """(u, v, w) steps of a helix (rtl/arc_plane.v): core A runs (N, travel) with N = count,
    or 0 for count <= 0, one tick per arc step; the w travel left when the arc ends follows
    one step per entry."""
    lead = max(count, 0)
    spread = su_steps(lead, travel) if travel else []
    out = []
    for k, (u, v) in enumerate(arc):
        out.append((u, v, spread[k].dy if k < len(spread) else 0))
    left = abs(travel) - sum(abs(s[2]) for s in out)
    sign = -1 if travel < 0 else 1
    return out + [(0, 0, sign)] * left


@dataclass
class Command:
    """One entry of motion_top's queues (the ports cmd_kind, cmd_feed, cmd_x ... cmd_l, cmd_plane,
    and the profile cmd_limit, cmd_exit, cmd_rate, cmd_cost, cmd_length, cmd_budget)."""

    kind: int
    feed: int = 0
    x: int = 0
    y: int = 0
    z: int = 0
    i: int = 0
    j: int = 0
    k: int = 0
    l: int = 0          # noqa: E741 (the port's name)
    source: int = 0     # G-code line number, for messages
    plane: int = 0      # arcs: 0 XY, 1 ZX, 2 YZ
    limit: int = 0      # v max for override > 100 % (>= feed)
    exit: int = 0       # exit speed, quanta
    rate: int = 0       # acceleration p * 2^PF
    cost: int = 0       # path units per step event (0: the lecture's costs)
    length: int = 0     # exact sum of the step costs
    budget: int = 0     # braking budget Z0

    def ports(self) -> dict[str, int]:
        return {"cmd_kind": self.kind, "cmd_plane": self.plane, "cmd_feed": self.feed,
                **{f"cmd_{f}": getattr(self, f) for f in FIELDS},
                **{f"cmd_{f}": getattr(self, f) for f in PROFILE_FIELDS}}

    def row(self) -> tuple[int, ...]:
        """The 16 integers of a native command file line."""
        return (self.kind, self.plane, self.feed, *(getattr(self, f) for f in FIELDS),
                *(getattr(self, f) for f in PROFILE_FIELDS))


def bad_profile(cmd: Command, pf: int) -> bool:
    """motion_top's push check of a move's profile (error 8)."""
    return cmd.kind in (LINE, ARC_CW, ARC_CCW, CURVE) and (
        not 1 <= cmd.rate <= 1 << pf or cmd.length <= 0 or cmd.limit < cmd.feed)


def inline(cmd: Command) -> bool:
    """An inline EVENT (plane bit 0): it runs when the dispatcher reaches it, without a stop,
    and takes no entry of the profile queue (a laser's power along a path)."""
    return cmd.kind == EVENT and bool(cmd.plane & 1)


def next_not_inline(commands) -> list:
    """For each command, the next one after it that is not an inline event (None at the end):
    what a move runs into, as the speed generator sees it."""
    after, out = None, [None] * len(commands)
    for n in range(len(commands) - 1, -1, -1):
        out[n] = after
        after = after if inline(commands[n]) else commands[n]
    return out


def command_steps(cmd: Command, width: int = 16, pf: int | None = None) -> tuple[list[tuple[int, int, int]], int]:
    """(steps, error code) of one command by the step-level models of its core; with `pf`
    the profile is checked too (motion_top's push checks, in their order)."""
    lo = -(1 << (width - 1))
    if cmd.kind > EVENT:
        return [], E_KIND
    if cmd.kind not in (DWELL, EVENT) and cmd.feed == 0:
        return [], E_FEED
    if cmd.kind == LINE and lo in (cmd.x, cmd.y, cmd.z):
        return [], E_RANGE
    if cmd.kind in (ARC_CW, ARC_CCW) and cmd.plane & 3 == 3:
        return [], E_PLANE
    if pf is not None and bad_profile(cmd, pf):
        return [], E_PROFILE
    if cmd.kind == LINE:
        return line_steps(cmd.x, cmd.y, cmd.z), 0
    if cmd.kind in (ARC_CW, ARC_CCW):
        from .arc import arc_error, arc_steps     # the arc core's model (rtl/circ_arc.v)

        # arc_plane gives circ_arc the start (0, 0), the end (x, y), the centre (i, j) in (u, v)
        if arc_error(cmd.i, cmd.j, 0, 0, cmd.x, cmd.y, width):
            return [], E_CORE
        path = arc_steps(cmd.i, cmd.j, 0, 0, cmd.x, cmd.y, cmd.kind == ARC_CCW, (cmd.x, cmd.y) == (0, 0))
        uvw = helix_steps([(s.dx, s.dy) for s in path], cmd.z, cmd.k)
        return [to_machine(cmd.plane & 3, *s) for s in uvw], 0
    if cmd.kind == CURVE:
        from .curve import Program, steps as curve_steps

        res = curve_steps(Program(0, 0, cmd.x, cmd.y, cmd.i, cmd.j, cmd.k, cmd.l,
                                  cmd.z & ((1 << width) - 1)), width, width + 8)
        return [(s.dx, s.dy, 0) for s in res.steps], E_CORE if res.error else 0
    return [], 0


def queue_steps(cmds, width: int = 16, pf: int | None = None) -> tuple[list[tuple[int, int, int]], list[int]]:
    """Every step the drive must see, in order, and the error codes, for a command list
    (a core's refusal, E_CORE, is a fault: nothing after it runs)."""
    out, errors = [], []
    for cmd in cmds:
        s, err = command_steps(cmd, width, pf)
        out += s
        if err:
            errors.append(err)
            if err == E_CORE:
                break
    return out, errors


# ---------------- motion_top, cycle level ----------------

S_IDLE, S_LINE, S_ARC, S_CURVE, S_DRAIN, S_DWELL, S_EVENT, S_FAULT = range(8)
P_IDLE, P_ARC, P_TAIL = range(3)


def _signed(value: int, bits: int) -> int:
    value &= (1 << bits) - 1
    return value - (1 << bits) if value >> (bits - 1) else value


class ArcPlane(CycleModel):
    """Cycle model of rtl/arc_plane.v: circ_arc in (u, v), the arc step held a cycle, the
    helix axis w from line core A (which the caller owns and clocks), the tail counter.

    Combinational outputs (`helix_*`, `done`, `error`) read the registers and the
    inputs given to `nets`; `step`/`dir` need core A's outputs (`helix_step`, `helix_dir`).
    """

    watch = {"step": False, "dir": False, "busy": False}

    def __init__(self, w: int = 16):
        from .arc import CircArc

        self.w = w
        self.arc = CircArc(w)
        self.reset()

    def reset(self) -> None:
        self.arc.reset()
        self.phase, self.plane_q, self.helix_q, self.w_neg_q = P_IDLE, 0, 0, 0
        self.left_q, self.arc_q, self.tail_step_q = 0, 0, 0

    @property
    def busy(self) -> int:
        return int(self.phase != P_IDLE)

    def nets(self, i) -> dict[str, int]:
        """The combinational outputs for inputs `i` (start, travel)."""
        arc, in_arc = self.arc, self.phase == P_ARC
        travel = _signed(i.get("travel", 0), self.w)
        load = int(bool(i.get("start")) and self.phase == P_IDLE)
        return {"load": load, "helix_start": int(load and travel != 0),
                "helix_tick": int(in_arc and bool(arc.step_x or arc.step_y)),
                "helix_abort": int(in_arc and bool(arc.done or arc.error)),
                "done": int((in_arc and arc.done and not self.helix_q)
                            or (self.phase == P_TAIL and self.left_q == 0)),
                "error": int(in_arc and bool(arc.error))}

    def outputs(self, helix_step: int, helix_dir: int) -> tuple[int, int]:
        """(step, dir) bits {z, y, x} from the registers and core A's w step."""
        in_arc, in_tail = self.phase == P_ARC, self.phase == P_TAIL
        w_step = helix_step if in_arc else int(in_tail and self.tail_step_q)
        w_dir = helix_dir if in_arc else self.w_neg_q
        a = self.arc_q if in_arc else 0
        axes = PLANE_AXES.get(self.plane_q, PLANE_AXES[0])
        step = dirs = 0
        for axis, s, d in zip(axes, (a & 1, a >> 1 & 1, w_step), (self.arc_q >> 2 & 1, self.arc_q >> 3 & 1, w_dir)):
            step |= s << axis
            dirs |= d << axis
        return step, dirs

    def clock(self, i, nets: dict[str, int], helix_step: int) -> None:
        """The edge; `nets` from nets(i) before it, helix_step core A's output before it."""
        w = self.w
        arc = self.arc
        arc_done, arc_error = arc.done, arc.error
        arc_out = arc.step_x | arc.step_y << 1 | arc.dir_x << 2 | arc.dir_y << 3
        end_u, end_v = _signed(i["end_u"], w), _signed(i["end_v"], w)
        arc_tick = int(bool(i["tick"]) and not self.arc_q & 3)      # the held step is in flight
        arc.clock({"rst": i.get("rst"), "start": nets["load"], "tick": arc_tick, "cx": i["centre_u"],
                   "cy": i["centre_v"], "x0": 0, "y0": 0, "x1": end_u, "y1": end_v, "ccw": i["ccw"],
                   "full": int(end_u == 0 and end_v == 0)})
        if i.get("rst"):
            self.reset()
            return
        more = self.left_q != 0
        tail_step = int(self.phase == P_TAIL and bool(i["tick"]) and more)
        if self.phase == P_IDLE:
            if nets["load"]:
                travel = _signed(i["travel"], w)
                self.phase, self.plane_q = P_ARC, i["plane"] & 3
                self.helix_q, self.w_neg_q, self.left_q = int(travel != 0), int(travel < 0), abs(travel)
        elif self.phase == P_ARC:
            if helix_step:
                self.left_q -= 1
            if arc_error or (arc_done and not self.helix_q):
                self.phase = P_IDLE
            elif arc_done:
                self.phase = P_TAIL
        else:
            if not more:
                self.phase = P_IDLE
            elif i["tick"]:
                self.left_q -= 1
        self.arc_q, self.tail_step_q = arc_out, tail_step


class MotionTop(CycleModel):
    """Cycle model of rtl/motion_top.v: the block models wired as the RTL wires them.

    Every combinational net is computed from the registers before the edge,
    then every block is clocked with it, as the RTL's always blocks are.
    """

    watch = {**{f"step_{a}": False for a in AXES}, **{f"dir_{a}": False for a in AXES},
             **{f"pos_{a}": True for a in AXES}, "busy": False, "done": False, "error": False,
             "error_code": False, "cmd_full": False, "queue_level": False, "event_valid": False,
             "event_code": False, "event_value": True, "speed": False, "stopped": False, "still": False}
    SETTINGS = ("speed_quantum", "block_shift", "jerk_shift", "override")

    def __init__(self, w: int = 16, feed_w: int = 16, frac: int = 16, nw: int = 16, pf: int = 12,
                 len_w: int = 34, zw: int = 48, mw: int = 6, qdepth: int = 4, qlw: int = 3,
                 sdepth: int = 2, tw: int = 8, pos_w: int = 32):
        from .curve import CurveTangent
        from .profile import PathProfile
        from .su1571551 import Su1571551

        self.w, self.feed_w, self.pos_w, self.pf = w, feed_w, pos_w, pf
        self.widths = {"limit": feed_w, "exit": nw, "rate": pf + 1, "cost": feed_w, "length": len_w,
                       "budget": zw}
        self.queue = SyncFifo(5 + feed_w + 7 * w, qdepth, qlw)
        self.line_a, self.line_b = Su1571551(w, True), Su1571551(w, True)
        self.arc, self.curve = ArcPlane(w), CurveTangent(w, w + 8, w)
        self.sync = StepSync(3, sdepth, 2, feed_w, 4)
        self.profile = PathProfile(feed_w, frac, nw, pf, len_w, zw, mw, qdepth, qlw)
        self.out = StepDir(3, tw)
        self.reset()

    def reset(self, jerk_shift: int = 0) -> None:
        self._flush(jerk_shift)
        self.out.reset()
        self.state = S_IDLE
        self.lead_q = self.lead_neg_q = self.cost_q = self.dwell_q = 0
        self.pos = [0, 0, 0]
        self.step_q = self.busy_q = self.done = self.error = self.error_code = self.sync_overflow_q = 0
        self.event_valid = self.event_code = self.event_value = self.inline_q = 0
        self._speed = self._stopped = self._busy = 0
        self._still = 1

    def _flush(self, jerk_shift: int = 0) -> None:
        """What `flush` (rst or a fault) resets: the queues, the step buffer, the speed block, the cores."""
        for block in (self.queue, self.line_a, self.line_b, self.arc, self.curve, self.sync):
            block.reset()
        self.profile.reset(jerk_shift)

    # ---- outputs ----
    def _bit(self, vector: int, axis: int) -> int:
        return vector >> axis & 1

    step_x = property(lambda self: self._bit(self.out.step, 0))
    step_y = property(lambda self: self._bit(self.out.step, 1))
    step_z = property(lambda self: self._bit(self.out.step, 2))
    dir_x = property(lambda self: self._bit(self.out.dir, 0))
    dir_y = property(lambda self: self._bit(self.out.dir, 1))
    dir_z = property(lambda self: self._bit(self.out.dir, 2))
    pos_x = property(lambda self: self.pos[0])
    pos_y = property(lambda self: self.pos[1])
    pos_z = property(lambda self: self.pos[2])
    cmd_full = property(lambda self: int(bool(self.queue.full or self.profile.full)))
    queue_level = property(lambda self: self.queue.level)

    def settled(self, i: Mapping[str, int]) -> None:
        """The combinational outputs (speed, stopped, still, busy) on the registers after an edge,
        with the inputs still applied (the bench samples between edges)."""
        nets = self._profile_nets(i)
        self._busy = self.busy_with(nets["moving"])
        self._speed = nets["speed"]
        self._stopped = int(bool(nets["stopped"]) or (bool(i.get("hold", 0)) and not self._busy))
        self._still = int(bool(nets["still"]) and bool(self.out.ready))

    def _profile_nets(self, i, barrier_done: int = 0) -> dict:
        sync, out = self.sync, self.out
        return self.profile.nets({
            "barrier_done": barrier_done, **{k: i.get(k, 0) for k in self.SETTINGS}, "hold": i.get("hold", 0),
            "step_valid": sync.out_valid, "step_axes": bin(sync.out_step).count("1"),
            "step_cost": sync.out_data, "drive_ready": out.ready})

    @property
    def speed(self) -> int:
        return self._speed

    @property
    def stopped(self) -> int:
        return self._stopped

    @property
    def still(self) -> int:
        return self._still

    def busy_with(self, moving: int) -> int:
        return int((self.state not in (S_IDLE, S_FAULT)) or bool(self.queue.valid) or self.profile.level != 0
                   or bool(self.sync.out_valid) or not self.out.ready or bool(moving))

    @property
    def busy(self) -> int:
        return self._busy

    def pack(self, inputs) -> int:
        value = (inputs.get("cmd_kind", 0) & 7) << 2 | inputs.get("cmd_plane", 0) & 3
        value = value << self.feed_w | inputs.get("cmd_cost", 0) & ((1 << self.feed_w) - 1)
        for f in FIELDS:
            value = value << self.w | inputs.get(f"cmd_{f}", 0) & ((1 << self.w) - 1)
        return value

    def unpack(self, value: int) -> dict[str, int]:
        fields = {}
        for f in reversed(FIELDS):
            fields[f] = _signed(value, self.w)
            value >>= self.w
        fields["cost"] = value & ((1 << self.feed_w) - 1)
        fields["plane"] = value >> self.feed_w & 3
        fields["kind"] = value >> self.feed_w + 2 & 7
        return fields

    def push_error(self, i) -> int:
        """The push check's error code for the command inputs `i` (0: none)."""
        kind = i.get("cmd_kind", 0) & 7
        feed = i.get("cmd_feed", 0) & ((1 << self.feed_w) - 1)
        lo = 1 << (self.w - 1)
        fields = {f: i.get(f"cmd_{f}", 0) & ((1 << self.w) - 1) for f in "xyz"}
        prof = {f: i.get(f"cmd_{f}", 0) & ((1 << bits) - 1) for f, bits in self.widths.items()}
        move = kind <= CURVE
        if kind > EVENT:
            return E_KIND
        if move and feed == 0:
            return E_FEED
        if kind == LINE and lo in fields.values():
            return E_RANGE
        if kind in (ARC_CW, ARC_CCW) and i.get("cmd_plane", 0) & 3 == 3:
            return E_PLANE
        if move and (prof["rate"] == 0 or prof["rate"] > 1 << self.pf or prof["length"] == 0
                     or prof["limit"] < feed or i.get("block_shift", 0) < BLOCK_SHIFT_MIN):
            return E_PROFILE
        return 0

    def clock(self, i) -> None:
        if i.get("rst"):
            self.reset(i.get("jerk_shift", 0))
            self.settled(i)
            return
        w = self.w
        fault = self.state == S_FAULT
        h = self.unpack(self.queue.dout)
        kind = h["kind"]
        idle = self.state == S_IDLE
        is_arc = kind in (ARC_CW, ARC_CCW)
        valid = bool(i.get("cmd_valid", 0))
        bad = self.push_error(i)
        full = self.cmd_full
        push = int(valid and not fault and not bad and not full)
        dispatch = idle and bool(self.queue.valid) and not self.inline_q     # a clock after an inline event
        start_line = int(dispatch and kind == LINE)
        start_arc = int(dispatch and is_arc)
        start_curve = int(dispatch and kind == CURVE)
        mags = [abs(h[a]) & ((1 << w) - 1) for a in AXES]     # -2^(W-1) wraps, as in the RTL
        lead = 0 if mags[0] >= mags[1] and mags[0] >= mags[2] else 1 if mags[1] >= mags[2] else 2
        minor1 = h["y"] if lead == 0 else h["x"]
        minor2 = h["y"] if lead == 2 else h["z"]
        core_tick = 1 - self.sync.stop

        a, b = self.line_a, self.line_b
        if self.lead_q == 0:
            line_step = a.step_x | a.step_y << 1 | b.step_y << 2
            line_dir = self.lead_neg_q | a.dir_y << 1 | b.dir_y << 2
        elif self.lead_q == 1:
            line_step = a.step_y | a.step_x << 1 | b.step_y << 2
            line_dir = a.dir_y | self.lead_neg_q << 1 | b.dir_y << 2
        else:
            line_step = a.step_y | b.step_y << 1 | a.step_x << 2
            line_dir = a.dir_y | b.dir_y << 1 | self.lead_neg_q << 2
        arc_in = {"start": start_arc, "tick": core_tick, "plane": h["plane"], "ccw": int(kind == ARC_CCW),
                  "end_u": h["x"], "end_v": h["y"], "centre_u": h["i"], "centre_v": h["j"],
                  "travel": h["z"]}
        arc_nets = self.arc.nets(arc_in)
        helix_step = a.step_y
        arc_step, arc_dir = self.arc.outputs(a.step_y, a.dir_y)
        core_step, core_dir = {
            S_ARC: (arc_step, arc_dir),
            S_CURVE: (self.curve.step_x | self.curve.step_y << 1, self.curve.dir_x | self.curve.dir_y << 1),
            S_LINE: (line_step, line_dir)}.get(self.state, (0, 0))

        sync, out = self.sync, self.out
        out_valid, out_step, out_dir = sync.out_valid, sync.out_step, sync.out_dir
        pre = self._profile_nets(i)                    # moving does not depend on barrier_done
        drained = not out_valid and out.ready and not pre["moving"]
        event_go = drained and not i.get("hold", 0)    # an event or dwell waits while held (two pauses stay two)
        barrier_done = int((self.state == S_DWELL and self.dwell_q == 0 and not i.get("hold", 0))
                           or (self.state == S_EVENT and event_go))
        pnets = self._profile_nets(i, barrier_done)
        fire = pnets["fire"]
        core_done = ((self.state == S_LINE and a.done) or
                     (self.state == S_ARC and (arc_nets["done"] or arc_nets["error"])) or
                     (self.state == S_CURVE and (self.curve.done or self.curve.error)))
        core_error = (self.state == S_ARC and arc_nets["error"]) or (self.state == S_CURVE and self.curve.error)
        sync_overflow = sync.overflow
        late = self.profile.ramp.late          # the ramp's register, before the edge
        overrun = self.profile.pacer.overrun and not fault     # the pacer's register: distance lost
        busy = self.busy_with(pnets["moving"])
        drv_step, drv_dir = out.step, out.dir
        inline = kind == EVENT and h["plane"] & 1           # an inline event: at once, no stop
        event_strobe = int((self.state == S_EVENT and event_go) or (dispatch and inline))

        # ---- the edge ----
        if fault:                                      # flush: held in reset
            self._flush(i.get("jerk_shift", 0))
        else:
            self.queue.clock({"push": push, "pop": int(dispatch), "din": self.pack(i)})
            lead_len = mags[lead]
            self.line_a.clock({"rst": arc_nets["helix_abort"], "start": start_line | arc_nets["helix_start"],
                               "tick": arc_nets["helix_tick"] if self.state == S_ARC else core_tick,
                               "x": max(_signed(h["k"], w), 0) if is_arc else lead_len,
                               "y": h["z"] if is_arc else minor1})
            self.line_b.clock({"start": start_line, "tick": core_tick, "x": lead_len, "y": minor2})
            self.arc.clock(arc_in, arc_nets, helix_step)
            self.curve.clock({"start": start_curve, "tick": core_tick, "x0": 0, "y0": 0, "p0": h["x"],
                              "q0": h["y"], "dp_dx": h["i"], "dp_dy": h["j"], "dq_dx": h["k"], "dq_dy": h["l"],
                              "reverse": 0, "count": h["z"] & ((1 << w) - 1), "end_sel": 0, "end_coord": 0,
                              "improved": 0, "e_load": 0, "e_init": 0})
            sync.clock({"in_step": core_step, "in_dir": core_dir, "in_data": self.cost_q, "tick": fire})
            rest = not busy and not valid            # the speed block held in reset at rest
            self.profile.clock({"rst": int(rest), "jerk_shift": i.get("jerk_shift", 0),
                                "push": int(push and not ((i.get("cmd_kind", 0) & 7) == EVENT
                                                          and i.get("cmd_plane", 0) & 1)),
                                "push_barrier": int((i.get("cmd_kind", 0) & 7) > CURVE),
                                **{f"push_{f}": i.get(f"cmd_{f}", 0) for f in
                                   ("feed", "limit", "exit", "rate", "length", "budget")}}, pnets)
        out.clock({"pulse_width": i["pulse_width"], "setup": i["setup"], "hold": i["hold_time"],
                   "valid": fire, "step_in": out_step, "dir_in": out_dir})

        if self.state == S_IDLE:
            if dispatch:
                self.cost_q = h["cost"]
                if kind == LINE:
                    self.state, self.lead_q = S_LINE, lead
                    self.lead_neg_q = int(h[AXES[lead]] < 0)
                elif kind == CURVE:
                    self.state = S_CURVE
                elif kind == DWELL:
                    self.state, self.dwell_q = S_DRAIN, h["x"] & ((1 << w) - 1)
                elif kind == EVENT:
                    self.state = S_IDLE if inline else S_EVENT
                    self.event_code, self.event_value = h["x"] & 0xFF, h["y"]
                else:
                    self.state = S_ARC
        elif self.state in (S_LINE, S_ARC, S_CURVE):
            if core_error:
                self.state = S_FAULT
            elif core_done:
                self.state = S_IDLE
        elif self.state == S_DRAIN:
            if event_go:
                self.state = S_DWELL
        elif self.state == S_EVENT:
            if event_go:
                self.state = S_IDLE
        elif self.state == S_DWELL:
            if i.get("hold", 0):
                pass                                   # a dwell waits while held
            elif self.dwell_q == 0:
                self.state = S_IDLE
            else:
                self.dwell_q -= 1
        if overrun:
            self.state = S_FAULT                       # until rst
        for k in range(3):
            if drv_step >> k & 1 and not self.step_q >> k & 1:
                self.pos[k] = _signed(self.pos[k] + (-1 if drv_dir >> k & 1 else 1), self.pos_w)
        self.step_q = drv_step
        self.event_valid = event_strobe
        self.inline_q = int(dispatch and inline)
        self.busy_q, self.done = busy, int(self.busy_q and not busy)
        code = (E_CORE if core_error or (valid and fault) else bad if valid and bad
                else E_QUEUE if valid and full else E_SYNC if sync_overflow and not self.sync_overflow_q
                else E_OVERRUN if overrun else E_LATE if late else 0)
        self.sync_overflow_q = sync_overflow
        self.error = int(code != 0)
        if code:
            self.error_code = code
        self.settled(i)
