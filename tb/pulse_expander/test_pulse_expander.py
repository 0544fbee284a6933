# SPDX-License-Identifier: Apache-2.0
"""Pulse expander (SU1665343 expander 25): RTL vs model, every cycle."""
import cocotb
import pytest

from interp.models.base import sequence
from interp.models.su1665343 import PulseExpander
from interp.testing.tbkit import TB, scoreboard, seeded_rng


@cocotb.test()
async def holds_for_length(dut):
    """One trigger: active for exactly LENGTH cycles; then random trigger/clear/rst."""
    tb = TB(dut)
    await tb.reset({"trigger": 0, "clear": 0})
    length = int(dut.LENGTH.value)
    idle = {"rst": 0, "clear": 0, "trigger": 0}
    stim = [{**idle, "trigger": 1}] + [idle] * (length + 3)
    samples = await scoreboard(tb, PulseExpander(length), sequence(stim), context="one trigger")
    assert [s["active"] for s in samples] == [0] + [1] * length + [0] * 4
    rng = seeded_rng(dut, "holds_for_length")
    stim = [{"rst": int(rng.random() < 0.02), "clear": int(rng.random() < 0.03),
             "trigger": int(rng.random() < 0.15)} for _ in range(1000)]
    await scoreboard(tb, PulseExpander(length), sequence([{**idle, "rst": 1}] + stim), context="random")


@pytest.mark.parametrize("length", [4])
def test_pulse_expander(sim, length):
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="pulse_expander", test_module="test_pulse_expander", sim=sim,
               parameters={"LENGTH": length}, name=f"pulse_expander_l{length}")
