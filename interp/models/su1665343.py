# SPDX-License-Identifier: Apache-2.0
"""Golden models of the SU 1665343 circular interpolator.

`steps()` is the step-level algorithm, the patent's evaluation functions (1)-(6)
written out (F is kept as 4F so it stays an integer; it is always n + 0.75):

    sector 1 (X > Y):  F >= 0: Y step,   F -= 2Y + 1           (new Y)
                       F <  0: diagonal, F += 2(X - Y) - 1     (new X, Y)
    sector 2 (Y >= X): F >= 0: diagonal, F += 2(X - Y) - 1
                       F <  0: X step,   F += 2X - 1           (new X)
    switch when X - Y - 1 < 0: F += X + Y;  stop when X = 0 (CT7 = X - 1 < 0)

`Su1665343` is the cycle model of rtl/circ_su1665343.v: the same registers
(counters and adder as ones'-complement bit patterns), the same
micro-operations in the same cycles.  The RTL's load former forms F0 with
adders only, over `setup_cycles(width)` cycles after `start`; the model holds
the captured inputs for as long and then loads the values of `preload()`.  `trace()` turns its (or the RTL's)
per-cycle samples into the patent's Table 2 rows.
"""
from __future__ import annotations

from dataclasses import dataclass

from .base import MOTION_OUTPUTS, CycleModel
from .blocks import AccumAddSub, UpDownCounter, ones_code, ones_value

CORRECTION_CYCLES = 4       # pulse expander 25


def setup_cycles(width: int) -> int:
    """Cycles from `start` to the load (or refusal): the RTL's load former runs
    Horner's rule for E = R^2 - X^2 - Y^2 (three micro-steps per bit), then
    seven steps for the checks and F0, then the load cycle."""
    return 3 * width + 8


# Ones'-complement codes: the counters' and the adder's number system.
oc_bits = ones_code
oc_value = ones_value


def r_max(width: int) -> int:
    """Largest radius the counters hold (|CT7|, |CT8| <= R + 1)."""
    return (1 << (width - 1)) - 2


def start_error(r: int, x0: int, y0: int, width: int) -> str | None:
    """Why the core refuses this start, or None (the RTL's `error` condition)."""
    if r < 1:
        return f"R = {r}: the radius must be at least 1"
    if r > r_max(width):
        return f"R = {r} does not fit WIDTH = {width} (R <= {r_max(width)})"
    if x0 < 0 or y0 < 0 or not (r - 1) ** 2 <= x0 * x0 + y0 * y0 <= (r + 1) ** 2:
        return f"start point ({x0}, {y0}) is farther than one step from the circle R = {r}"
    return None


def preload(r: int, x0: int, y0: int) -> tuple[int, int, int, int]:
    """(4 F0, CT7, CT8, T16) by formulas (3)/(4); T16 = input 34 (Y >= X)."""
    if y0 >= x0:        # (4): F2,0 = R^2 - (X - 1)^2 - (Y + 0.5)^2
        return 4 * r * r - 4 * (x0 - 1) ** 2 - (2 * y0 + 1) ** 2, x0 - 1, x0 - y0, 1
    # (3): F1,0 = R^2 - (X - 0.5)^2 - (Y + 1)^2
    return 4 * r * r - (2 * x0 - 1) ** 2 - 4 * (y0 + 1) ** 2, y0, x0 - y0 - 1, 0


@dataclass
class Step:
    kind: str           # "y" | "x" | "diagonal"
    x: int              # point after the step
    y: int
    f4: int             # 4F after the step and its correction
    switch: str = ""    # "", "A" or "B": the sector switch this step caused


def steps(r: int, x0: int | None = None, y0: int | None = None) -> list[Step]:
    """The step sequence from (x0, y0) (default (R, 0)) to X = 0 by the equations."""
    x, y = (r, 0) if x0 is None else (x0, y0)
    f4, _, _, sector2 = preload(r, x, y)
    out = []
    while x > 0:
        switch = ""
        if not sector2:
            if f4 >= 0:
                kind, y = "y", y + 1
                f4 -= 4 * (2 * y + 1)
            else:
                kind, x, y = "diagonal", x - 1, y + 1
                f4 += 4 * (2 * (x - y) - 1)
            if x - y - 1 < 0:                       # (6): F2 = F1 + X + Y
                switch = "B" if x - y < 0 else "A"
                f4 += 4 * (x + y)
                sector2 = 1
        elif f4 >= 0:
            kind, x, y = "diagonal", x - 1, y + 1
            f4 += 4 * (2 * (x - y) - 1)
        else:
            kind, x = "x", x - 1
            f4 += 4 * (2 * x - 1)
        out.append(Step(kind, x, y, f4, switch))
    return out


def path_string(path: list[Step]) -> str:
    return "".join({"y": "Y", "x": "X", "diagonal": "D"}[s.kind] for s in path)


def radial_error(r: int, path: list[Step], x0: int | None = None, y0: int | None = None) -> float:
    """Largest | |P| - R | over the start point and every point of the path."""
    points = [(r, 0) if x0 is None else (x0, y0)] + [(s.x, s.y) for s in path]
    return max(abs((x * x + y * y) ** 0.5 - r) for x, y in points)


class DelayLine(CycleModel):
    """rtl/delay_line.v: taps[i] is d delayed by i + 1 cycles (delay elements 12 ... 26)."""

    watch = {"taps": False}

    def __init__(self, length: int):
        self.q = [0] * length

    @property
    def taps(self) -> int:
        return sum(bit << i for i, bit in enumerate(self.q))

    def __getitem__(self, i: int) -> int:
        return self.q[i]

    def __bool__(self) -> bool:
        return any(self.q)

    def clock(self, inputs) -> None:
        if inputs.get("rst") or inputs.get("clear"):
            self.q = [0] * len(self.q)
        else:
            self.q = [int(bool(inputs["d"]))] + self.q[:-1]


class PulseExpander(CycleModel):
    """rtl/pulse_expander.v: `active` for LENGTH cycles after a trigger (expander 25)."""

    watch = {"active": False}

    def __init__(self, length: int):
        self.length, self.count = length, 0

    @property
    def active(self) -> int:
        return int(self.count != 0)

    def clock(self, inputs) -> None:
        if inputs.get("rst") or inputs.get("clear"):
            self.count = 0
        elif inputs["trigger"]:
            self.count = self.length
        elif self.count:
            self.count -= 1


def commutator(width: int, sel: tuple[int, int, int], channels) -> int:
    """rtl/commutator.v (commutator 6): OR over k of sel_k AND {v_k, lsb_k}."""
    out = 0
    for s, (v, lsb) in zip(sel, channels):
        if s:
            out |= (v << 1 | lsb) & ((1 << (width + 1)) - 1)
    return out


class Su1665343(CycleModel):
    """Cycle model of rtl/circ_su1665343.v (names as the RTL's nets)."""

    watch = {**MOTION_OUTPUTS, "error": False, "ct7": False, "ct8": False, "f": False,
             "t16": False, "code": False, "xfer_step": False, "xfer_corr": False,
             "corr_end": False}

    def __init__(self, width: int = 12):
        self.width, self.fw = width, width + 5
        self.reset()

    def reset(self) -> None:
        self.run = self.t16 = 0
        self.setup_left, self.captured = 0, (0, 0, 0)     # load former: cycles to go, (r, x0, y0)
        self.u_ct7 = UpDownCounter(self.width, True)
        self.u_ct8 = UpDownCounter(self.width, True)
        self.u_adder1 = AccumAddSub(self.fw, True)
        self.d12, self.d13, self.d14, self.d26 = (DelayLine(2) for _ in range(4))
        self.d19 = DelayLine(4)
        self.expander = PulseExpander(CORRECTION_CYCLES)
        self.step_x = self.step_y = self.dir_x = self.dir_y = self.done = self.error = 0

    @property
    def busy(self) -> int:
        return int(bool(self.run or self.setup_left))

    ct7 = property(lambda self: self.u_ct7.q)
    ct8 = property(lambda self: self.u_ct8.q)
    f = property(lambda self: self.u_adder1.f)

    def _ct8_is(self, value: int) -> bool:
        return self.ct8 == oc_bits(value, self.width)

    # Combinational nets of the RTL that depend only on registers.
    @property
    def and22(self) -> int:
        return int((self.d12[0] or self.d13[0]) and not self.t16 and self._ct8_is(-1))

    @property
    def and23(self) -> int:
        return int(self.d12[0] and not self.t16 and self._ct8_is(-2))

    @property
    def or15(self) -> int:
        return int(self.d14[1] or self.and22 or self.d19[2])

    @property
    def code(self) -> int:
        """Commutator 6: {~CT7, 0}, {CT8, ~T16} or {CT7, T16}."""
        mask = (1 << self.width) - 1
        return commutator(self.width, (self.d13[1], self.d12[1], self.or15),
                          ((~self.ct7 & mask, 0), (self.ct8, 1 - self.t16), (self.ct7, self.t16)))

    @property
    def xfer_step(self) -> int:
        return int(self.d12[1] or self.d13[1] or self.d14[1])

    @property
    def xfer_corr(self) -> int:
        return int(self.and22 or self.d19[2])

    @property
    def corr_end(self) -> int:
        return int(self.d26[1] or self.d19[3])

    def clock(self, inputs) -> None:
        if inputs.get("rst"):
            self.reset()
            return
        w, fw = self.width, self.fw
        ct7_negative = self.ct7 >> (w - 1) & 1
        finish = self.run and ct7_negative
        idle_start = bool(inputs.get("start")) and not self.busy
        # load former: start captures r, x0, y0; the last set-up cycle loads or refuses
        set_up = self.setup_left == 1
        r, x0, y0 = self.captured
        ok = start_error(r, x0, y0, w) is None
        load, refuse = set_up and ok, set_up and not ok
        if self.setup_left:
            self.setup_left -= 1
        elif idle_start:
            self.captured = tuple(int(inputs.get(k, 0)) for k in ("r", "x0", "y0"))
            self.setup_left = setup_cycles(w)
        settle = self.d12 or self.d13 or self.d14 or self.expander.active
        enable = self.run and not ct7_negative and not settle and inputs.get("tick")
        f_negative = self.f >> (fw - 1) & 1
        and2 = enable and not self.t16 and f_negative
        and3 = enable and not self.t16 and not f_negative
        and10 = enable and self.t16 and not f_negative
        and11 = enable and self.t16 and f_negative
        or9 = and2 or and10
        and22, and23 = self.and22, self.and23
        add = self.d13[1] or self.d12[1] or self.or15
        code = self.code
        sign = code >> w & 1
        operand = code << 2 | sign * 3 | (((1 << (fw - w - 3)) - 1) * sign) << (w + 3)

        f4, ct7_0, ct8_0, sector2 = preload(r, x0, y0)
        corr_ct7 = self.d19[1] or self.d19[3] or self.d26[1]
        or17 = or9 or and3 or and11 or corr_ct7
        reload = int(bool(load or finish))
        self.u_ct7.clock(dict(rst=0, load=reload, load_value=oc_bits(ct7_0, w) if load else 0,
                              inc=int(bool(or17 and not self.t16)), dec=int(bool(or17 and self.t16)),
                              dec2=0))
        self.u_ct8.clock(dict(rst=0, load=reload, load_value=oc_bits(ct8_0, w) if load else 0,
                              inc=int(bool(and22 or and23)), dec=int(bool(and3 or and11)),
                              dec2=int(bool(or9))))
        self.u_adder1.clock(dict(rst=0, clear=int(bool(finish)), load=int(bool(load)),
                                 load_value=oc_bits(f4, fw), add=int(bool(add)), operand=operand, cin=0))
        # triggers 4 and 16 (start_stop: set when clear, reset when set)
        t16_set = (load and sector2) or and22 or and23
        if t16_set and not self.t16:
            self.t16 = 1
        elif finish and self.t16:
            self.t16 = 0
        self.run = 1 if load else (0 if finish else self.run)
        clear = int(bool(finish))
        for line, d in ((self.d12, or9), (self.d13, and3), (self.d14, and11), (self.d26, and22),
                        (self.d19, and23)):
            line.clock({"clear": clear, "d": d})
        self.expander.clock({"clear": clear, "trigger": and22 or and23})
        self.step_x = int(bool(or9 or and11))
        self.step_y = int(bool(or9 or and3))
        if load:
            self.dir_x, self.dir_y = 1, 0
        self.done, self.error = int(bool(finish)), int(refuse)


def trace(samples: list[dict], width: int) -> list[dict]:
    """Table 2 rows from per-cycle samples: one per step and per correction micro-step.

    A step row holds CT7, CT8, F after the step's transfer and the commutator
    code it added; the last step (CT7 negative, no transfer) has no code and no F.
    Correction rows ("9a", "9b") follow the circuit's order: in case A the
    correction's transfer precedes the step's own (see the RTL header).
    """
    rows, step, letter = [], 0, 0
    pending = None

    def row(label, kind, after, code=None, with_f=True):
        return {"step": label, "kind": kind, "ct7": oc_value(after["ct7"], width),
                "ct8": oc_value(after["ct8"], width),
                "code": None if code is None else oc_value(code, width + 1),
                "f": oc_value(after["f"], width + 5) / 4 if with_f else None}

    for i, s in enumerate(samples[:-1]):
        if s["step_x"] or s["step_y"]:
            step, letter = step + 1, 0
            pending = "diagonal" if s["step_x"] and s["step_y"] else ("x" if s["step_x"] else "y")
            if samples[i + 1]["done"]:
                rows.append(row(str(step), pending, s, with_f=False))
                pending = None
        if s["xfer_step"] and pending:
            rows.append(row(str(step), pending, samples[i + 1], s["code"]))
            pending = None
        if s["xfer_corr"] or s["corr_end"]:
            label = f"{step}{'abcd'[letter]}"
            letter += 1
            rows.append(row(label, "correction", samples[i + 1], s["code"] if s["xfer_corr"] else None))
    return rows


def per_step(rows: list[dict]) -> list[tuple[str, float | None]]:
    """(kind, F after the step and its correction) for each step of a trace."""
    kinds: dict[int, str] = {}
    f_after: dict[int, float | None] = {}
    for row in rows:
        n = int(row["step"].rstrip("abcd"))
        if row["kind"] != "correction":
            kinds[n] = row["kind"]
        if row["f"] is not None or n not in f_after:
            f_after[n] = row["f"]
    return [(kinds[n], f_after[n]) for n in sorted(kinds)]


def expected_per_step(path: list[Step]) -> list[tuple[str, float | None]]:
    """The same from the step-level model (the last step makes no transfer,
    unless it switched sectors: then the correction runs before CT7 is seen)."""
    last = len(path) - 1
    return [(s.kind, None if n == last and not s.switch else s.f4 / 4) for n, s in enumerate(path)]


STEP_CYCLES = 3             # pulse, settle/check, transfer (delay elements 12, 13, 14)


def move_cycles(path: list[Step], width: int = 12) -> int:
    """Cycle of the `done` sample at full speed (`tick` high), cycle 0 = start.

    The load is in cycle setup_cycles(width) (the RTL's default WIDTH is 12),
    the first pulse in the next; a step takes STEP_CYCLES, a sector switch
    adds the expander's CORRECTION_CYCLES - 1; `done` follows the cycle in
    which CT7 is negative.
    """
    load = setup_cycles(width)
    if not path:
        return load + 2
    pulses = load + 1 + sum(STEP_CYCLES + (CORRECTION_CYCLES - 1 if s.switch else 0) for s in path[:-1])
    return pulses + (2 if not path[-1].switch else 2 * STEP_CYCLES + 1)
