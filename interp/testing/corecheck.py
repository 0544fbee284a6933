# SPDX-License-Identifier: Apache-2.0
"""cocotb checks shared by the lecture and arc core benches (tb/lin_*, tb/circ_*).

A `CoreTB` keeps one cycle model alive across moves (like the SU 1571551 bench),
runs whole commands through `tbkit.scoreboard`, and turns the samples into steps
for comparison with a step-level model.  The generic robustness checks (reset in
any cycle, start while busy) are written once here.
"""
from __future__ import annotations

from typing import Callable, Mapping

from cocotb.triggers import FallingEdge

from ..models.base import CycleModel, move
from .tbkit import TB, scoreboard


def moves(samples: list[dict]) -> list[tuple[int, int, dict]]:
    """(dx, dy, sample) for every sample with a step strobe."""
    out = []
    for s in samples:
        if s["step_x"] or s["step_y"]:
            out.append(((-1 if s["dir_x"] else 1) * s["step_x"],
                        (-1 if s["dir_y"] else 1) * s["step_y"], s))
    return out


class CoreTB(TB):
    """TB with a persistent cycle model and whole-command scoreboarding."""

    def __init__(self, dut, idle: Mapping[str, int], make_model: Callable[[], CycleModel]):
        super().__init__(dut)
        self.idle, self.make_model = dict(idle), make_model

    async def reset(self, idle=None, cycles: int = 2):
        await super().reset(self.idle if idle is None else idle, cycles)
        self.ref = self.make_model()

    async def run(self, load: Mapping[str, int], tick=lambda c: 1, context: str = "",
                  max_cycles: int = 1_000_000) -> list[dict]:
        """One command, compared with the model in every cycle; returns the samples."""
        return await scoreboard(self, self.ref, move(load, tick, max_cycles), context=context or str(load))

    async def run_cut(self, load, cycles: int, context: str = "") -> None:
        """The first `cycles` cycles of a command (scoreboarded), then a reset."""
        try:
            await self.run(load, max_cycles=cycles, context=context)
        except RuntimeError:
            pass                                    # not finished: cut short
        await self.reset()


async def reset_at_any_cycle(tb: CoreTB, load: Mapping[str, int], cycles: int) -> None:
    """rst in each cycle 0 .. cycles of a command: idle at once, no step after it."""
    for k in range(cycles + 1):
        await tb.reset()
        try:
            await tb.run(load, max_cycles=k, context=f"reset at {k}")
        except RuntimeError:
            pass
        tb.drive({"rst": 1, "start": 0})
        await FallingEdge(tb.dut.clk)
        tb.drive({"rst": 0, "tick": 1})
        for _ in range(12):
            await FallingEdge(tb.dut.clk)
            s = tb.sample({n: False for n in ("step_x", "step_y", "busy", "done")})
            assert not any(s.values()), f"reset at {k}: {s}"
    await tb.reset()


async def start_while_busy(tb: CoreTB, load: Mapping[str, int], other: Mapping[str, int]) -> list[dict]:
    """Hold start high with another command in every cycle of a move (set-up included): ignored."""

    def stim():
        sample = yield {**load, "start": 1, "tick": 1}
        while not (sample["done"] or sample.get("error")):
            sample = yield {**other, "start": 1, "tick": 1}
        yield {**other, "start": 0, "tick": 1}

    return await scoreboard(tb, tb.ref, stim(), context="start while busy")
