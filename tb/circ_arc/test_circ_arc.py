# SPDX-License-Identifier: Apache-2.0
"""Production arc core: RTL vs cycle model vs the step-level midpoint model.

Every arc is also checked for the promises of the core: it ends exactly at the
end point, and every visited point is within half a step of the circle.
"""
import itertools
import math

import cocotb
import pytest

from interp.cores.arc import PROBES
from interp.testing.corecheck import CoreTB, moves, reset_at_any_cycle, start_while_busy
from interp.testing.tbkit import seeded_rng
from interp.models.base import CycleModel
from interp.models.arc import CircArc, arc_error, arc_setup_cycles, arc_steps
from interp.models.lecture import radial_deviation, within_half_step
from interp.simulation.runner import run_cocotb

# make test runs this bench on Verilator alone, its faster simulator (make test-all: both)
QUICK_SIMULATOR = "verilator"

IDLE = {"start": 0, "tick": 0, "cx": 0, "cy": 0, "x0": 0, "y0": 0, "x1": 0, "y1": 0, "ccw": 0, "full": 0}


class Probed(CycleModel):
    """CircArc with the watched names of the DUT: its point and E inside it (PROBES)."""

    def __init__(self, model: CycleModel):
        self.model, self.names = model, {PROBES.get(n, n): n for n in model.watch}
        self.watch = {PROBES.get(n, n): signed for n, signed in model.watch.items()}

    def clock(self, inputs) -> None:
        self.model.clock(inputs)

    def sample(self, names=None) -> dict:
        return {n: int(getattr(self.model, self.names[n])) for n in (self.watch if names is None else names)}


async def setup(dut):
    width = int(dut.WIDTH.value)
    tb = CoreTB(dut, IDLE, lambda: Probed(CircArc(width)))
    tb.width = width
    await tb.reset()
    return tb


async def check_arc(tb, cx, cy, x0, y0, x1, y1, ccw, full=0, tick=lambda c: 1):
    """Scoreboard one command; steps against the model; end point and deviation."""
    load = {"cx": cx, "cy": cy, "x0": x0, "y0": y0, "x1": x1, "y1": y1, "ccw": ccw, "full": full}
    samples = await tb.run(load, tick, context=str(load))
    got = [(dx, dy) for dx, dy, _ in moves(samples)]
    reason = arc_error(cx, cy, x0, y0, x1, y1, tb.width)
    if reason:
        assert not got and sum(s["error"] for s in samples) == 1 and not any(s["done"] for s in samples), \
            f"{load}: {reason}"
        return got
    want = arc_steps(cx, cy, x0, y0, x1, y1, ccw, full)
    assert got == [(w.dx, w.dy) for w in want], str(load)
    assert sum(s["done"] for s in samples) == 1 and not any(s["error"] for s in samples)
    assert (x0 + sum(d[0] for d in got), y0 + sum(d[1] for d in got)) == (x1, y1), f"{load}: end point missed"
    assert radial_deviation(x0, y0, want, cx, cy) <= 0.5, f"{load}: more than half a step off"
    return got


@cocotb.test()
async def circles(dut):
    """Full circles R = 1 .. 30 (every third at full width) about (3, -2), both ways."""
    tb = await setup(dut)
    for r in range(1, 31, 1 if tb.width <= 16 else 3):
        for ccw in (1, 0):
            got = await check_arc(tb, 3, -2, 3 + r, -2, 3 + r, -2, ccw, full=1)
            assert len(got) == len(arc_steps(0, 0, r, 0, r, 0, ccw, True))
            assert any(dx and dy for dx, dy in got) or r == 1


@cocotb.test()
async def exhaustive_small(dut):
    """Every start with |u|, |v| <= 3 (2 at full width), every end point within half a step, both ways."""
    tb = await setup(dut)
    cx, cy = -1, 2
    span = 3 if tb.width <= 16 else 2
    for u0, v0 in itertools.product(range(-span, span + 1), repeat=2):
        if u0 == v0 == 0:
            continue
        r2 = u0 * u0 + v0 * v0
        ends = [(u, v) for u, v in itertools.product(range(-5, 6), repeat=2) if within_half_step(r2, u * u + v * v)]
        for (u1, v1), ccw in itertools.product(ends, (0, 1)):
            await check_arc(tb, cx, cy, cx + u0, cy + v0, cx + u1, cy + v1, ccw, full=int((u0, v0) == (u1, v1)))


@cocotb.test()
async def random_arcs(dut):
    """Random centres, radii (up to the width's limit) and arcs of up to ~150 steps, tick gaps."""
    rng = seeded_rng(dut, "random_arcs")
    tb = await setup(dut)
    limit = 1 << (tb.width - 3)
    lo, hi = -(1 << (tb.width - 1)), (1 << (tb.width - 1)) - 1
    for n in range(40):
        r = rng.randint(1, min(limit - 1, 40)) if n < 25 else int(2 ** rng.uniform(5, tb.width - 3.6))
        c = [rng.randint(max(lo, -limit), min(hi, limit)) for _ in range(2)]
        t0 = rng.random() * 2 * math.pi
        sweep = rng.uniform(-1, 1) * min(2 * math.pi, 150 / r)
        x0, y0 = c[0] + round(r * math.cos(t0)), c[1] + round(r * math.sin(t0))
        x1, y1 = c[0] + round(r * math.cos(t0 + sweep)), c[1] + round(r * math.sin(t0 + sweep))
        if all(lo <= v <= hi for v in (x0, y0, x1, y1)):
            await check_arc(tb, *c, x0, y0, x1, y1, int(sweep > 0), tick=lambda k: rng.random() < 0.8)


@cocotb.test()
async def bad_commands(dut):
    """Off-circle end, R = 0, out of range: error strobe and no step; end = start: no-op."""
    tb = await setup(dut)
    limit = 1 << (tb.width - 3)
    for cmd in [(0, 0, 5, 0, 0, 6), (0, 0, 5, 0, 2, 2), (4, 4, 4, 4, 4, 4), (0, 0, limit, 0, 0, limit),
                (-limit, 0, 1, 0, -limit, limit + 1), (0, 0, 3, 4, 5, 3)]:
        await check_arc(tb, *cmd, 1)
        assert arc_error(*cmd, tb.width), cmd
    assert not await check_arc(tb, 0, 0, 3, 4, 3, 4, 1, full=0)      # zero length: done, no step
    assert len(await check_arc(tb, 0, 0, 3, 4, 3, 4, 0, full=1)) > 20  # full circle


@cocotb.test()
async def start_while_busy_is_ignored(dut):
    tb = await setup(dut)
    load = {"cx": 0, "cy": 0, "x0": 7, "y0": 0, "x1": -7, "y1": 0, "ccw": 1, "full": 0}
    samples = await start_while_busy(tb, load, {**load, "x1": 0, "y1": -7, "ccw": 0})
    assert [(dx, dy) for dx, dy, _ in moves(samples)] == [(w.dx, w.dy) for w in arc_steps(0, 0, 7, 0, -7, 0, True)]


@cocotb.test()
async def reset_any_cycle(dut):
    tb = await setup(dut)
    # Every cycle of the move: the set-up and the 7 steps.
    await reset_at_any_cycle(tb, {"cx": 1, "cy": 1, "x0": 6, "y0": 1, "x1": 1, "y1": 6, "ccw": 1, "full": 0},
                             arc_setup_cycles(tb.width) + 10)


@pytest.mark.parametrize("width", [8, 32])
def test_circ_arc(sim, width):
    run_cocotb(toplevel="circ_arc", test_module="test_circ_arc", sim=sim,
               parameters={"WIDTH": width}, name=f"circ_arc_w{width}")
