# SPDX-License-Identifier: Apache-2.0
"""Gradient unit: value = c + a·x + b·y tracked by adders, checked against the product form
(value, next value, their magnitudes, overflow)."""
import cocotb
import pytest
from cocotb.triggers import FallingEdge

from interp.models.curve import fits, wrap
from interp.testing.tbkit import TB, seeded_rng
from interp.simulation.runner import run_cocotb


IDLE = dict(load=0, load_value=0, coef_a_in=0, coef_b_in=0, step_a=0, neg_a=0, step_b=0,
            neg_b=0, advance=0)


async def setup(dut):
    tb = TB(dut)
    await tb.reset(IDLE)
    return tb, IDLE


@cocotb.test()
async def random_walks(dut):
    """Random walks from random loads: value, next_value and overflow every cycle."""
    w = int(dut.WIDTH.value)
    rng = seeded_rng(dut, "random_walks")
    tb, idle = await setup(dut)
    lo, hi = -(1 << (w - 1)), (1 << (w - 1)) - 1
    for _ in range(200):
        c, a, b = (rng.randint(lo, hi) for _ in range(3))
        if rng.random() < 0.7:
            a, b = wrap(rng.randint(-9, 9), w), wrap(rng.randint(-9, 9), w)
        tb.drive({**idle, "load": 1, "load_value": c, "coef_a_in": a, "coef_b_in": b})
        await FallingEdge(dut.clk)
        x = y = 0
        for _ in range(30):
            sa, sb, na, nb = (rng.randint(0, 1) for _ in range(4))
            dx, dy = sa * (-1 if na else 1), sb * (-1 if nb else 1)
            want = c + a * (x + dx) + b * (y + dy)
            tb.drive({**idle, "step_a": sa, "neg_a": na, "step_b": sb, "neg_b": nb, "advance": 0})
            await FallingEdge(dut.clk)   # settle the combinational outputs
            assert dut.value.value.to_signed() == c + a * x + b * y
            assert int(dut.magnitude.value) == abs(c + a * x + b * y)
            assert int(dut.overflow.value) == int(not fits(want, w)), (c, a, b, x, y, dx, dy)
            assert dut.next_value.value.to_signed() == wrap(want, w)
            if fits(want, w):
                assert int(dut.next_magnitude.value) == abs(want), (c, a, b, x, y, dx, dy)
            if not fits(want, w):
                break
            tb.drive({"advance": 1})
            await FallingEdge(dut.clk)
            x, y = x + dx, y + dy
        tb.drive({"advance": 0})


@cocotb.test()
async def advance_past_overflow(dut):
    """`advance` on an overflowing step stores the wrapped value; -v follows it."""
    w = int(dut.WIDTH.value)
    rng = seeded_rng(dut, "advance_past_overflow")
    tb, idle = await setup(dut)
    lo, hi = -(1 << (w - 1)), (1 << (w - 1)) - 1
    for _ in range(100):
        v, a, b = (rng.randint(lo, hi) for _ in range(3))
        tb.drive({**idle, "load": 1, "load_value": wrap(v, w), "coef_a_in": wrap(a, w),
                  "coef_b_in": wrap(b, w)})
        await FallingEdge(dut.clk)
        for _ in range(6):
            sa, sb, na, nb = (rng.randint(0, 1) for _ in range(4))
            want = v + sa * (-a if na else a) + sb * (-b if nb else b)
            tb.drive({**idle, "step_a": sa, "neg_a": na, "step_b": sb, "neg_b": nb, "advance": 1})
            await FallingEdge(dut.clk)
            v = wrap(want, w)
            assert dut.value.value.to_signed() == v
            assert int(dut.magnitude.value) == abs(v)
        tb.drive({"advance": 0})


@pytest.mark.parametrize("width", [3, 24])
def test_gradient_unit(sim, width):
    run_cocotb(toplevel="gradient_unit", test_module="test_gradient_unit", sim=sim,
               parameters={"WIDTH": width}, name=f"gradient_unit_w{width}")
