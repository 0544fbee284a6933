# SPDX-License-Identifier: Apache-2.0
"""cocotb side of the benches: clock/reset, cycle-by-cycle scoreboard.

Timing convention shared by every bench and by `interp run`: inputs are driven
and outputs are sampled at the falling edge of `clk`, so each sample is the
state the previous rising edge left, and each drive is what the next rising
edge sees.  A cycle model (interp.models.base.CycleModel) is clocked with the
same inputs, and every watched signal must agree in every cycle.
"""
from __future__ import annotations

import random
from typing import Callable, Generator, Mapping

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge

from ..models.base import CycleModel
from .seeds import seeded_random


def seeded_rng(dut, name: str) -> random.Random:
    """A random generator whose seed is logged and can be forced with SEED=..."""
    return seeded_random(name, dut._log.info)[0]


def read(dut, name: str, signed: bool = False) -> int:
    """Integer value of `dut.<name>` (dotted paths reach into instances)."""
    handle = dut
    for part in name.split("."):
        handle = getattr(handle, part)
    value = handle.value
    if signed:
        return value.to_signed()
    return int(value)


def write(dut, name: str, value: int) -> None:
    handle = getattr(dut, name)
    handle.value = int(value) & ((1 << len(handle)) - 1)


class TB:
    """Clock, reset and per-cycle drive/sample for one DUT."""

    def __init__(self, dut, period_ns: int = 10):
        self.dut = dut
        self.cycle = 0
        cocotb.start_soon(Clock(dut.clk, period_ns, unit="ns").start())

    async def reset(self, idle: Mapping[str, int], cycles: int = 2) -> None:
        """Hold rst for `cycles` rising edges with the `idle` inputs applied."""
        await FallingEdge(self.dut.clk)
        self.drive({**idle, "rst": 1})
        for _ in range(cycles):
            await FallingEdge(self.dut.clk)
        self.drive({"rst": 0})
        self.cycle = 0

    def drive(self, inputs: Mapping[str, int]) -> None:
        for name, value in inputs.items():
            write(self.dut, name, value)

    def sample(self, watch: Mapping[str, bool]) -> dict[str, int]:
        """Read every watched signal; `watch` maps name -> signed?"""
        return {name: read(self.dut, name, signed) for name, signed in watch.items()}

    async def tick(self, inputs: Mapping[str, int]) -> None:
        """Apply `inputs` for one rising edge, return at the next falling edge."""
        self.drive(inputs)
        await FallingEdge(self.dut.clk)
        self.cycle += 1


async def run_stimulus(
    tb: TB,
    stimulus: Generator[Mapping[str, int], dict, None],
    sample: Callable[[], dict[str, int]],
    on_edge: Callable[[Mapping[str, int]], None] = lambda inputs: None,
    first: Mapping[str, int] | None = None,
) -> list[dict[str, int]]:
    """Drive `stimulus` cycle by cycle (protocol of interp.models.base.drive).

    `sample()` is taken before the first edge and after every edge and is sent
    to the stimulus; `on_edge(inputs)` runs with each edge (a model's clock).
    `first`: the stimulus's first inputs, if the caller already took them.
    Returns the samples.
    """
    samples = [sample()]
    inputs = next(stimulus) if first is None else first
    while True:
        on_edge(inputs)
        await tb.tick(inputs)
        samples.append(sample())
        try:
            inputs = stimulus.send(samples[-1])
        except StopIteration:
            return samples


async def scoreboard(
    tb: TB,
    model: CycleModel,
    stimulus: Generator[Mapping[str, int], dict, None],
    watch: Mapping[str, bool] | None = None,
    context: str = "",
) -> list[dict[str, int]]:
    """Clock DUT and model with the same inputs; assert at the first difference.

    `stimulus` is a generator (see interp.models.base.drive): it yields the
    inputs for the next rising edge and is sent each cycle's sample.  Returns
    the per-cycle samples (the DUT's, equal to the model's).
    """
    watch = dict(watch if watch is not None else model.watch)

    def compare() -> dict[str, int]:
        got = tb.sample(watch)
        want = model.sample(watch)
        if got != want:
            diff = {k: (got[k], want[k]) for k in watch if got[k] != want[k]}
            raise AssertionError(
                f"{context}: cycle {tb.cycle}: RTL != model as (rtl, model): {diff}; "
                f"model state {want}"
            )
        return got

    return await run_stimulus(tb, stimulus, compare, model.clock)
