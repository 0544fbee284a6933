# SPDX-License-Identifier: Apache-2.0
"""Accumulating adder-subtractor (SU1571551 node 19 adder 3, SU1665343 adder 1)."""
import cocotb
import pytest

from interp.models.base import sequence
from interp.models.blocks import AccumAddSub, ones_code, ones_value
from interp.testing.tbkit import TB, scoreboard, seeded_rng

IDLE = {"clear": 0, "load": 0, "load_value": 0, "add": 0, "operand": 0, "cin": 0}


async def setup(dut):
    tb = TB(dut)
    await tb.reset(IDLE)
    width, ones = len(dut.f), bool(int(dut.ONES_COMPLEMENT.value))
    return tb, AccumAddSub(width, ones), width, ones


@cocotb.test()
async def random_operations(dut):
    """Random clear/load/add with carry-in, every cycle against the model."""
    tb, model, width, _ = await setup(dut)
    rng = seeded_rng(dut, "random_operations")
    stim = [{"rst": int(rng.random() < 0.01), "clear": int(rng.random() < 0.02),
             "load": int(rng.random() < 0.05), "load_value": rng.randrange(1 << width),
             "add": int(rng.random() < 0.8), "operand": rng.randrange(1 << width),
             "cin": rng.randint(0, 1)} for _ in range(3000)]
    await scoreboard(tb, model, sequence(stim), context="random")


@cocotb.test()
async def signed_sums(dut):
    """Adding signed codes gives the signed sum, and the sign outputs follow it.

    (No sum is 0: in ones' complement x + (-x) is -0, whose sign bit is set.)"""
    tb, model, width, ones = await setup(dut)
    mask = (1 << width) - 1
    code = (lambda v: ones_code(v, width)) if ones else (lambda v: v & mask)
    value = (lambda c: ones_value(c, width)) if ones else \
        (lambda c: c - (1 << width) if c >> (width - 1) else c)
    operands = [5, -6, -3, 12, -20, 13]
    stim = [{**IDLE, "rst": 0, "load": 1, "load_value": code(2)}]
    stim += [{**IDLE, "rst": 0, "add": 1, "operand": code(v)} for v in operands]
    samples = await scoreboard(tb, model, sequence(stim), context="signed sums")
    running, want = 2, [2]
    for v in operands:
        running += v
        want.append(running)
    assert [value(s["f"]) for s in samples[1:]] == want
    assert [s["negative"] for s in samples[1:]] == [int(v < 0) for v in want]


@pytest.mark.parametrize("ones_complement", [0, 1])
def test_accum_addsub(sim, ones_complement):
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="accum_addsub", test_module="test_accum_addsub", sim=sim,
               parameters={"WIDTH": 8, "ONES_COMPLEMENT": ones_complement},
               name=f"accum_addsub_oc{ones_complement}")
