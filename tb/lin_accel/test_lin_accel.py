"""Lecture's accelerated linear interpolator: RTL vs cycle model vs the lecture's equations."""
import cocotb
import pytest

from interp.corecheck import CoreTB, moves, reset_at_any_cycle, start_while_busy
from interp.tbkit import seeded_rng
from interp.models.lecture import LinAccel, lin_accel_steps
from interp.sim import run_cocotb

IDLE = {"start": 0, "tick": 0, "x": 0, "y": 0}


async def setup(dut):
    width = int(dut.WIDTH.value)
    tb = CoreTB(dut, IDLE, lambda: LinAccel(width))
    tb.width = width
    await tb.reset()
    return tb


async def check_move(tb, x, y, tick=lambda c: 1):
    """Scoreboard one move; steps and F against the equations; one step per tick."""
    samples = await tb.run({"x": x, "y": y}, tick, context=f"({x}, {y})")
    got = moves(samples)
    want = lin_accel_steps(x, y)
    assert [(dx, dy, s["f"]) for dx, dy, s in got] == [(w.dx, w.dy, w.f) for w in want], f"({x}, {y})"
    assert (sum(dx for dx, _, _ in got), sum(dy for _, dy, _ in got)) == (x, y)
    assert len(got) == max(abs(x), abs(y)), "one step per tick along the leading axis"
    return samples


@cocotb.test()
async def lecture_example(dut):
    """dX = 5, dY = 3 worked by hand from the lecture's rules: X D D X D, F -3 -1 1 -2 0."""
    tb = await setup(dut)
    samples = await check_move(tb, 5, 3)
    assert [(dx, dy) for dx, dy, _ in moves(samples)] == [(1, 0), (1, 1), (1, 1), (1, 0), (1, 1)]
    assert [s["f"] for _, _, s in moves(samples)] == [-3, -1, 1, -2, 0]
    samples = await check_move(tb, -4, -4)                   # 45 degrees: all diagonal
    assert [(dx, dy) for dx, dy, _ in moves(samples)] == [(-1, -1)] * 4


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
    assert not moves(samples) and sum(s["done"] for s in samples) == 1


@cocotb.test()
async def start_while_busy_is_ignored(dut):
    tb = await setup(dut)
    samples = await start_while_busy(tb, {"x": 9, "y": -4}, {"x": -20, "y": 20})
    assert [(dx, dy) for dx, dy, _ in moves(samples)] == [(w.dx, w.dy) for w in lin_accel_steps(9, -4)]


@cocotb.test()
async def reset_any_cycle(dut):
    tb = await setup(dut)
    await reset_at_any_cycle(tb, {"x": -7, "y": 5}, 10)


@pytest.mark.parametrize("width", [8, 32])
def test_lin_accel(sim, width):
    run_cocotb(toplevel="lin_accel", test_module="test_lin_accel", sim=sim,
               parameters={"WIDTH": width}, name=f"lin_accel_w{width}")
