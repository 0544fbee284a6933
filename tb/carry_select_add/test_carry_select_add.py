# SPDX-License-Identifier: Apache-2.0
"""carry_select_add (lin_exact's step-loop adders): a + b mod 2^WIDTH, in both forms:
the portable one (rtl/carry_select_add.v, one carry chain) and the iCE40 one
(rtl/ice40/carry_select_add.v, carry select)."""
import cocotb
import pytest
from cocotb.triggers import Timer
from interp.testing.tbkit import seeded_rng


@cocotb.test()
async def adds(dut):
    """Random and carry-edge operands; the sum must equal a + b modulo 2^WIDTH."""
    width = len(dut.sum)
    lo = int(dut.LOW.value) or (1 if width < 5 else width * 2 // 5)
    mask, rng = (1 << width) - 1, seeded_rng(dut, "adds")
    edges = [0, 1, mask, mask - 1, (1 << lo) - 1, 1 << lo, (1 << (width - 1)) - 1, 1 << (width - 1)]
    pairs = [(a, b) for a in edges for b in edges]
    pairs += [(rng.randrange(1 << width), rng.randrange(1 << width)) for _ in range(300)]
    for a, b in pairs:
        dut.a.value, dut.b.value = a, b
        dut.b_high_plus1.value = ((b >> lo) + 1) % (1 << (width - lo))
        await Timer(1, unit="ns")
        assert int(dut.sum.value) == (a + b) & mask, (a, b)


@pytest.mark.parametrize("width, low", [(2, None), (7, None), (34, None), (34, 17)])
@pytest.mark.parametrize("family", [None, "ice40"])
def test_carry_select_add(sim, width, low, family):
    from interp.flows import synth
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="carry_select_add", test_module="test_carry_select_add", sim=sim,
               parameters={"WIDTH": width, **({"LOW": low} if low else {})},
               name=f"carry_select_add_w{width}_l{low or 'default'}_{family or 'portable'}",
               sources=synth.sources("carry_select_add", family))
