# SPDX-License-Identifier: Apache-2.0
"""Adder with an operand select (the arc core's loop adders), the portable form:
sum = x + y, y = sel ? c : d, x = a (LOAD = 0) or sel ? 0 : a (LOAD = 1).

The family forms (rtl/ecp5/mux_add.v in carry cells, rtl/ice40/mux_add.v with carry
select) are proved equivalent to this one by `make formal` (formal/arc_leaves.sby)."""
import cocotb
import pytest
from cocotb.triggers import Timer

from interp.simulation.runner import run_cocotb
from interp.testing.tbkit import seeded_rng


def expected(a: int, sel: int, c: int, d: int, load: bool, width: int) -> int:
    mask = (1 << width) - 1
    x = 0 if load and sel else a
    y = c if sel else d
    return (x + y) & mask


@cocotb.test()
async def sums(dut):
    """Edge and random operands and selects, the sum every time."""
    width, load = len(dut.sum), bool(int(dut.LOAD.value))
    mask, rng = (1 << width) - 1, seeded_rng(dut, "sums")
    edges = [0, 1, mask, mask - 1, 1 << (width - 1), mask >> 1]
    cases = [(a, s, c, d) for a in edges for s in (0, 1) for c in edges[:3] for d in edges[:3]]
    cases += [(rng.randrange(1 << width), rng.randrange(2), rng.randrange(1 << width), rng.randrange(1 << width))
              for _ in range(3000)]
    for a, s, c, d in cases:
        dut.a.value, dut.sel.value, dut.c.value, dut.d.value = a, s, c, d
        await Timer(1, unit="ns")
        assert int(dut.sum.value) == expected(a, s, c, d, load, width), (hex(a), s, hex(c), hex(d))


@pytest.mark.parametrize("width,load", [(1, 0), (1, 1), (7, 1), (7, 0), (34, 0), (33, 1)])
def test_mux_add(sim, width, load):
    run_cocotb(toplevel="mux_add", test_module="test_mux_add", sim=sim,
               parameters={"WIDTH": width, "LOAD": load}, name=f"mux_add_w{width}_l{load}")
