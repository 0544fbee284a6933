# SPDX-License-Identifier: Apache-2.0
"""Commutator 6 of SU1665343 (2x3 AND/OR elements 37): each channel {v, lsb}, one-hot selects."""
import itertools

import cocotb
import pytest
from cocotb.triggers import Timer

from interp.models.su1665343 import commutator, oc_value
from interp.testing.tbkit import seeded_rng


@cocotb.test()
async def channels(dut):
    """Every select pattern with random data; and the ones'-complement meaning 2v +- 1."""
    width = len(dut.v1)
    rng = seeded_rng(dut, "channels")
    for sel in list(itertools.product((0, 1), repeat=3)) * 40:
        data = [(rng.randrange(1 << width), rng.randint(0, 1)) for _ in range(3)]
        dut.sel1.value, dut.sel2.value, dut.sel3.value = sel
        for k, (v, lsb) in enumerate(data, 1):
            getattr(dut, f"v{k}").value = v
            getattr(dut, f"lsb{k}").value = lsb
        await Timer(1, unit="ns")
        assert int(dut.out.value) == commutator(width, sel, data), (sel, data)
    # {v, 1} = 2v + 1 for v >= 0; {v, 0} = 2v - 1 for v < 0 (the patent's ones' complement)
    dut.sel1.value, dut.sel2.value, dut.sel3.value = 1, 0, 0
    top = (1 << (width - 1)) - 1
    for v in range(-top, top + 1):
        dut.v1.value = v & ((1 << width) - 1) if v >= 0 else ~(-v) & ((1 << width) - 1)
        dut.lsb1.value = int(v >= 0)
        await Timer(1, unit="ns")
        assert oc_value(int(dut.out.value), width + 1) == 2 * v + (1 if v >= 0 else -1), v


@pytest.mark.parametrize("width", [6])
def test_commutator(sim, width):
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="commutator", test_module="test_commutator", sim=sim,
               parameters={"WIDTH": width}, name=f"commutator_w{width}")
