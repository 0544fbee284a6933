# SPDX-License-Identifier: Apache-2.0
"""Path-speed profile generator (rtl/speed_ramp.v): the virtual domain of the
speed-setting block, a trapezoid generator with look-ahead of one segment.

Units: path unit = 2^-FRAC of an axial step; speed v = path units per clock.
The speed is n quanta, v = n * A (A = `speed_quantum`).  Time runs in blocks of
2^block_shift clocks; n changes by at most one per block, only when the block's
DDA (acc += rate, rate = p * 2^PF) overflows: acceleration p * A / 2^block_shift
path units per clock^2.

The golden equations (`braking_need`, `segment_budget`) and the cycle model
`SpeedRamp` (mirrors the registers of the RTL, every cycle) live here.

Braking criterion.  Z is the budget of the segment in quanta^2 (2^-PF units):
Z = 2 p S / (2^block_shift A) for the remaining distance S; a block at speed n
uses 2 p n of it.  If from the start of a block with DDA phase u = acc / 2^PF the
speed is lowered at every following DDA tick, from n to the floor f, the k-th
tick comes after t_k <= (k - u) / p + 1 blocks, and summing by parts the budget
used is at most

    R(n, u) = n^2 + n - f^2 - f + 2 n (p - u)        (n > f; R = 0 for n <= f)

(`braking_need`).  Keeping `Z >= R(n', u')` at every DDA tick for the speed n'
chosen there (raise only if it holds for n + 1, keep n only if it holds for n,
else lower) is an invariant: lowering continues the chain that R bounds.
n (n + 1) is kept as Q, p n as P, n * acc as NA, all with adders; the model keeps
Z scaled by 2^block_shift (Zx, minus 2 P every clock) so that the segment may
end in any clock of a block.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

from .base import CycleModel

PCT = 100            # override unit: percent
BLOCK_SHIFT_MIN = 2  # blocks of 4 clocks at least: the decision pipeline's three clocks
OVERRIDE_MIN, OVERRIDE_MAX = 1, 200


def clamp_override(value: int) -> int:
    """The override in percent as the RTL uses it: 0 -> 1, above 200 -> 200."""
    return min(max(value, OVERRIDE_MIN), OVERRIDE_MAX)


def segment_budget(rate: int, length: int, quantum: int, block_shift: int) -> int:
    """Z0 = floor(2 * rate * length / (2^block_shift * A)), quanta^2 in 2^-PF units."""
    return (2 * rate * length) // (quantum << block_shift)


def braking_need(n: int, floor: int, rate: int, acc: int, pf: int) -> int:
    """R(n, u) * 2^PF: the budget (2^-PF quanta^2) that braking from n to `floor`
    at every DDA tick (phase acc at the start of the next block) may need."""
    if n <= floor:
        return 0
    return ((n * n + n - floor * floor - floor) << pf) + 2 * n * rate - 2 * n * acc


def target_floor(exit_quanta: int) -> int:
    """The lowest speed braking aims at: the exit speed, at least one quantum
    (with exit 0 the last quantum drops at the clock the segment ends)."""
    return max(exit_quanta, 1)


@dataclass
class Segment:
    """One entry of the profile queue (the command's fields)."""

    feed: int = 0
    limit: int = 0
    exit: int = 0
    rate: int = 0
    length: int = 0
    budget: int = 0
    barrier: bool = False

    def ports(self, valid: bool = True) -> dict[str, int]:
        return {"next_valid": int(valid), "next_barrier": int(self.barrier),
                "next_feed": self.feed, "next_limit": self.limit, "next_exit": self.exit,
                "next_rate": self.rate, "next_length": self.length, "next_budget": self.budget}


class ShiftMult:
    """rtl/speed_ramp_mul.v: unsigned a * b, MSB of b first, BW busy cycles."""

    def __init__(self, bw: int):
        self.bw = bw
        self.reset()

    def reset(self) -> None:
        self.busy = self.done = self.count = self.a = self.b = self.product = 0

    def clock(self, start: int, a: int, b: int) -> None:
        if not self.busy:
            self.done = 0
            if start:
                self.a, self.b, self.product, self.count, self.busy = a, b, 0, self.bw, 1
            return
        self.product = 2 * self.product + (self.a if (self.b >> (self.bw - 1)) & 1 else 0)
        self.b = (self.b << 1) & ((1 << self.bw) - 1)
        self.count -= 1
        if self.count == 0:
            self.busy, self.done = 0, 1


class Decide:
    """rtl/speed_ramp_decide.v: the braking criterion and the cap over the three clocks
    before a DDA tick.  R(n) and R(n + 1) (`braking_need` at the phase the tick leaves,
    times 2^PF) against floor((Zx - 8 P) / 2^bs), Zx projected to the tick."""

    def __init__(self, pf: int, nmax: int):
        self.pf, self.nmax = pf, nmax
        self.reset()

    def reset(self) -> None:
        self.fresh = 0
        self.s1 = dict(dh=0, du=0, naa=0, zx=0, succ=0, le=0, lt=0)
        self.s2 = dict(hold=0, up=0, zx=0, succ=0, le=0, lt=0, v100=0, va100=0, above=0, fit=0)
        self.s3 = dict(hold=0, up=0, succ=0, le=0, lt=0)
        self.over = self.room = 0

    def valid(self, succ: int) -> bool:
        """The bits are this clock's tick's: no event in the three clocks before, and the
        successor stage 1 saw is still there."""
        return self.fresh == 3 and not (self.s3["succ"] and not succ)

    @property
    def ok_hold(self) -> int:
        return int(bool(self.s3["le"] or self.s3["hold"]))

    @property
    def ok_up(self) -> int:
        return int(bool(self.s3["lt"] or self.s3["up"]))

    def clock(self, *, event: bool, succ: int, n: int, q: int, f_sq: int, floor: int, na: int,
              acc: int, p: int, budget_x: int, bs: int, v: int, va: int, limit: int, fo: int,
              fo_valid: int) -> None:
        s1, s2 = self.s1, self.s2
        self.over = int(bool(s2["above"] or (fo_valid and s2["v100"] > fo)))
        self.room = int(bool(fo_valid and s2["fit"] and s2["va100"] <= fo))
        self.s3 = dict(hold=int(s2["zx"] >= s2["hold"]), up=int(s2["zx"] >= s2["up"]),
                       succ=s2["succ"], le=s2["le"], lt=s2["lt"])
        self.s2 = dict(hold=(s1["dh"] << self.pf) - 2 * na, up=(s1["du"] << self.pf) - 2 * s1["naa"],
                       zx=s1["zx"] >> bs, succ=s1["succ"], le=s1["le"], lt=s1["lt"],
                       v100=PCT * v, va100=PCT * va, above=int(v > limit),
                       fit=int(va <= limit and n != self.nmax))
        self.s1 = dict(dh=q - f_sq + 2 * n, du=q - f_sq + 4 * (n + 1), naa=na + acc,
                       zx=budget_x - 8 * p, succ=int(bool(succ)), le=int(n <= floor),
                       lt=int(n < floor))
        self.fresh = 0 if event else min(self.fresh + 1, 3)


IDLE, BUSY, DONE = range(3)


class SpeedRamp(CycleModel):
    """rtl/speed_ramp.v, register for register.

    Inputs per clock (dict): rst, next_valid, next_barrier, next_feed, next_limit,
    next_exit, next_rate, next_length, next_budget, barrier_done, speed_quantum,
    block_shift, override, hold.  Outputs: speed, up, down, block, moving,
    segment, stopped, next_pop, late (and the state the bench compares).
    """

    watch = {"speed": False, "up": False, "down": False, "block": False, "moving": False,
             "segment": False,
             "stopped": False, "next_pop": False, "late": False, "n": False,
             "remaining": True, "budget_x": True, "known": False}

    def __init__(self, feed_w: int = 16, nw: int = 16, pf: int = 12, len_w: int = 34,
                 zw: int = 48):
        self.feed_w, self.nw, self.pf, self.len_w, self.zw = feed_w, nw, pf, len_w, zw
        self.one = 1 << pf
        self.nmax = (1 << nw) - 1
        self.mul_p = ShiftMult(nw)
        self.mul_f = ShiftMult(nw)
        self.mul_fo = ShiftMult(8)
        self.mul_fn = ShiftMult(8)
        self.decide = Decide(pf, self.nmax)
        self.reset()

    def reset(self) -> None:
        self.bc = self.bs_q = self.acc = 0
        self.n = self.v = self.q = self.p = self.na = 0
        self.remaining = self.budget_x = 0
        self.seg = self.rate = self.feed = self.limit = self.exit = self.f_sq = 0
        self.pre = IDLE
        self.n_sh = self.p_sh = self.f_pre = 0
        self.ref_count = self.ref_r = self.ref_d = self.ref_m = 0
        self.fo = self.fo_valid = self.fo_ok = 0
        self.fo_next = self.fn_valid = self.fn_ok = 0
        self.bar_count = 0
        self.up = self.down = self.next_pop = self.late = self.hold_q = 0
        self.decide.reset()
        self.mul_p.reset()
        self.mul_f.reset()
        self.mul_fo.reset()
        self.mul_fn.reset()

    # registered outputs
    @property
    def block(self) -> int:
        return int(self.bc >= (1 << self.bs_q) - 1)

    @property
    def speed(self) -> int:
        return self.v

    @property
    def segment(self) -> int:
        return self.seg

    @property
    def moving(self) -> int:
        return int(self.n != 0 or self.seg != 0)

    @property
    def stopped(self) -> int:
        return int(self.hold_q and self.n == 0)

    @property
    def known(self) -> int:
        return int(self.pre == DONE and self.n_sh == self.n)

    def consistent(self, next_rate: int) -> list[str]:
        """The incremental registers against their products (empty if all agree)."""
        bad = []
        if self.q != self.n * (self.n + 1):
            bad.append("q")
        if self.p != self.rate * self.n:
            bad.append("p")
        if self.na != self.n * self.acc:
            bad.append("na")
        if self.pre == DONE and self.p_sh != next_rate * self.n_sh:
            bad.append("p_sh")
        return bad

    def clock(self, inputs: Mapping[str, int]) -> None:
        if inputs.get("rst"):
            self.reset()
            return
        g = inputs.get
        pf, one = self.pf, self.one
        a_q = g("speed_quantum", 0)
        bs = self.bs_q
        hold = g("hold", 0)
        ovr = clamp_override(g("override", 100))
        # the head is ignored in the clock after a pop (the queue drops it at this edge)
        head = g("next_valid", 0) and not self.next_pop
        move_head = head and not g("next_barrier", 0)
        bar_head = head and g("next_barrier", 0)
        n_rate, n_exit = g("next_rate", 0), g("next_exit", 0)
        fo, fo_valid = self.fo, self.fo_valid

        known = move_head and self.known
        exit_t = self.exit if known else 0             # the current segment's exit speed
        floor = target_floor(self.exit) if known else 1
        f_sq = self.f_sq if known else 2

        # block and DDA
        bend = self.bc >= (1 << bs) - 1
        acc_sum = self.acc + self.rate
        dtick = bend and acc_sum >= one
        acc_n = (acc_sum - one if dtick else acc_sum) if bend else self.acc
        na1 = (self.na + self.p - ((self.n << pf) if dtick else 0)) if bend else self.na
        # budget after this clock (plus the refinement's quotient bit)
        ref_hit = self.ref_count and self.ref_r >= self.ref_d
        zx1 = self.budget_x - 2 * self.p + (self.ref_m if ref_hit else 0)

        # decision: on the pipeline's comparisons, formed over the three clocks before
        n, v = self.n, self.v
        q_up, p_up, na_up = self.q + 2 * (n + 1), self.p + self.rate, na1 + acc_n
        decide = self.decide
        step = 0
        if dtick:
            if hold:
                step = -1 if n > 0 else 0
            elif not self.seg:
                step = 0
            elif n == 0:
                step = 1
            elif not decide.valid(known):
                step = 0
            elif decide.over and n > 1:
                step = -1
            elif decide.room and decide.ok_up:
                step = 1
            elif decide.ok_hold:
                step = 0
            elif n > 1:
                step = -1
        if step > 0:
            n_d, v_d, q_d, p_d, na_d = n + 1, v + a_q, q_up, p_up, na_up
        elif step < 0:
            n_d, v_d, q_d, p_d, na_d = n - 1, v - a_q, self.q - 2 * n, self.p - self.rate, na1 - acc_n
        else:
            n_d, v_d, q_d, p_d, na_d = n, v, self.q, self.p, na1

        # crossing, switch, load, barrier
        rem1 = self.remaining - v
        cross = self.seg and rem1 <= 0
        pop = late = 0
        switch = load = 0
        seg_n, rate_n, feed_n, limit_n = self.seg, self.rate, self.feed, self.limit
        exit_n, f_sq_n = self.exit, self.f_sq
        rem_n, zx_n = rem1 if self.seg else self.remaining, zx1
        ref_start = 0
        load_r = 0
        if cross:
            if exit_t == 0:                           # the final drop: the segment ends at rest
                late = int(n > 1)
                n_d = v_d = q_d = p_d = na_d = 0
            elif known and n_d > floor:
                late = 1                              # the look-ahead came too late
            if known:
                switch = pop = 1
                if n_d:                               # the new segment's p * n', n' = n +- 1
                    p_d = self.p_sh + (n_d - n) * n_rate
                rate_n, feed_n, limit_n = n_rate, g("next_feed", 0), g("next_limit", 0)
                exit_n, f_sq_n = n_exit, self.f_pre
                rem_n = rem1 + g("next_length", 0)
                zx_n = (g("next_budget", 0) << bs) - 2 * self.p_sh
                ref_start = 1
            else:
                seg_n = 0
                zx_n = 0
        elif not self.seg and known:
            load = pop = 1
            seg_n = 1
            rate_n, feed_n, limit_n = n_rate, g("next_feed", 0), g("next_limit", 0)
            exit_n, f_sq_n = n_exit, self.f_pre
            rem_n = self.remaining + g("next_length", 0)
            # the carry c = S <= 0 is charged as K quanta-clocks (K = 1 if c > -A, else
            # 2^NW - 1) and 2 p' floor((K A + c) / A) given back by the refinement
            small = self.remaining + a_q > 0
            k_charge = 2 * n_rate if small else (n_rate << (self.nw + 1)) - 2 * n_rate
            load_r = self.remaining + (a_q if small else (a_q << self.nw) - a_q)
            zx_n = (g("next_budget", 0) << bs) - k_charge
            p_d = 0
        bar_pop = int(bool(bar_head and not self.seg and n == 0
                           and (self.bar_count or g("barrier_done", 0))))
        pop = pop or bar_pop

        # the successor's set-up (p' n and f (f + 1)), tracked while n moves
        pre_start = self.pre == IDLE and move_head and not pop and not self.mul_p.busy
        fx = target_floor(n_exit)
        if pre_start:
            self.n_sh = n
        start_fo = not self.mul_fo.busy
        fo_done, fo_prod = self.mul_fo.done, self.mul_fo.product
        start_fn = not self.mul_fn.busy
        fn_done, fn_prod = self.mul_fn.done, self.mul_fn.product
        p_done = self.mul_p.done
        self.mul_p.clock(pre_start, n_rate, n)
        self.mul_f.clock(pre_start, fx + 1, fx)
        self.mul_fo.clock(start_fo, self.feed, ovr)
        self.mul_fn.clock(start_fn, g("next_feed", 0), ovr)
        if pop:
            self.pre = IDLE
        elif pre_start:
            self.pre = BUSY
        elif self.pre == BUSY and p_done:
            self.pre = DONE
            self.p_sh, self.f_pre = self.mul_p.product, self.mul_f.product
        elif self.pre == DONE:                        # follow n after this edge
            gap = max(-2, min(2, n_d - self.n_sh))
            self.n_sh += gap
            self.p_sh += gap * n_rate
        # feed * override for the cap, recomputed all the time, for the segment and
        # for the head (taken over at the switch)
        if switch or load:
            self.fo, self.fo_valid, self.fo_ok = self.fo_next, self.fn_valid, 0
        else:
            if fo_done and self.fo_ok:
                self.fo, self.fo_valid = fo_prod, 1
            if start_fo:
                self.fo_ok = 1
        if pop:
            self.fn_valid = self.fn_ok = 0
        else:
            if fn_done and self.fn_ok:
                self.fo_next, self.fn_valid = fn_prod, 1
            if start_fn:
                self.fn_ok = int(bool(move_head))

        # refinement of the carried budget: + 2 p' floor(S / A), MSB first
        if ref_start and n:
            self.ref_r, self.ref_d = self.remaining, a_q << (self.nw - 1)
            self.ref_m, self.ref_count = n_rate << self.nw, self.nw
        elif load:
            self.ref_r, self.ref_d = max(load_r, 0), a_q << (self.nw - 1)
            self.ref_m, self.ref_count = n_rate << self.nw, self.nw
        elif cross:
            self.ref_count = 0
        elif self.ref_count:
            if ref_hit:
                self.ref_r -= self.ref_d
            self.ref_d >>= 1
            self.ref_m >>= 1
            self.ref_count -= 1

        decide.clock(event=bend or switch or load or (cross and not known), succ=known, n=n,
                     q=self.q, f_sq=f_sq, floor=floor, na=self.na, acc=self.acc, p=self.p,
                     budget_x=self.budget_x, bs=bs, v=v, va=v + a_q, limit=self.limit, fo=fo,
                     fo_valid=fo_valid)
        self.bar_count += int(bool(g("barrier_done", 0))) - bar_pop
        self.up, self.down = int(n_d > n), int(n_d < n)
        self.late = late
        self.next_pop = int(pop)
        self.n, self.v, self.q, self.p, self.na = n_d, v_d, q_d, p_d, na_d
        self.acc = acc_n
        self.bc = 0 if bend else self.bc + 1
        self.bs_q = g("block_shift", 0)
        self.hold_q = int(bool(hold))
        self.seg, self.rate, self.feed, self.limit = seg_n, rate_n, feed_n, limit_n
        self.exit, self.f_sq = exit_n, f_sq_n
        self.remaining, self.budget_x = rem_n, zx_n


def profile_stimulus(segments: list[Segment], *, quantum: int, block_shift: int = BLOCK_SHIFT_MIN,
                     override: int = 100, controls: list[tuple[int, str, int]] = (),
                     arrivals: Mapping[int, int] | None = None, max_cycles: int = 1_000_000,
                     barrier_delay: int = 3, resets: tuple[int, ...] = (),
                     tail: int = 2):
    """Inputs, clock by clock, of a profile queue holding `segments` (a stimulus
    generator: it is sent each clock's sample and follows `next_pop`).

    `controls`: (cycle, "hold" | "resume" | "override", value), sorted; `arrivals`:
    segment index -> the cycle it enters the queue (default: all at cycle 0); a
    barrier is done `barrier_delay` clocks after the generator stopped before it;
    `resets`: cycles with rst high (the queue starts over).  Ends `tail` clocks
    after the generator is idle with the queue empty.
    """
    arrivals = arrivals or {}
    head, hold, ovr, after = 0, 0, override, 0
    controls = list(controls)
    barrier_wait = None
    moving = pop = 0
    for cycle in range(max_cycles):
        if pop:
            head += 1
            barrier_wait = None
        while controls and controls[0][0] <= cycle:
            _, what, value = controls.pop(0)
            hold = {"hold": 1, "resume": 0}.get(what, hold)
            ovr = value if what == "override" else ovr
        rst = int(cycle in resets)
        if rst:
            head, barrier_wait = 0, None
        valid = head < len(segments) and arrivals.get(head, 0) <= cycle
        seg = segments[head] if valid else Segment()
        done = 0
        if valid and seg.barrier and not moving:
            barrier_wait = cycle if barrier_wait is None else barrier_wait
            done = int(cycle - barrier_wait == barrier_delay)
        if head >= len(segments) and not moving and not pop:
            after += 1
            if after > tail:
                return
        sample = yield {**seg.ports(valid), "barrier_done": done, "speed_quantum": quantum,
                        "block_shift": block_shift, "override": ovr, "hold": hold, "rst": rst}
        moving, pop = sample["moving"], sample["next_pop"] and not rst
    raise RuntimeError(f"profile not finished after {max_cycles} clocks")


def run_profile(segments: list[Segment], *, widths: Mapping[str, int] | None = None,
                model: SpeedRamp | None = None, **options) -> list[dict[str, int]]:
    """The model alone on `profile_stimulus(segments, **options)`: one sample per
    clock (sample i: the state after i edges)."""
    from .base import drive

    model = model or SpeedRamp(**(widths or {}))
    return drive(model, profile_stimulus(segments, **options))


def plan_exits(segments: list[Segment], quantum: int, pf: int,
               underrun_safe: bool = False) -> list[Segment]:
    """A reference backward pass (the host's job, here for tests): each segment's
    exit speed in quanta is the highest n <= both cruise speeds from which the rest
    of the queue can still be stopped, n^2 + 7 n <= Z0' / 2^PF + f' (f' + 1)
    (R(n, u) <= n^2 + n - f^2 - f + 2 n, the successor enters with up to one clock at n
    already travelled, and its first tick may keep n unchecked: up to 2 n less budget
    each), the last exit 0.  Barriers stop.
    `underrun_safe`: f' = 1, every segment can stop within itself (a queue that runs
    dry, or a successor set up late, still ends in a braked stop)."""
    out = list(segments)
    nxt_floor_sq = 0
    for i in range(len(out) - 1, -1, -1):
        seg = out[i]
        if seg.barrier:
            nxt_floor_sq = None
            continue
        if i == len(out) - 1 or nxt_floor_sq is None or out[i + 1].barrier:
            exit_n = 0
        else:
            nxt = out[i + 1]
            room = (nxt.budget >> pf) + (2 if underrun_safe else nxt_floor_sq)
            n = max(0, int((room) ** 0.5))
            while n > 0 and n * n + 7 * n > room:
                n -= 1
            exit_n = min(n, seg.feed // quantum, nxt.feed // quantum)
        out[i] = Segment(seg.feed, seg.limit, exit_n, seg.rate, seg.length, seg.budget)
        f = max(exit_n, 1)
        # what this segment's entry may be: stoppable within it to its floor
        nxt_floor_sq = f * f + f
    return out


def random_segments(rng, *, count: int, quantum: int, pf: int, block_shift: int,
                    feed_w: int, len_w: int, barriers: float = 0.0,
                    max_length: int | None = None, min_clocks: int = 0,
                    max_quanta: int = 200, min_quanta: int = 1,
                    underrun_safe: bool = False) -> list[Segment]:
    """Random moves (cruise 1 .. max_quanta quanta, rates 1/8 .. 1, lengths up to
    `max_length`, at least `min_clocks` clocks at the limit speed) with planned
    exits, and barriers with probability `barriers`."""
    segs = []
    max_length = max_length or min(1 << (len_w - 1), 400 * quantum * max_quanta)
    for _ in range(count):
        if segs and rng.random() < barriers:
            segs.append(Segment(barrier=True))
            continue
        feed = min(rng.randint(min_quanta, max_quanta) * quantum + rng.randrange(quantum), (1 << feed_w) - 1)
        limit = min(feed + rng.randrange(feed + 1), (1 << feed_w) - 1)
        rate = rng.randint(max(1, (1 << pf) // 8), 1 << pf)
        length = rng.randint(min_clocks * limit + 1, max(max_length, min_clocks * limit + 1))
        segs.append(Segment(feed, limit, 0, rate, length,
                            segment_budget(rate, length, quantum, block_shift)))
    return plan_exits(segs, quantum, pf, underrun_safe)
