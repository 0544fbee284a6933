# SPDX-License-Identifier: Apache-2.0
"""Sign-analysis node (SU1571551 node 18: AND 5, AND 6): full truth table."""
import itertools

import cocotb
from cocotb.triggers import Timer

from interp.models.blocks import sign_analysis


@cocotb.test()
async def truth_table(dut):
    for tick, enable, negative in itertools.product((0, 1), repeat=3):
        dut.tick.value, dut.enable.value, dut.negative.value = tick, enable, negative
        await Timer(1, unit="ns")
        got = {"pulse_pos": int(dut.pulse_pos.value), "pulse_neg": int(dut.pulse_neg.value)}
        assert got == sign_analysis(tick, enable, negative), (tick, enable, negative, got)


def test_sign_analysis(sim):
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="sign_analysis", test_module="test_sign_analysis", sim=sim)
