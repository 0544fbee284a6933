# SPDX-License-Identifier: Apache-2.0
"""Arc run loop: RTL vs cycle model every cycle, steps vs the step-level midpoint model.

Every move loads the inputs (`run` low for a few cycles), then runs with a tick
pattern; the octant reloads (no step, whatever `tick`) are compared too.  The point
and E are compared inside the stepper (its step stage, arc_step_stage); the stepper's
parts (arc_loop, arc_reload, arc_octant, arc_end_tables, arc_end_window, and the leaves
mux_add, chain_add) are covered through it.
"""
import itertools
import math

import cocotb
import pytest

from interp.testing.corecheck import moves
from interp.models.arc import RELOAD_CYCLES, START_CYCLES, ArcStepper, arc_steps
from interp.models.lecture import within_half_step
from interp.simulation.runner import run_cocotb
from interp.models.base import CycleModel
from interp.testing.tbkit import TB, scoreboard, seeded_rng

# make test runs this bench on Verilator alone, its faster simulator (make test-all: both)
QUICK_SIMULATOR = "verilator"

IDLE = {"run": 0, "tick": 0, "u0": 0, "v0": 0, "u1": 0, "v1": 0, "ccw": 0}


def inputs(u0, v0, u1, v1, ccw):
    return {"u0": u0, "v0": v0, "u1": u1, "v1": v1, "ccw": ccw}


def arc(load, tick):
    """`run` low for 9 cycles with the inputs, then run and tick until `fin`, then 2 idle cycles."""
    for _ in range(9):
        yield {**load, "run": 0, "tick": 1}
    cycle = 0
    sample = yield {**load, "run": 1, "tick": tick(cycle)}
    while not sample["fin"]:
        cycle += 1
        if cycle > 100_000:
            raise RuntimeError("no fin")
        sample = yield {**load, "run": 1, "tick": tick(cycle)}
    for _ in range(2):
        yield {**load, "run": 0, "tick": 0}


async def check(tb, u0, v0, u1, v1, ccw, full, tick=lambda c: 1):
    load = inputs(u0, v0, u1, v1, ccw)
    samples = await scoreboard(tb, tb.ref, arc(load, tick), context=str((u0, v0, u1, v1, ccw)))
    got = [(dx, dy) for dx, dy, _ in moves(samples)]
    assert got == [(s.dx, s.dy) for s in arc_steps(0, 0, u0, v0, u1, v1, ccw, full)], (u0, v0, u1, v1, ccw)
    return samples


# The model's point and E, which the stepper keeps inside its step stage.
PROBES = {"u": "u_step_stage.position_u", "v": "u_step_stage.position_v", "e": "u_step_stage.e_value"}


class Probed(CycleModel):
    """A cycle model whose watched names are the DUT's signals (PROBES: inside it)."""

    def __init__(self, model: CycleModel, probes: dict):
        self.model, self.names = model, {probes.get(n, n): n for n in model.watch}
        self.watch = {probes.get(n, n): signed for n, signed in model.watch.items()}

    def clock(self, inputs) -> None:
        self.model.clock(inputs)

    def sample(self, names=None) -> dict:
        return {n: int(getattr(self.model, self.names[n])) for n in (self.watch if names is None else names)}


async def setup(dut):
    tb = TB(dut)
    await tb.reset(IDLE)
    tb.ref = Probed(ArcStepper(), PROBES)
    return tb


@cocotb.test()
async def circles(dut):
    """Full circles R = 1 .. 12 both ways, ticks every cycle: six reload cycles per octant, two to start."""
    tb = await setup(dut)
    for r, ccw in itertools.product(range(1, 13), (0, 1)):
        samples = await check(tb, r, 0, r, 0, ccw, True)
        steps = len(arc_steps(0, 0, r, 0, r, 0, ccw, True))
        run_cycles = len(samples) - 7 - 3
        assert steps + START_CYCLES < run_cycles <= steps + START_CYCLES + RELOAD_CYCLES * 8 + 1, \
            (r, steps, run_cycles)


@cocotb.test()
async def exhaustive_small(dut):
    """Every start with |u|, |v| <= 4, every end within half a step, both ways."""
    tb = await setup(dut)
    for u0, v0 in itertools.product(range(-4, 5), repeat=2):
        if u0 == v0 == 0:
            continue
        r2 = u0 * u0 + v0 * v0
        ends = [(u, v) for u, v in itertools.product(range(-6, 7), repeat=2)
                if within_half_step(r2, u * u + v * v) and (u, v) != (u0, v0)]
        for (u1, v1), ccw in itertools.product(ends, (0, 1)):
            await check(tb, u0, v0, u1, v1, ccw, False)


@cocotb.test()
async def random_arcs(dut):
    """Random radii up to the width's limit, random tick patterns (a tick in a reload cycle waits)."""
    rng = seeded_rng(dut, "random_arcs")
    tb = await setup(dut)
    width = int(dut.WIDTH.value)
    for n in range(40):
        r = int(2 ** rng.uniform(2, width - 3.6))
        t0, sweep = rng.random() * 2 * math.pi, rng.uniform(-1, 1) * min(2 * math.pi, 300 / r)
        u0, v0 = round(r * math.cos(t0)), round(r * math.sin(t0))
        u1, v1 = round(r * math.cos(t0 + sweep)), round(r * math.sin(t0 + sweep))
        if (u0, v0) == (0, 0) or (u0, v0) == (u1, v1) or not within_half_step(u0 * u0 + v0 * v0, u1 * u1 + v1 * v1):
            continue
        density = rng.choice([1.0, 0.7, 0.4])
        await check(tb, u0, v0, u1, v1, int(sweep > 0), False, tick=lambda c: rng.random() < density)


# The loop adders' family forms (rtl/ecp5/, rtl/ice40/) are proved equivalent to the
# portable ones simulated here by `make formal` (formal/arc_leaves.sby).
@pytest.mark.parametrize("width", [8, 32])
def test_arc_stepper(sim, width):
    run_cocotb(toplevel="arc_stepper", test_module="test_arc_stepper", sim=sim,
               parameters={"WIDTH": width}, name=f"arc_stepper_w{width}")
