# SPDX-License-Identifier: Apache-2.0
"""Coordinate-increment former (SU1571551 node 20: AND 7, 8, OR 10, 11): truth table."""
import itertools

import cocotb
from cocotb.triggers import Timer

from interp.models.blocks import increment_former


@cocotb.test()
async def truth_table(dut):
    for axial, diagonal, x_is_long in itertools.product((0, 1), repeat=3):
        dut.axial.value, dut.diagonal.value, dut.x_is_long.value = axial, diagonal, x_is_long
        await Timer(1, unit="ns")
        got = {"inc_x": int(dut.inc_x.value), "inc_y": int(dut.inc_y.value)}
        assert got == increment_former(axial, diagonal, x_is_long), (axial, diagonal, x_is_long, got)


def test_increment_former(sim):
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="increment_former", test_module="test_increment_former", sim=sim)
