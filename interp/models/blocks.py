# SPDX-License-Identifier: Apache-2.0
"""Models of the building blocks, one per rtl/ module."""
from __future__ import annotations

from .base import CycleModel


def end_around_add(a: int, b: int, width: int, cin: int = 0) -> int:
    """Ones'-complement addition: the carry out of the top bit wraps into the LSB."""
    mask = (1 << width) - 1
    total = (a & mask) + (b & mask) + cin
    return ((total & mask) + (total >> width)) & mask


def ones_code(value: int, width: int) -> int:
    """Ones'-complement code of a small integer (negative: bits of |value| inverted)."""
    mask = (1 << width) - 1
    return value & mask if value >= 0 else ~(-value) & mask


def ones_value(code: int, width: int) -> int:
    """Integer meaning of a ones'-complement code (both zeros read as 0)."""
    mask = (1 << width) - 1
    code &= mask
    return -(~code & mask) if code >> (width - 1) else code


class UpDownCounter(CycleModel):
    """rtl/updown_counter.v: q += inc - dec - 2*dec2, or load."""

    watch = {"q": False, "q_n": False}

    def __init__(self, width: int, ones_complement: bool = False):
        self.width, self.ones = width, ones_complement
        self.mask = (1 << width) - 1
        self.q = 0

    @property
    def q_n(self) -> int:
        return ~self.q & self.mask

    def clock(self, inputs) -> None:
        if inputs["rst"]:
            self.q = 0
        elif inputs["load"]:
            self.q = inputs["load_value"] & self.mask
        else:
            delta = inputs["inc"] - inputs["dec"] - 2 * inputs["dec2"]
            if self.ones and delta < 0:     # subtract with end-around borrow: 1 - 1 = +0
                diff = self.q + delta
                self.q = (diff - (diff < 0)) & self.mask
            elif self.ones:
                self.q = end_around_add(self.q, ones_code(delta, self.width), self.width)
            else:
                self.q = (self.q + delta) & self.mask


class AccumAddSub(CycleModel):
    """rtl/accum_addsub.v: F += operand + cin (ones' complement: end-around carry)."""

    watch = {"f": False, "negative": False, "non_negative": False}

    def __init__(self, width: int, ones_complement: bool = False):
        self.width, self.ones = width, ones_complement
        self.mask = (1 << width) - 1
        self.f = 0

    @property
    def negative(self) -> int:
        return self.f >> (self.width - 1)

    @property
    def non_negative(self) -> int:
        return 1 - self.negative

    def clock(self, inputs) -> None:
        if inputs["rst"] or inputs["clear"]:
            self.f = 0
        elif inputs["load"]:
            self.f = inputs["load_value"] & self.mask
        elif inputs["add"]:
            if self.ones:
                self.f = end_around_add(self.f, inputs["operand"], self.width, inputs["cin"])
            else:
                self.f = (self.f + inputs["operand"] + inputs["cin"]) & self.mask


class StartStop(CycleModel):
    """rtl/start_stop.v: trigger 14 — set by start when idle, reset by stop."""

    watch = {"run": False, "accept": False, "finish": False}

    def __init__(self):
        self.run = 0
        self.inputs = {"start": 0, "stop": 0}

    @property
    def accept(self) -> int:     # combinational outputs follow the inputs driven now
        return self.inputs["start"] & (1 - self.run)

    @property
    def finish(self) -> int:
        return self.inputs["stop"] & self.run

    def clock(self, inputs) -> None:
        self.inputs = {"start": inputs["start"], "stop": inputs["stop"]}
        if inputs["rst"]:
            self.run = 0
        elif self.accept:
            self.run = 1
        elif self.finish:
            self.run = 0


def sign_analysis(tick: int, enable: int, negative: int) -> dict:
    """Node 18: AND 5 passes the generator pulse for F >= 0, AND 6 for F < 0."""
    return {"pulse_pos": tick & enable & (1 - negative), "pulse_neg": tick & enable & negative}


def increment_former(axial: int, diagonal: int, x_is_long: int) -> dict:
    """Node 20: long axis gets every step (OR 10/11), short axis the diagonals."""
    long_pulse, short_pulse = axial | diagonal, diagonal
    if x_is_long:
        return {"inc_x": long_pulse, "inc_y": short_pulse}
    return {"inc_x": short_pulse, "inc_y": long_pulse}


class SeqMult(CycleModel):
    """rtl/seq_mult.v: sequential signed a * b, radix 2, four carry-saved chunks.

    Cycle 0: start captures a, b.  Busy cycles k = 0 .. WIDTH+1: in cycle k the
    partial product b_k * A * 2^k (k = WIDTH-1: subtracted, as ~A * 2^k plus 2^k,
    preset in the sum in cycle 0) is registered, and the one registered
    a cycle before is added chunk by chunk (cycle 0 clears the sum instead), each
    chunk's carry entering the next chunk one cycle later; the last cycle only settles
    those carries.  `done` follows.
    """

    watch = {"busy": False, "done": False, "product": False}

    def __init__(self, width: int):
        self.width = width
        w = width
        self.borders = [0, (w - 1) // 2, w - 1, w - 1 + (w + 2) // 2, 2 * w]
        self.reset()

    def reset(self) -> None:
        self.acc = self.mcand = self.mplier = self.count = self.addend = 0
        self.carry = [0, 0, 0]
        self.sign_bit = self.busy = self.done = 0

    @property
    def product(self) -> int:
        return self.acc

    def clock(self, inputs) -> None:
        if inputs.get("rst"):
            self.reset()
            return
        w, pmask = self.width, (1 << 2 * self.width) - 1
        self.done = 0
        if not self.busy:
            if inputs.get("start"):
                a = inputs["a"] & ((1 << w) - 1)
                a -= (a >> (w - 1)) << w                          # signed
                self.mcand, self.mplier = a & pmask, inputs["b"] & ((1 << w) - 1)
                self.sign_bit, self.count, self.busy = 0, 0, 1
            return
        addend = self.addend
        self.addend = 0
        if self.mplier & 1:
            self.addend = (~self.mcand & -(1 << (w - 1)) & pmask) if self.sign_bit else self.mcand
        if self.count == 0:
            self.acc, self.carry = (self.mplier >> (w - 1)) << (w - 1), [0, 0, 0]   # the + 1 of -A * 2^(w-1)
        else:
            cins = [0, *self.carry]
            sums = []
            for j, (lo, hi) in enumerate(zip(self.borders, self.borders[1:])):
                mask = (1 << (hi - lo)) - 1
                sums.append((((self.acc >> lo) & mask) + ((addend >> lo) & mask) + cins[j], lo, hi - lo))
            self.acc = sum((s & ((1 << n) - 1)) << lo for s, lo, n in sums)
            self.carry = [s >> n for s, _, n in sums[:3]]
        self.mcand = (self.mcand << 1) & pmask
        self.mplier >>= 1
        self.sign_bit = int(self.count == w - 2)
        self.count += 1
        if self.count == w + 2:
            self.busy, self.done = 0, 1


class CircleSetup(CycleModel):
    """rtl/circle_setup.v: set-up of a circle command, register by register.

    Round 1 squares x0, y0, x1, y1 on four SeqMult models; a = x0^2 + y0^2 and
    b = x1^2 + y1^2 (ADD1), d = b - a and -d (ADD2), each a two-cycle sum of SW/2-bit
    chunks with a registered carry (one per sum).  Round 2 forms m^2 (as d^2), m = |d|;
    ADD3 forms t = min(a, b) + (m - 1) div 2 - m^2 from a carry-save step registered every
    cycle; CHECK shows on_band = d == 0 or
    (m < 2^(SW/2-1) and t >= 0).
    """

    IDLE, PREP, MUL1, ADD1, ADD2, MUL2, ADD3, CHECK = range(8)
    watch = {"busy": False, "check": False, "on_band": False}

    def __init__(self, mw: int, sw: int):
        self.mw, self.sw, self.sk = mw, sw, sw // 2
        self.mask = (1 << sw) - 1
        self.mults = [SeqMult(mw) for _ in range(4)]
        self.reset()

    def reset(self) -> None:
        self.state = self.sub = self.a = self.b = self.d = self.nd = self.t = 0
        self.m = self.h = self.dzero = self.msmall = self.tcs_s = self.tcs_c = 0
        self.zeros = self.zeros2 = (0, 0, 0)   # d == 0, d's and -d's bits from SW/2 - 1 up == 0 (two stages)
        self.carry = {"a": 0, "b": 0, "d": 0, "nd": 0, "t": 0}
        for mult in self.mults:
            mult.reset()

    def sum2(self, x: int, y: int, cin: int, hcin: int) -> tuple[int, int]:
        """(x + y + cin, carry out of the low chunk): high chunk with the registered carry."""
        sk, chunk = self.sk, (1 << self.sk) - 1
        lo = (x & chunk) + (y & chunk) + cin
        hi = ((x >> sk & chunk) + (y >> sk & chunk) + hcin) & chunk
        return hi << sk | lo & chunk, lo >> sk

    @property
    def busy(self) -> int:
        return int(self.state != self.IDLE)

    @property
    def check(self) -> int:
        return int(self.state == self.CHECK)

    @property
    def on_band(self) -> int:
        return int(self.dzero or (self.msmall and not self.t >> (self.sw - 1)))

    def clock(self, inputs) -> None:
        if inputs.get("rst"):
            self.reset()
            return
        mw, sw, mask = self.mw, self.sw, self.mask
        state, sub, top = self.state, self.sub, sw - 1
        p = [mult.product & mask for mult in self.mults]
        # Combinational values of this cycle (before the edge).
        carry = self.carry
        d_sum, d_c = self.sum2(self.b, ~self.a & mask, 1, carry["d"])
        nd_sum, nd_c = self.sum2(self.a, ~self.b & mask, 1, carry["nd"])
        t_sum, t_c = self.sum2(self.tcs_s, self.tcs_c, 0, carry["t"])
        m_abs = (self.nd if self.d >> top else self.d) & ((1 << mw) - 1)   # from the registers
        round1, round2 = state == self.PREP, state == self.MUL2 and sub
        squares = [inputs["x0"], inputs["y0"], inputs["x1"]]
        for k, mult in enumerate(self.mults[:3]):
            mult.clock({"start": int(round1), "a": squares[k], "b": squares[k]})
        # m^2 as d^2: the signed multiplier squares d's low mw bits (d itself whenever m^2 matters).
        op3 = inputs["y1"] if round1 else self.d & ((1 << mw) - 1)
        done = self.mults[3].done
        self.mults[3].clock({"start": int(round1 or round2), "a": op3, "b": op3})
        # Registers.  ADD3's carry-save step and the first stage of the wide zero tests,
        # every cycle (-m^2 = ~m^2 + 1).
        d_zero, dhi_zero, ndhi_zero = self.zeros2
        self.zeros2 = self.zeros
        self.zeros = (int(self.d == 0), int(self.d >> (self.sk - 1) == 0), int(self.nd >> (self.sk - 1) == 0))
        nsq = ~p[3] & mask
        self.tcs_s = self.a ^ self.h ^ nsq
        self.tcs_c = ((self.a & self.h | self.a & nsq | self.h & nsq) << 1 | 1) & mask
        self.sub = 0
        if state == self.IDLE:
            if inputs.get("start"):
                self.state = self.PREP
        elif state == self.PREP:
            self.state = self.MUL1
        elif state == self.MUL1:
            self.state = self.ADD1 if done else state
        elif state == self.ADD1:
            (self.a, carry["a"]), (self.b, carry["b"]) = self.sum2(p[0], p[1], 0, carry["a"]), \
                self.sum2(p[2], p[3], 0, carry["b"])
            self.sub = int(not sub)
            self.state = self.ADD2 if sub else state
        elif state == self.ADD2:
            self.d, self.nd, self.sub = d_sum, nd_sum, 1
            carry["d"], carry["nd"] = d_c, nd_c
            self.state = self.MUL2 if sub else state
        elif state == self.MUL2:                # round 2 starts in the first cycle
            self.h = ((self.m - 1) & ((1 << mw) - 1)) >> 1
            if sub:
                self.a = self.b if self.d >> top else self.a        # s = min(a, b)
                self.m = m_abs
            self.dzero = d_zero
            self.msmall = ndhi_zero if self.d >> top else dhi_zero
            self.state = self.ADD3 if done else state
        elif state == self.ADD3:
            self.t, carry["t"] = t_sum, t_c
            self.sub = int(not sub)
            self.state = self.CHECK if sub else state
        else:
            self.state = self.IDLE
