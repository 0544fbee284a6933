# SPDX-License-Identifier: Apache-2.0
"""Multiplexer (SU1571551 mux 12): random data through both inputs."""
import cocotb
import pytest
from cocotb.triggers import Timer
from interp.testing.tbkit import seeded_rng



@cocotb.test()
async def selects(dut):
    width = len(dut.out)
    rng = seeded_rng(dut, "selects")
    for _ in range(200):
        a, b, sel = rng.randrange(1 << width), rng.randrange(1 << width), rng.randint(0, 1)
        dut.in0.value, dut.in1.value, dut.sel.value = a, b, sel
        await Timer(1, unit="ns")
        assert int(dut.out.value) == (b if sel else a), (a, b, sel)


@pytest.mark.parametrize("width", [1, 13])
def test_mux2(sim, width):
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="mux2", test_module="test_mux2", sim=sim,
               parameters={"WIDTH": width}, name=f"mux2_w{width}")
