"""circle_band: the integer half-step test against |sqrt(b) - sqrt(a)| <= 1/2."""
import math
from decimal import Decimal, localcontext

import cocotb
import pytest
from cocotb.triggers import Timer

from interp.testing.tbkit import seeded_rng
from interp.models.lecture import within_half_step
from interp.simulation.runner import run_cocotb


def exact(a: int, b: int) -> bool:
    """The definition with 60-digit square roots (no integer pair sits exactly on 1/2)."""
    with localcontext() as ctx:
        ctx.prec = 60
        return abs(Decimal(b).sqrt() - Decimal(a).sqrt()) <= Decimal("0.5")


async def check(dut, a, b):
    dut.a.value, dut.b.value = a, b
    await Timer(1, unit="ns")
    want = exact(a, b)
    assert within_half_step(a, b) == want, f"model ({a}, {b})"
    assert int(dut.on_band.value) == want, f"rtl a={a} b={b}: {int(dut.on_band.value)}, want {want}"


@cocotb.test()
async def exhaustive_small(dut):
    """Every a <= 120 against every b <= 250 (radii up to ~15.8)."""
    for a in range(121):
        for b in range(251):
            await check(dut, a, b)


@cocotb.test()
async def random_full_width(dut):
    """Random pairs over the whole width, most of them near the band's edges."""
    rng = seeded_rng(dut, "random_full_width")
    top = (1 << int(dut.AW.value)) - 1
    for _ in range(3000):
        a = rng.randint(0, top)
        r = math.isqrt(a)
        edge = (r + rng.choice([-1, 1]) * 0.5) ** 2
        b = min(top, max(0, int(edge) + rng.randint(-2, 2))) if rng.random() < 0.8 else rng.randint(0, top)
        await check(dut, a, b)
    for a, b in [(top, top), (top, 0), (0, top), (top, top - 1)]:
        await check(dut, a, b)


@pytest.mark.parametrize("aw", [24])
def test_circle_band(sim, aw):
    run_cocotb(toplevel="circle_band", test_module="test_circle_band", sim=sim,
               parameters={"AW": aw}, name=f"circle_band_aw{aw}")
