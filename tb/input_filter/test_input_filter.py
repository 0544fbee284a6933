# SPDX-License-Identifier: Apache-2.0
"""input_filter: every cycle against a cycle model (seeded random inputs that bounce, the
period and the mask changed on the fly, reset at random cycles); the contract in directed
runs: a change of 4 x period clocks always passes, one of 3 x period clocks never does, and
with period 0 or a clear mask bit the input passes in the same clock."""
import cocotb
from cocotb.triggers import FallingEdge, ReadOnly

from interp.models.base import CycleModel
from interp.simulation.runner import run_cocotb
from interp.testing.tbkit import TB, scoreboard, seeded_rng

N = 5
SAMPLES = 4
IDLE = {"period": 0, "mask": (1 << N) - 1, "raw": 0}


class InputFilter(CycleModel):
    """A sample every `period` clocks; an input takes a new level at the SAMPLES-th sample
    in a row that shows it; period 0 or a clear mask bit: the input passes at once."""

    watch = {"filtered": False}

    def __init__(self):
        self.reset(IDLE)

    def reset(self, i):
        self.inputs = dict(i)
        self.prescale, self.sample_now = 0, 0
        self.level = [i["raw"] >> k & 1 for k in range(N)]
        self.count = [0] * N

    @property
    def filtered(self) -> int:
        i = self.inputs
        if i["period"] == 0:
            return i["raw"]
        return sum((self.level[k] if i["mask"] >> k & 1 else i["raw"] >> k & 1) << k for k in range(N))

    def clock(self, i) -> None:
        if i.get("rst"):
            return self.reset(i)
        off = i["period"] == 0
        sample = self.sample_now
        for k in range(N):
            raw = i["raw"] >> k & 1
            if off or not i["mask"] >> k & 1:
                self.level[k], self.count[k] = raw, 0
            elif sample:
                if raw == self.level[k]:
                    self.count[k] = 0
                elif self.count[k] == SAMPLES - 1:
                    self.level[k], self.count[k] = raw, 0
                else:
                    self.count[k] += 1
        due = not off and self.prescale + 1 >= i["period"]
        self.prescale = 0 if off or due else self.prescale + 1
        self.sample_now = int(due)
        self.inputs = dict(i)


def bouncing(rng, cycles: int):
    """Inputs that hold, bounce or glitch; the period and mask change now and then; rst."""
    i = dict(IDLE, period=3)
    for cycle in range(cycles):
        if rng.random() < 0.002:
            i["period"] = rng.choice([0, 1, 2, 3, 5, 8, rng.randrange(1 << 16)])
        if rng.random() < 0.002:
            i["mask"] = rng.randrange(1 << N)
        if rng.random() < 0.05:
            i["raw"] ^= 1 << rng.randrange(N)            # a change, or a glitch undone soon after
        yield {**i, "rst": int(rng.random() < 0.001)}


@cocotb.test()
async def against_the_model(dut):
    rng = seeded_rng(dut, "against_the_model")
    tb = TB(dut)
    await tb.reset(IDLE)
    model = InputFilter()
    samples = await scoreboard(tb, model, bouncing(rng, 20000), context="input_filter")
    assert len({s["filtered"] for s in samples}) > 8, "the filtered inputs hardly moved"


async def pulse(tb, dut, period: int, mask: int, width: int, gap: int = 200) -> int:
    """A pulse of `width` clocks on every raw input; returns the filtered inputs seen high."""
    seen = 0
    for cycle in range(width + gap):
        tb.drive({"period": period, "mask": mask, "raw": (1 << N) - 1 if cycle < width else 0})
        await ReadOnly()
        seen |= int(dut.filtered.value)
        await FallingEdge(dut.clk)
    return seen


@cocotb.test()
async def glitches_and_changes(dut):
    """At every phase of the prescaler: 3 x period clocks never pass, 4 x period always do,
    after 3 x period + 1 .. 4 x period clocks; unfiltered inputs pass in the same clock."""
    tb = TB(dut)
    for period in (1, 2, 5):
        for phase in range(period):
            await tb.reset({**IDLE, "period": period})
            for _ in range(phase + 7):
                await FallingEdge(dut.clk)
            assert await pulse(tb, dut, period, 0b11111, 3 * period) == 0, (period, phase)
            assert await pulse(tb, dut, period, 0b10110, 3 * period) == 0b01001, (period, phase)
            delay = None
            for cycle in range(4 * period + 20):
                tb.drive({"period": period, "mask": 0b11111, "raw": 0b11111 if cycle < 4 * period else 0})
                await ReadOnly()
                if delay is None and int(dut.filtered.value) == 0b11111:
                    delay = cycle
                await FallingEdge(dut.clk)
            assert delay is not None and 3 * period + 1 <= delay <= 4 * period, (period, phase, delay)
    await tb.reset(IDLE)
    tb.drive({"period": 0, "mask": 0b11111, "raw": 0b10101})
    await ReadOnly()
    assert int(dut.filtered.value) == 0b10101, "period 0: the inputs pass in the same clock"


def test_input_filter(sim):
    run_cocotb(toplevel="input_filter", test_module="test_input_filter", sim=sim,
               parameters={"N": N, "PW": 16}, name="input_filter")
