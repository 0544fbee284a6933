"""cocotb tests shared by tb/lin_std and tb/lin_accel (line cores taking signed x, y).

A test module calls `configure(model, steps, check)` and imports the tests
with `from interp.linear_bench import *`; its own hand-worked examples use
`setup` and `check_move` from here.
"""
from __future__ import annotations

import cocotb

from .testing.corecheck import CoreTB, moves, reset_at_any_cycle, start_while_busy
from .testing.tbkit import seeded_rng

IDLE = {"start": 0, "tick": 0, "x": 0, "y": 0}
CORE: dict = {}


def configure(model, steps, check, reset_cycles: int) -> None:
    """model(width): cycle model; steps(x, y): step-level model; check(tb, x, y, samples, got):
    the core's own assertions; reset_cycles: cycles of the (7, -5) move to reset in."""
    CORE.update(model=model, steps=steps, check=check, reset_cycles=reset_cycles)


async def setup(dut):
    width = int(dut.WIDTH.value)
    tb = CoreTB(dut, IDLE, lambda: CORE["model"](width))
    tb.width = width
    await tb.reset()
    return tb


async def check_move(tb, x, y, tick=lambda c: 1):
    """Scoreboard one move; steps and F against the equations, then the core's own checks."""
    samples = await tb.run({"x": x, "y": y}, tick, context=f"({x}, {y})")
    got = moves(samples)
    want = CORE["steps"](x, y)
    assert [(dx, dy, s["f"]) for dx, dy, s in got] == [(w.dx, w.dy, w.f) for w in want], f"({x}, {y})"
    assert (sum(dx for dx, _, _ in got), sum(dy for _, dy, _ in got)) == (x, y)
    assert sum(s["done"] for s in samples) == 1
    CORE["check"](tb, x, y, samples, got)
    return samples


@cocotb.test()
async def exhaustive_small(dut):
    """Every |X|, |Y| <= 10 (5 at full width): all eight octants and their boundaries."""
    tb = await setup(dut)
    span = 10 if tb.width <= 16 else 5          # full width: the random test's job
    for x in range(-span, span + 1):
        for y in range(-span, span + 1):
            await check_move(tb, x, y)


@cocotb.test()
async def random_moves(dut):
    """Random full-width commands (cut short) and random whole moves with tick gaps."""
    rng = seeded_rng(dut, "random_moves")
    tb = await setup(dut)
    lo, hi = -(1 << (tb.width - 1)), (1 << (tb.width - 1)) - 1
    edges = [lo, lo + 1, -1, 0, 1, hi]
    for x, y in [(a, b) for a in edges for b in edges] + [(rng.randint(lo, hi), rng.randint(lo, hi)) for _ in range(20)]:
        await tb.run_cut({"x": x, "y": y}, 60, context=f"full width ({x}, {y})")
    span = min(hi, 200)
    for _ in range(25):
        await check_move(tb, rng.randint(-span, span), rng.randint(-span, span), tick=lambda c: rng.random() < 0.7)


@cocotb.test()
async def zero_length(dut):
    """X = Y = 0: done with no step."""
    tb = await setup(dut)
    samples = await check_move(tb, 0, 0)
    assert not moves(samples)


@cocotb.test()
async def start_while_busy_is_ignored(dut):
    tb = await setup(dut)
    samples = await start_while_busy(tb, {"x": 9, "y": -4}, {"x": -20, "y": 20})
    assert [(dx, dy) for dx, dy, _ in moves(samples)] == [(w.dx, w.dy) for w in CORE["steps"](9, -4)]


@cocotb.test()
async def reset_any_cycle(dut):
    tb = await setup(dut)
    await reset_at_any_cycle(tb, {"x": 7, "y": -5}, CORE["reset_cycles"])
