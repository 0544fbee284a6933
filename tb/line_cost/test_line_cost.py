# SPDX-License-Identifier: Apache-2.0
"""line_cost: seeded random lines (small moves like a CAM program's, full-width ones, the
extremes -2^(W-1) and 2^(W-1) - 1, zero axes, an axis of the step events that is not the
largest, and |axis| = 0) against the host's model (interp.link.records.derived_cost, which
the closed form round(2^FRAC sqrt(x^2 + y^2 + z^2) / |axis|) checks where |axis| is the
largest); `done` strobes exactly CLOCKS = 4 W + FRAC + 6 clocks after `start` and never
otherwise; a reset mid-run, and a start again mid-run, leave no stale strobe."""
import math

import cocotb
from cocotb.triggers import FallingEdge, ReadOnly

from interp.link import records
from interp.simulation import motion_build
from interp.simulation.runner import run_cocotb
from interp.testing.tbkit import TB, seeded_rng

IDLE = {"start": 0, "x": 0, "y": 0, "z": 0, "axis": 1}
AXES = {1: "x", 2: "y", 3: "z"}


def build_of(dut) -> records.Build:
    return records.Build(**{k: int(getattr(dut, k).value) for k in ("W", "FEED_W", "FRAC")})


def random_line(rng, w):
    """(x, y, z): small, full-width or extreme values, zeros among them."""
    top = 1 << (w - 1)

    def value():
        how = rng.random()
        if how < 0.15:
            return 0
        if how < 0.25:
            return rng.choice((-top, top - 1, -1, 1))
        if how < 0.6:
            return rng.randint(-300, 300)
        return rng.randint(-top, top - 1)
    return value(), value(), value()


async def run_line(tb, line, axis, clocks, reset_at=None, restart_at=None):
    """Start one line; the cost at its `done` (None after a reset at `reset_at` clocks), the
    clocks from start to done checked; a start again at `restart_at` starts it over."""
    dut = tb.dut
    x, y, z = line
    w = len(dut.x)
    tb.drive({"start": 1, "x": x & ((1 << w) - 1), "y": y & ((1 << w) - 1), "z": z & ((1 << w) - 1), "axis": axis})
    started = 0
    for clock in range(1, 2 * clocks + 10):
        await FallingEdge(dut.clk)
        tb.drive({"start": int(clock == restart_at), "rst": int(clock == reset_at)})
        if clock == restart_at:
            started = clock
        await ReadOnly()
        if int(dut.done.value):
            assert reset_at is None or clock <= reset_at, "done after a reset"
            assert clock - started == clocks, f"done {clock - started} clocks after start, want {clocks}"
            await FallingEdge(dut.clk)
            tb.drive({"rst": 0})
            return int(dut.cost.value)
    await FallingEdge(dut.clk)
    tb.drive({"rst": 0})
    assert reset_at is not None, f"no done in {2 * clocks + 10} clocks"
    return None


@cocotb.test()
async def random_lines(dut):
    rng = seeded_rng(dut, "random_lines")
    b = build_of(dut)
    clocks = 4 * b.W + b.FRAC + 6
    assert clocks + 1 == records.cost_clocks(b)
    tb = TB(dut)
    await tb.reset(IDLE)
    checked = closed = 0
    for n in range(60):
        line = random_line(rng, b.W)
        sizes = [abs(v) for v in line]
        axis = 1 + sizes.index(max(sizes)) if rng.random() < 0.7 else rng.randint(1, 3)
        reset_at = rng.randrange(1, clocks) if n % 15 == 7 else None
        restart_at = rng.randrange(1, clocks) if n % 15 == 11 else None
        got = await run_line(tb, line, axis, clocks, reset_at, restart_at)
        if reset_at is not None:
            assert got is None
            continue
        want = records.derived_cost(*line, AXES[axis], b)
        assert got == want, f"line {line} axis {AXES[axis]}: cost {got}, want {want}"
        checked += 1
        if sizes[axis - 1] == max(sizes) > 0:          # the closed form (exact: isqrt)
            s = sum(v * v for v in line)
            assert want == ((math.isqrt(s << (2 * b.FRAC + 2)) // max(sizes) + 1) >> 1) % (1 << b.FEED_W)
            closed += 1
        if sizes[axis - 1] == 0:                          # all W + FRAC + 1 quotient bits one
            assert got == (1 << (b.W + b.FRAC)) % (1 << b.FEED_W)
    assert checked > 40 and closed > 20, f"{checked} lines checked, {closed} against the closed form"


def test_line_cost(sim):
    p = motion_build.PARAMETERS
    for params in ({}, {k: p[k] for k in ("W", "FEED_W", "FRAC")}):
        run_cocotb(toplevel="line_cost", test_module="test_line_cost", sim=sim, parameters=params, name="line_cost")
