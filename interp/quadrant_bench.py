# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of the lecture's first-quadrant circular interpolator, rtl/circ_quadrant.v
(the CLI's circ-std with ACCEL = 0, circ-accel with ACCEL = 1).

`quadrant_suite()` makes the tests; a bench module binds them into its own
namespace, where cocotb finds them:

    globals().update(quadrant_suite())

The DUT's ACCEL parameter selects the standard or the accelerated equations.
"""
from __future__ import annotations

import itertools

import cocotb

from .testing.corecheck import CoreTB, moves, reset_at_any_cycle, start_while_busy
from .testing.tbkit import seeded_rng
from .models.lecture import CircQuadrant, circ_steps, quadrant_error

IDLE = {"start": 0, "tick": 0, "x0": 0, "y0": 0, "x1": 0, "y1": 0, "ccw": 0}


async def setup(dut):
    width, accel = int(dut.WIDTH.value), bool(int(dut.ACCEL.value))
    tb = CoreTB(dut, IDLE, lambda: CircQuadrant(width, accel))
    tb.width, tb.accel = width, accel
    await tb.reset()
    return tb


async def check_arc(tb, x0, y0, x1, y1, ccw, tick=lambda c: 1):
    """Scoreboard one command; steps and F against the equations, or the error strobe."""
    load = {"x0": x0, "y0": y0, "x1": x1, "y1": y1, "ccw": ccw}
    samples = await tb.run(load, tick, context=str(load))
    got = moves(samples)
    reason = quadrant_error(x0, y0, x1, y1, ccw)
    if reason:
        assert not got and sum(s["error"] for s in samples) == 1 and not any(s["done"] for s in samples), \
            f"{load}: {reason}"
        return samples
    want = circ_steps(x0, y0, x1, y1, ccw, tb.accel)
    assert [(dx, dy, s["f"]) for dx, dy, s in got] == [(w.dx, w.dy, w.f) for w in want], str(load)
    assert sum(s["done"] for s in samples) == 1 and not any(s["error"] for s in samples)
    if not tb.accel:
        assert all(not (dx and dy) for dx, dy, _ in got)
    return samples


def quadrant_suite() -> dict:
    """The cocotb tests, by name, for a bench module to bind into its namespace."""
    tests = {}

    def _test(func):
        tests[func.__name__] = cocotb.test(name=func.__name__)(func)
        return func

    @_test
    async def lecture_example(dut):
        """R = 5 from (5, 0) to (0, 5) and back: F = x^2 + y^2 - 25 after every step."""
        tb = await setup(dut)
        for ccw, (x0, y0, x1, y1) in ((1, (5, 0, 0, 5)), (0, (0, 5, 5, 0)), (1, (4, 3, 3, 4))):
            samples = await check_arc(tb, x0, y0, x1, y1, ccw)
            x, y = x0, y0
            for dx, dy, s in moves(samples):
                x, y = x + dx, y + dy
                assert s["f"] == x * x + y * y - (x0 * x0 + y0 * y0)
            assert (x, y) == (x1, y1)

    @_test
    async def exhaustive_small(dut):
        """Every start and end point with coordinates 0 .. 5, both directions (bad ones too)."""
        tb = await setup(dut)
        for x0, y0, x1, y1 in itertools.product(range(6), repeat=4):
            for ccw in (0, 1):
                await check_arc(tb, x0, y0, x1, y1, ccw)

    @_test
    async def quarter_circles(dut):
        """Whole quarter circles R = 1 .. 30 both ways, random arcs with tick gaps, full-width radii."""
        rng = seeded_rng(dut, "quarter_circles")
        tb = await setup(dut)
        for r in range(1, 31):
            await check_arc(tb, r, 0, 0, r, 1)
            await check_arc(tb, 0, r, r, 0, 0)
        hi = (1 << (tb.width - 1)) - 1
        for _ in range(20):
            r = rng.randint(2, min(hi, 300))
            a, b = sorted(rng.sample(range(0, r + 1), 2))
            x0, x1 = b, a
            y0, y1 = round((r * r - x0 * x0) ** 0.5), round((r * r - x1 * x1) ** 0.5)
            x0, y0 = (x0, y0) if x0 * x0 + y0 * y0 else (r, 0)
            await check_arc(tb, x0, y0, x1, y1, 1, tick=lambda c: rng.random() < 0.7)
            await check_arc(tb, x1, y1, x0, y0, 0)
        for _ in range(6):                         # full-width coordinates: squares near 2^(2 WIDTH - 2)
            r = rng.randint(hi // 2, hi)
            y1 = rng.randint(1, min(hi, 120))
            if quadrant_error(r, 0, r, y1, True) is None:
                await check_arc(tb, r, 0, r, y1, 1)
                await check_arc(tb, r, y1, r, 0, 0)

    @_test
    async def bad_commands(dut):
        """Off-circle end, R = 0, wrong direction, negative coordinates: error strobe, no step."""
        tb = await setup(dut)
        lo = -(1 << (tb.width - 1))
        for cmd in [(5, 0, 0, 6, 1), (5, 0, 1, 3, 1), (0, 0, 0, 0, 1), (0, 5, 5, 0, 1), (5, 0, 0, 5, 0),
                    (-5, 0, 0, 5, 1), (5, 0, 0, -5, 0), (lo, 0, 0, lo, 1)]:
            samples = await check_arc(tb, *cmd)
            assert sum(s["error"] for s in samples) == 1, cmd
        samples = await check_arc(tb, 3, 4, 3, 4, 1)               # zero length: done, no step
        assert not moves(samples) and sum(s["done"] for s in samples) == 1

    @_test
    async def start_while_busy_is_ignored(dut):
        tb = await setup(dut)
        load = {"x0": 10, "y0": 0, "x1": 6, "y1": 8, "ccw": 1}
        samples = await start_while_busy(tb, load, {"x0": 0, "y0": 10, "x1": 10, "y1": 0, "ccw": 0})
        assert [(dx, dy) for dx, dy, _ in moves(samples)] == \
            [(w.dx, w.dy) for w in circ_steps(10, 0, 6, 8, True, tb.accel)]

    @_test
    async def reset_any_cycle(dut):
        tb = await setup(dut)
        # Every cycle of the move: the set-up (check in cycle 2 * WIDTH + 17) and the steps.
        await reset_at_any_cycle(tb, {"x0": 5, "y0": 0, "x1": 3, "y1": 4, "ccw": 1}, 2 * tb.width + 24)

    return tests
