# SPDX-License-Identifier: Apache-2.0
"""Sequential signed multiplier: RTL vs cycle model every cycle, products vs Python's a * b."""
import cocotb
import pytest

from interp.models.base import sequence
from interp.models.blocks import SeqMult
from interp.testing.tbkit import TB, scoreboard, seeded_rng

IDLE = {"start": 0, "a": 0, "b": 0}


def signed(value: int, width: int) -> int:
    value &= (1 << width) - 1
    return value - ((value >> (width - 1)) << width)


async def setup(dut):
    tb = TB(dut)
    await tb.reset(IDLE)
    return tb, int(dut.WIDTH.value)


def products(samples, stim, width):
    """(a, b, product) for every product the samples show with `done`."""
    out, pending = [], None
    for n, inputs in enumerate(stim):
        if inputs.get("rst"):
            pending = None
        elif inputs["start"] and not samples[n]["busy"]:
            pending = (signed(inputs["a"], width), signed(inputs["b"], width))
        if samples[n + 1]["done"] and pending:
            out.append((*pending, signed(samples[n + 1]["product"], 2 * width)))
    return out


@cocotb.test()
async def corner_products(dut):
    """All sign and extreme combinations, back to back (start in the `done` cycle)."""
    tb, width = await setup(dut)
    lo, hi = -(1 << (width - 1)), (1 << (width - 1)) - 1
    values = sorted({lo, lo + 1, -1, 0, 1, hi - 1, hi})
    stim = []
    for a in values:
        for b in values:
            stim += [{"rst": 0, "start": 1, "a": a & ((1 << width) - 1), "b": b & ((1 << width) - 1)}]
            stim += [{**IDLE, "rst": 0}] * (width + 2)     # the next start meets `done`
    stim += [{**IDLE, "rst": 0}] * (width + 4)
    samples = await scoreboard(tb, SeqMult(width), sequence(stim), context="corners")
    got = products(samples, stim, width)
    assert len(got) == len(values) ** 2
    assert all(p == a * b for a, b, p in got), [g for g in got if g[2] != g[0] * g[1]]


@cocotb.test()
async def random_products(dut):
    """Random operands and start pulses (many while busy, ignored), rare resets."""
    tb, width = await setup(dut)
    rng = seeded_rng(dut, "random_products")
    stim = [{"rst": int(rng.random() < 0.004), "start": int(rng.random() < 0.3),
             "a": rng.randrange(1 << width), "b": rng.randrange(1 << width)} for _ in range(4000)]
    samples = await scoreboard(tb, SeqMult(width), sequence(stim), context="random")
    got = products(samples, stim, width)
    assert len(got) > 4000 // (width + 16)
    assert all(p == a * b for a, b, p in got), [g for g in got if g[2] != g[0] * g[1]]
    busy = [s["busy"] for s in samples]
    assert max(len(run) for run in "".join(map(str, busy)).split("0")) == width + 2


@pytest.mark.parametrize("width", [3, 5, 16, 33])
def test_seq_mult(sim, width):
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="seq_mult", test_module="test_seq_mult", sim=sim,
               parameters={"WIDTH": width}, name=f"seq_mult_w{width}")
