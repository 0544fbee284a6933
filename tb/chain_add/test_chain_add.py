# SPDX-License-Identifier: Apache-2.0
"""Adder with carry in and out, the portable form: {cout, sum} = a + b + cin, or
a + ~b + cin (SUBTRACT = 1).  The iCE40 form (rtl/ice40/chain_add.v, carry select) is
proved equivalent to this one by `make formal` (formal/arc_leaves.sby)."""
import cocotb
import pytest
from cocotb.triggers import Timer

from interp.simulation.runner import run_cocotb
from interp.testing.tbkit import seeded_rng


@cocotb.test()
async def sums(dut):
    """Edge and random operands and carries in: sum and carry out every time."""
    width, subtract = len(dut.sum), bool(int(dut.SUBTRACT.value))
    mask, rng = (1 << width) - 1, seeded_rng(dut, "sums")
    edges = [0, 1, mask, mask - 1, 1 << (width - 1), mask >> 1]
    cases = [(a, b, c) for a in edges for b in edges for c in (0, 1)]
    cases += [(rng.randrange(1 << width), rng.randrange(1 << width), rng.randrange(2)) for _ in range(3000)]
    for a, b, cin in cases:
        dut.a.value, dut.b.value, dut.cin.value = a, b, cin
        await Timer(1, unit="ns")
        total = a + ((~b & mask) if subtract else b) + cin
        got = (int(dut.cout.value), int(dut.sum.value))
        assert got == (total >> width, total & mask), (hex(a), hex(b), cin, got)


@pytest.mark.parametrize("width,subtract", [(1, 0), (1, 1), (6, 0), (6, 1), (33, 0), (31, 1)])
def test_chain_add(sim, width, subtract):
    run_cocotb(toplevel="chain_add", test_module="test_chain_add", sim=sim,
               parameters={"WIDTH": width, "SUBTRACT": subtract}, name=f"chain_add_w{width}_s{subtract}")
