# SPDX-License-Identifier: Apache-2.0
"""Golden models of the SU 1571551 linear interpolator.

`steps()` is the step-level algorithm, written as the patent's expressions:
  (1)  F0 = L/2 - S;  F >= 0: axial,    F -= S;        F < 0: diagonal, F += L - S
  (5)  F >= 0: axial,    F -= C2, C1 -= 1;   F < 0: diagonal, F += C1, C2 -= 1
with C1 = L - S, C2 = S loaded at the start (live counters).  F is kept doubled
so it stays an integer (the patent's 0.5 is one extra LSB).

`Su1571551` is the cycle model of rtl/su1571551.v: same registers, same edges; and
of rtl/lin_exact.v (the exact mode retimed: the same values in every cycle).
"""
from __future__ import annotations

from dataclasses import dataclass

from .base import MOTION_OUTPUTS, CycleModel

MODES = ("faithful", "exact")


@dataclass
class Step:
    kind: str       # "axial" | "diagonal"
    dx: int
    dy: int
    f2: int         # 2F after the step
    ctr1: int       # counter 1 after the step
    ctr2: int       # counter 2 after the step (logical value, as in the patent's table)

    @property
    def f(self) -> float:
        return self.f2 / 2


def steps(x: int, y: int, mode: str = "exact") -> list[Step]:
    """The step sequence for the move (x, y) by expression (1) or (5)."""
    if mode not in MODES:
        raise ValueError(f"mode must be one of {MODES}")
    big, small = max(abs(x), abs(y)), min(abs(x), abs(y))
    sx, sy = (-1 if x < 0 else 1), (-1 if y < 0 else 1)
    x_is_long = abs(x) >= abs(y)                     # trigger 15
    f2 = big - 2 * small                             # 2 * (L/2 - S), formula (2)
    c1, c2 = big - small, small                      # formulas (3), (4) at d = k = 0
    out = []
    while c1 or c2:
        if f2 >= 0:                                  # axial: long axis only
            f2 -= 2 * (small if mode == "exact" else c2)
            c1 -= 1
            kind, dl, ds = "axial", 1, 0
        else:                                        # diagonal: both axes
            f2 += 2 * ((big - small) if mode == "exact" else c1)
            c2 -= 1
            kind, dl, ds = "diagonal", 1, 1
        if c1 < 0:
            raise AssertionError(f"counter 1 below zero for ({x}, {y}) in {mode} mode")
        dx, dy = (dl, ds) if x_is_long else (ds, dl)  # expression (7)
        out.append(Step(kind, dx * sx, dy * sy, f2, c1, c2))
    return out


def max_deviation(x: int, y: int, path: list[Step]) -> float:
    """Largest distance (in steps) from a visited point to the ideal line."""
    if x == 0 and y == 0:
        return 0.0
    norm = (x * x + y * y) ** 0.5
    px = py = worst = 0
    for s in path:
        px, py = px + s.dx, py + s.dy
        worst = max(worst, abs(px * y - py * x))
    return worst / norm


class Su1571551(CycleModel):
    """Cycle model of rtl/su1571551.v and rtl/lin_exact.v (registers named as the RTL's nets)."""

    watch = {**MOTION_OUTPUTS, "f": True, "ctr1": True, "ctr2": True}

    def __init__(self, width: int = 32, exact: bool = True):
        self.width, self.exact = width, exact
        self.reset()

    def reset(self) -> None:
        self.frame = self.run = self.x_is_long = 0
        self.f = self.ctr1 = self.ctr2 = 0
        self.op_diagonal = self.op_axial = 0
        self.step_x = self.step_y = self.dir_x = self.dir_y = self.done = 0

    @property
    def busy(self) -> int:
        return self.frame | self.run

    def _signed(self, value: int) -> int:
        w = self.width
        value &= (1 << w) - 1
        return value - (1 << w) if value >> (w - 1) else value

    def clock(self, inputs) -> None:
        if inputs.get("rst"):
            self.reset()
            return
        load = bool(inputs.get("start")) and not self.busy
        at_end = self.run and self.ctr1 == 0 and self.ctr2 == -1      # AND 9
        axial = diagonal = 0
        if self.run and not at_end and inputs.get("tick"):               # node 18
            axial, diagonal = (1, 0) if self.f >= 0 else (0, 1)
        nxt = {}
        if load:
            x, y = self._signed(inputs["x"]), self._signed(inputs["y"])
            big, small = max(abs(x), abs(y)), min(abs(x), abs(y))
            nxt = dict(ctr1=big - small, ctr2=small, f=big - 2 * small,
                       x_is_long=int(abs(x) >= abs(y)), dir_x=int(x < 0), dir_y=int(y < 0),
                       op_diagonal=big - small, op_axial=-small)
        elif at_end:                                                     # finish clears
            nxt = dict(ctr1=0, ctr2=0, f=0, x_is_long=0)
        else:
            if axial:
                operand = self.op_axial if self.exact else -self.ctr2 - 1   # ~ctr2
                nxt.update(f=self.f + 2 * operand, ctr1=self.ctr1 - 1)
            if diagonal:
                operand = self.op_diagonal if self.exact else self.ctr1
                nxt.update(f=self.f + 2 * operand, ctr2=self.ctr2 - 1)
            if self.frame:
                nxt.update(ctr2=self.ctr2 - 1)                           # OR 13
        long_pulse, short_pulse = axial | diagonal, diagonal             # node 20
        self.step_x = long_pulse if self.x_is_long else short_pulse
        self.step_y = short_pulse if self.x_is_long else long_pulse
        self.done = int(bool(at_end))
        if self.frame:
            self.run = 1                                                 # trigger 14
        elif at_end:
            self.run = 0
        self.frame = int(load)
        for name, value in nxt.items():
            setattr(self, name, value)
