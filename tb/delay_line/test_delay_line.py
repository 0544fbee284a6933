# SPDX-License-Identifier: Apache-2.0
"""Delay element (SU1665343 delay elements 12, 13, 14, 19, 26): RTL vs model, every cycle."""
import cocotb
import pytest

from interp.models.base import sequence
from interp.models.su1665343 import DelayLine
from interp.testing.tbkit import TB, scoreboard, seeded_rng


@cocotb.test()
async def taps_follow_input(dut):
    """A single pulse walks through every tap; then random d/clear/rst."""
    tb = TB(dut)
    await tb.reset({"d": 0, "clear": 0})
    length = int(dut.LENGTH.value)
    pulse = [{"rst": 0, "clear": 0, "d": 1}] + [{"rst": 0, "clear": 0, "d": 0}] * (length + 1)
    samples = await scoreboard(tb, DelayLine(length), sequence(pulse), context="pulse")
    assert [s["taps"] for s in samples[1:length + 2]] == [1 << i for i in range(length)] + [0]
    rng = seeded_rng(dut, "taps_follow_input")
    stim = [{"rst": int(rng.random() < 0.03), "clear": int(rng.random() < 0.05),
             "d": rng.randint(0, 1)} for _ in range(1000)]
    await scoreboard(tb, DelayLine(length), sequence([{"rst": 1, "clear": 0, "d": 0}] + stim),
                     context="random")


@pytest.mark.parametrize("length", [1, 4])
def test_delay_line(sim, length):
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="delay_line", test_module="test_delay_line", sim=sim,
               parameters={"LENGTH": length}, name=f"delay_line_l{length}")
