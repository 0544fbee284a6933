# SPDX-License-Identifier: Apache-2.0
"""Axis order (SU1571551 inputs 22-26, trigger 15's input): |X|, |Y| into L, S and L - S."""
import cocotb
import pytest
from cocotb.triggers import Timer
from interp.testing.tbkit import seeded_rng


@cocotb.test()
async def orders(dut):
    """Edge and random increments, -2^(WIDTH-1) included, against the definition."""
    width = len(dut.x)
    lo, hi = -(1 << (width - 1)), (1 << (width - 1)) - 1
    rng = seeded_rng(dut, "orders")
    edges = [lo, lo + 1, -1, 0, 1, hi - 1, hi]
    pairs = [(a, b) for a in edges for b in edges]
    pairs += [(rng.randint(lo, hi), rng.randint(lo, hi)) for _ in range(300)]
    mask = (1 << width) - 1
    for x, y in pairs:
        dut.x.value, dut.y.value = x & mask, y & mask
        await Timer(1, unit="ns")
        longer, shorter = max(abs(x), abs(y)), min(abs(x), abs(y))
        got = (int(dut.x_is_long.value), int(dut.long_len.value), int(dut.short_len.value),
               int(dut.difference.value))
        assert got == (int(abs(x) >= abs(y)), longer, shorter, longer - shorter), (x, y, got)


@pytest.mark.parametrize("width", [2, 9, 32])
def test_axis_order(sim, width):
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="axis_order", test_module="test_axis_order", sim=sim,
               parameters={"WIDTH": width}, name=f"axis_order_w{width}")
