# SPDX-License-Identifier: Apache-2.0
"""cocotb tests shared by tb/lin_std and tb/lin_accel (line cores taking signed x, y).

A bench module makes a `LinearSuite` for its core and binds the shared tests
into its own namespace, where cocotb finds them; its own hand-worked examples
use the suite's `setup` and `check_move`:

    suite = LinearSuite(LinStd, lin_std_steps, one_axis_and_registers, reset_cycles=14)
    globals().update(suite.tests())
"""
from __future__ import annotations

from typing import Callable

import cocotb

from .testing.corecheck import CoreTB, moves, reset_at_any_cycle, start_while_busy
from .testing.tbkit import seeded_rng

IDLE = {"start": 0, "tick": 0, "x": 0, "y": 0}


class LinearSuite:
    """The shared line tests for one core.

    model(width): its cycle model; steps(x, y): its step-level model;
    check(tb, x, y, samples, got): the core's own assertions on a move;
    reset_cycles: the cycles of the (7, -5) move to reset in."""

    def __init__(self, model: Callable, steps: Callable, check: Callable, reset_cycles: int):
        self.model, self.steps, self.check, self.reset_cycles = model, steps, check, reset_cycles

    async def setup(self, dut) -> CoreTB:
        width = int(dut.WIDTH.value)
        tb = CoreTB(dut, IDLE, lambda: self.model(width))
        tb.width = width
        await tb.reset()
        return tb

    async def check_move(self, tb, x, y, tick=lambda c: 1):
        """Scoreboard one move; steps and F against the equations, then the core's own checks."""
        samples = await tb.run({"x": x, "y": y}, tick, context=f"({x}, {y})")
        got = moves(samples)
        want = self.steps(x, y)
        assert [(dx, dy, s["f"]) for dx, dy, s in got] == [(w.dx, w.dy, w.f) for w in want], f"({x}, {y})"
        assert (sum(dx for dx, _, _ in got), sum(dy for _, dy, _ in got)) == (x, y)
        assert sum(s["done"] for s in samples) == 1
        self.check(tb, x, y, samples, got)
        return samples

    def tests(self) -> dict:
        """The cocotb tests, by name, for the bench module to bind into its namespace."""
        setup, check_move, tests = self.setup, self.check_move, {}

        def _test(func):
            tests[func.__name__] = cocotb.test(name=func.__name__)(func)
            return func

        @_test
        async def exhaustive_small(dut):
            """Every |X|, |Y| <= 10 (5 at full width): all eight octants and their boundaries."""
            tb = await setup(dut)
            span = 10 if tb.width <= 16 else 5          # full width: the random test's job
            for x in range(-span, span + 1):
                for y in range(-span, span + 1):
                    await check_move(tb, x, y)

        @_test
        async def random_moves(dut):
            """Random full-width commands (cut short) and random whole moves with tick gaps."""
            rng = seeded_rng(dut, "random_moves")
            tb = await setup(dut)
            lo, hi = -(1 << (tb.width - 1)), (1 << (tb.width - 1)) - 1
            edges = [lo, lo + 1, -1, 0, 1, hi]
            commands = [(a, b) for a in edges for b in edges]
            commands += [(rng.randint(lo, hi), rng.randint(lo, hi)) for _ in range(20)]
            for x, y in commands:
                await tb.run_cut({"x": x, "y": y}, 60, context=f"full width ({x}, {y})")
            span = min(hi, 200)
            for _ in range(25):
                await check_move(tb, rng.randint(-span, span), rng.randint(-span, span),
                                 tick=lambda c: rng.random() < 0.7)

        @_test
        async def zero_length(dut):
            """X = Y = 0: done with no step."""
            tb = await setup(dut)
            samples = await check_move(tb, 0, 0)
            assert not moves(samples)

        @_test
        async def start_while_busy_is_ignored(dut):
            """start held high with another move during a move changes nothing."""
            tb = await setup(dut)
            samples = await start_while_busy(tb, {"x": 9, "y": -4}, {"x": -20, "y": 20})
            assert [(dx, dy) for dx, dy, _ in moves(samples)] == [(w.dx, w.dy) for w in self.steps(9, -4)]

        @_test
        async def reset_any_cycle(dut):
            """rst in any cycle of a move returns to idle; no step after it."""
            tb = await setup(dut)
            await reset_at_any_cycle(tb, {"x": 7, "y": -5}, self.reset_cycles)

        return tests

