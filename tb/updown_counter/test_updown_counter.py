# SPDX-License-Identifier: Apache-2.0
"""Up/down counter (SU1571551 ctr 1, 2; SU1665343 CT7, CT8): RTL vs model, every cycle."""
import cocotb
import pytest

from interp.models.base import sequence
from interp.models.blocks import UpDownCounter, ones_code, ones_value
from interp.testing.tbkit import TB, scoreboard, seeded_rng

IDLE = {"load": 0, "load_value": 0, "inc": 0, "dec": 0, "dec2": 0}


async def setup(dut):
    tb = TB(dut)
    await tb.reset(IDLE)
    width, ones = len(dut.q), bool(int(dut.ONES_COMPLEMENT.value))
    return tb, UpDownCounter(width, ones), width, ones


@cocotb.test()
async def random_operations(dut):
    """Random load/inc/dec/dec2 (also simultaneous), wrapping through both ends."""
    tb, model, width, _ = await setup(dut)
    rng = seeded_rng(dut, "random_operations")
    stim = [{"rst": int(rng.random() < 0.01), "load": int(rng.random() < 0.05),
             "load_value": rng.randrange(1 << width), "inc": rng.randint(0, 1),
             "dec": rng.randint(0, 1), "dec2": rng.randint(0, 1)} for _ in range(3000)]
    await scoreboard(tb, model, sequence(stim), context="random")


@cocotb.test()
async def counts_through_zero(dut):
    """Counting down from 3 to -4 and back: the integer meaning follows +-1, -2."""
    tb, model, width, ones = await setup(dut)
    code = (lambda v: ones_code(v, width)) if ones else (lambda v: v & ((1 << width) - 1))
    value = (lambda c: ones_value(c, width)) if ones else \
        (lambda c: c - (1 << width) if c >> (width - 1) else c)
    stim = sequence([{**IDLE, "rst": 0, "load": 1, "load_value": code(3)}]
                    + [{**IDLE, "rst": 0, "dec": 1}] * 7 + [{**IDLE, "rst": 0, "dec2": 1}]
                    + [{**IDLE, "rst": 0, "inc": 1}] * 4 + [{**IDLE, "rst": 0, "dec2": 1, "inc": 1}])
    samples = await scoreboard(tb, model, stim, context="through zero")
    got = [value(s["q"]) for s in samples[1:]]
    assert got == [3, 2, 1, 0, -1, -2, -3, -4, -6, -5, -4, -3, -2, -3], got
    assert all(s["q_n"] == ~s["q"] & ((1 << width) - 1) for s in samples)
    # A reversible counter counting down to zero shows +0 (all outputs low),
    # also in ones' complement (SU1665343 Table 2: CT8 = 2 - 2 enters the adder as +1).
    assert [s["q"] for s in samples[1:5]] == [code(3), code(2), code(1), 0]


@pytest.mark.parametrize("ones_complement", [0, 1])
def test_updown_counter(sim, ones_complement):
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="updown_counter", test_module="test_updown_counter", sim=sim,
               parameters={"WIDTH": 6, "ONES_COMPLEMENT": ones_complement},
               name=f"updown_counter_oc{ones_complement}")
