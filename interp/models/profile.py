# SPDX-License-Identifier: Apache-2.0
"""The path-speed profile of motion_top (rtl/path_profile.v) and bench profiles.

`PathProfile` is the cycle model of rtl/path_profile.v: the profile queue (a
SyncFifo of barrier / feed / limit / exit / rate / length / budget), the
virtual domain (interp.models.speed_ramp.SpeedRamp), the S-curve filter and the
step pacer (interp.models.pacing.JerkFilter, StepPacer), wired as the RTL wires
them.  `nets(inputs)` gives its combinational outputs before an edge, `clock`
is the edge.

`profile_for` gives hand-made bench commands a valid profile: the exact number N
of step events of each command (by the step-level models of its core), its cost
(0: the lecture's costs, whose exact sum is the length; or the true path length / N),
a rate from the acceleration, and a simple plan of exit speeds: the lower cruise of
two moves that go on in the same direction, 0 at corners, before a dwell or event
and at the end, lowered backwards so that every segment can brake to its successor's
exit within its own length.  The real planner is interp.gcode's.
"""
from __future__ import annotations

import math
from dataclasses import replace
from typing import Mapping

from .base import CycleModel
from .speed_ramp import BLOCK_SHIFT_MIN
from .motion import (ARC_CCW, ARC_CW, CURVE, LINE, Command, SyncFifo, command_steps, next_not_inline,
                     interval_costs)


def profile_width(feed_w: int, nw: int, pf: int, len_w: int, zw: int) -> int:
    return 1 + 2 * feed_w + nw + pf + 1 + len_w + zw


class PathProfile(CycleModel):
    """Cycle model of rtl/path_profile.v."""

    watch = {"speed": False, "moving": False, "stopped": False, "still": False}

    def __init__(self, feed_w: int = 16, frac: int = 16, nw: int = 16, pf: int = 12, len_w: int = 34,
                 zw: int = 48, mw: int = 6, qdepth: int = 4, qlw: int = 3):
        from .pacing import JerkFilter, StepPacer
        from .speed_ramp import SpeedRamp

        self.feed_w, self.nw, self.pf, self.len_w, self.zw = feed_w, nw, pf, len_w, zw
        self.queue = SyncFifo(profile_width(feed_w, nw, pf, len_w, zw), qdepth, qlw)
        self.ramp = SpeedRamp(feed_w=feed_w, nw=nw, pf=pf, len_w=len_w, zw=zw)
        self.jerk = JerkFilter(feed_w=feed_w, mw=mw)
        self.pacer = StepPacer(feed_w=feed_w, frac=frac, mw=mw)
        self.reset()

    def reset(self, jerk_shift: int = 0) -> None:
        """rst: every block; the filter takes jerk_shift as its shift."""
        for block in (self.queue, self.ramp, self.pacer):
            block.reset()
        self.jerk.reset(jerk_shift)
        self.speed_f = self.block_q = 0

    # ---- the profile queue's entries ----
    _FIELDS = ("barrier", "feed", "limit", "exit", "rate", "length", "budget")

    def _widths(self) -> tuple[int, ...]:
        return (1, self.feed_w, self.feed_w, self.nw, self.pf + 1, self.len_w, self.zw)

    def pack(self, values: Mapping[str, int]) -> int:
        out = 0
        for name, bits in zip(self._FIELDS, self._widths()):
            out = out << bits | values[name] & ((1 << bits) - 1)
        return out

    def unpack(self, value: int) -> dict[str, int]:
        out = {}
        for name, bits in reversed(list(zip(self._FIELDS, self._widths()))):
            out[name] = value & ((1 << bits) - 1)
            value >>= bits
        return out

    @property
    def full(self) -> int:
        return self.queue.full

    @property
    def level(self) -> int:
        return self.queue.level

    def _ramp_inputs(self, i: Mapping[str, int]) -> dict[str, int]:
        h = self.unpack(self.queue.dout)
        return {"next_valid": self.queue.valid, "next_barrier": h["barrier"], "next_feed": h["feed"],
                "next_limit": h["limit"], "next_exit": h["exit"], "next_rate": h["rate"],
                "next_length": h["length"], "next_budget": h["budget"], "barrier_done": i["barrier_done"],
                "speed_quantum": i["speed_quantum"], "block_shift": i["block_shift"],
                "override": i["override"], "hold": i["hold"]}

    def nets(self, i: Mapping[str, int]) -> dict:
        """The combinational outputs for inputs `i` (barrier_done, the settings, hold,
        step_valid, step_axes, step_cost, drive_ready) on the registers before the edge.
        The ramp's outputs are registers; the filter gets its own copy of the speed, which
        follows the ramp's one quantum per block tick (the ramp's block a clock late), and a
        stop's last drop inside a block in the next clock."""
        ramp = self.ramp
        ramp_in = self._ramp_inputs(i)
        rise = int(bool(self.block_q) and ramp.speed > self.speed_f)
        fall = int(ramp.speed < self.speed_f)        # a stop's last drop: at once, inside a block
        jerk_in = {"speed": self.speed_f, "up": rise, "down": fall, "block": self.block_q,
                   "speed_quantum": i["speed_quantum"], "jerk_shift": i["jerk_shift"]}
        self.jerk.set_inputs(jerk_in)
        pacer_in = {"sum": self.jerk.sum, "jerk_shift": self.jerk.shift, "step_valid": i["step_valid"],
                    "step_axes": i["step_axes"], "step_cost": i["step_cost"], "drive_ready": i["drive_ready"]}
        self.pacer.set_inputs(pacer_in)
        return {"ramp_in": ramp_in, "jerk_in": jerk_in, "pacer_in": pacer_in, "next_pop": ramp.next_pop,
                "fire": self.pacer.fire, "speed": ramp.speed,
                # the S-curve filter lags the ramp: at rest only once it is empty too
                "stopped": int(bool(ramp.stopped) and self.jerk.empty),
                "still": int(ramp.speed == 0 and self.jerk.empty),
                "moving": int(bool(ramp.moving) or not self.jerk.empty)}

    def clock(self, i: Mapping[str, int], nets: Mapping) -> None:
        """The edge: `nets` from nets(i) before it; i also has push and the push_* fields."""
        if i.get("rst"):
            self.reset(i.get("jerk_shift", 0))
            return
        block = self.ramp.block
        a = nets["jerk_in"]["speed_quantum"]
        step = nets["jerk_in"]["up"] - nets["jerk_in"]["down"]
        self.queue.clock({"push": i["push"], "pop": nets["next_pop"], "din": self.pack(
            {"barrier": i["push_barrier"], "feed": i["push_feed"], "limit": i["push_limit"],
             "exit": i["push_exit"], "rate": i["push_rate"], "length": i["push_length"],
             "budget": i["push_budget"]})})
        self.ramp.clock(nets["ramp_in"])
        self.jerk.clock(nets["jerk_in"])
        self.pacer.clock(nets["pacer_in"])
        self.speed_f = (self.speed_f + step * a) & ((1 << self.feed_w) - 1)
        self.block_q = block


# ---------------- bench profiles ----------------

MOVES = (LINE, ARC_CW, ARC_CCW, CURVE)


def true_length(cmd: Command, steps) -> float:
    """The programmed path's length in steps: a line's straight length, an arc's (helix's)
    r * angle (with its travel), a curve's by its steps (1, sqrt 2 per step)."""
    if cmd.kind == LINE:
        return math.sqrt(cmd.x ** 2 + cmd.y ** 2 + cmd.z ** 2)
    if cmd.kind in (ARC_CW, ARC_CCW):
        r = math.hypot(cmd.i, cmd.j)
        a0 = math.atan2(-cmd.j, -cmd.i)
        a1 = math.atan2(cmd.y - cmd.j, cmd.x - cmd.i)
        turn = (a1 - a0) if cmd.kind == ARC_CCW else (a0 - a1)
        turn %= 2 * math.pi
        if turn == 0:
            turn = 2 * math.pi
        return math.hypot(r * turn, cmd.z)
    return sum(math.sqrt(sum(abs(c) for c in s)) for s in steps)


def direction(cmd: Command, at_end: bool) -> tuple[float, float, float] | None:
    """Unit tangent of a line (None for other moves: treated as corners)."""
    if cmd.kind != LINE:
        return None
    n = math.sqrt(cmd.x ** 2 + cmd.y ** 2 + cmd.z ** 2)
    return (cmd.x / n, cmd.y / n, cmd.z / n) if n else None


def profile_for(commands, *, quantum: int, accel: float, frac: int, pf: int = 12, block_shift: int = BLOCK_SHIFT_MIN,
                width: int = 16, lecture: bool = True, limit_factor: float = 1.0,
                feed_max: int | None = None, straight: float = 0.999,
                feed_w: int | None = None) -> list[Command]:
    """The commands with valid profiles (see the module text).

    quantum: A, path units per clock; accel: path acceleration, path units per clock^2;
    frac: path units per axial step = 2^frac; pf: rate fraction bits; lecture: cost 0
    (the lecture's 1, sqrt 2, sqrt 3 costs) or the true length / N; limit_factor: the
    ceiling cmd_limit = feed * factor (<= feed_max); straight: the cosine above which two
    lines go on without a corner; feed_w: the width of cmd_cost (a true-length cost that does
    not fit, e.g. a diagonal's at FEED_W = FRAC, falls back to the lecture's costs).
    Commands with no steps (or refused by their core) keep length 0: motion_top refuses
    them (bad profile)."""
    one = 1 << frac
    costs = interval_costs(frac)
    rate = max(1, min(1 << pf, int(accel * (1 << block_shift) / quantum * (1 << pf))))
    a_real = rate / (1 << pf) * quantum / (1 << block_shift)         # the acceleration the RTL runs
    out: list[Command] = []
    for cmd in commands:
        c = replace(cmd)
        if c.kind in MOVES and c.feed > 0:
            steps, err = command_steps(c, width)
            n = len(steps)
            if n and not err:
                cost = 0 if lecture else max(1, round(true_length(c, steps) * one / n))
                if feed_w is not None and cost >> feed_w:
                    cost = 0
                c.cost = cost
                c.length = n * cost if cost else sum(costs[sum(1 for v in s if v)] for s in steps)
            top = feed_max if feed_max is not None else c.feed * 2
            c.limit = max(c.feed, min(top, int(c.feed * limit_factor)))
            c.rate = rate
            c.budget = 2 * rate * c.length // ((1 << block_shift) * quantum)
        out.append(c)
    # exit speeds: junction speed, then backwards so each segment can brake to the next's exit
    moves = [k for k, c in enumerate(out) if c.kind in MOVES and c.length > 0]
    following_of = next_not_inline(out)                 # (inline events: no stop)
    v_next_entry = 0.0                  # the largest speed the rest can start from
    for pos in range(len(moves) - 1, -1, -1):
        k = moves[pos]
        c = out[k]
        following = following_of[k]
        junction = 0.0
        if following is not None and following.kind in MOVES and following.length > 0:
            d0, d1 = direction(c, True), direction(following, False)
            if d0 and d1 and sum(a * b for a, b in zip(d0, d1)) >= straight:
                junction = min(c.feed, following.feed)
        v_exit = min(junction, v_next_entry)
        n_exit = max(0, int(v_exit // quantum) - 1) if v_exit > 0 else 0
        c.exit = n_exit
        # the entry this segment allows: brake from it to its exit within its length
        v_entry = math.sqrt((n_exit * quantum) ** 2 + 2 * a_real * c.length) - 2 * quantum
        v_next_entry = max(0.0, min(v_entry, c.feed))
    return out
