# SPDX-License-Identifier: Apache-2.0
"""sync_fifo: RTL vs cycle model every cycle, both read forms (HEAD_REG 0 and 1); order, no
loss, overflow refused."""

import cocotb
import pytest

from interp.models.motion import SyncFifo
from interp.simulation.runner import run_cocotb
from interp.testing.tbkit import TB, scoreboard, seeded_rng

IDLE = {"push": 0, "pop": 0, "din": 0}


async def setup(dut):
    tb = TB(dut)
    await tb.reset(IDLE)
    p = {k: int(getattr(dut, k).value) for k in ("WIDTH", "DEPTH", "LW")}
    tb.ref = SyncFifo(p["WIDTH"], p["DEPTH"], p["LW"])
    tb.p = p
    return tb


def traffic(rng, width, cycles, p_push, p_pop, log, rst_at=()):
    """Random push/pop; `log` collects (pushed, popped) values as the DUT shows them."""
    sample = yield {**IDLE}
    for c in range(cycles):
        if c in rst_at:
            log["want"].clear()
            sample = yield {**IDLE, "rst": 1}
            continue
        inputs = {"rst": 0, "push": int(rng.random() < p_push), "pop": int(rng.random() < p_pop),
                  "din": rng.randrange(1 << width)}
        if inputs["pop"] and sample["valid"]:
            log["got"].append(sample["dout"])
            assert sample["dout"] == log["want"].pop(0), f"cycle {c}: out of order"
        if inputs["push"] and (not sample["full"] or (inputs["pop"] and sample["valid"])):
            log["want"].append(inputs["din"])
        elif inputs["push"]:
            log["refused"] += 1
        sample = yield inputs


@cocotb.test()
async def random_traffic(dut):
    """Every push/pop mix, overflow attempts included: order kept, refused pushes counted."""
    rng = seeded_rng(dut, "random_traffic")
    tb = await setup(dut)
    for p_push, p_pop in [(0.5, 0.5), (0.9, 0.2), (0.2, 0.9), (1.0, 1.0), (1.0, 0.0)]:
        log = {"want": [], "got": [], "refused": 0}
        await scoreboard(tb, tb.ref, traffic(rng, tb.p["WIDTH"], 400, p_push, p_pop, log),
                         context=f"push {p_push} pop {p_pop}")
        if p_pop == 0.0:
            assert log["refused"] > 0, "overflow never tried"
        await tb.reset(IDLE)
        tb.ref.reset()


@cocotb.test()
async def overflow_keeps_contents(dut):
    """Pushes into a full queue are refused (overflow high); the stored entries come out intact."""
    tb = await setup(dut)
    depth = tb.p["DEPTH"]

    def stim():
        for v in range(depth + 3):
            s = yield {"push": 1, "pop": 0, "din": v + 1}
        assert s["overflow"] and s["full"]
        out = []
        for _ in range(depth + 2):
            if s["valid"]:
                out.append(s["dout"])
            s = yield {"push": 0, "pop": 1, "din": 0}
        assert s["level"] == 0
        assert out == list(range(1, depth + 1)), f"stored {out}"

    await scoreboard(tb, tb.ref, stim(), context="overflow")


@cocotb.test()
async def reset_with_full_queue(dut):
    """rst with a full queue empties it; nothing stale comes out afterwards."""
    rng = seeded_rng(dut, "reset_with_full_queue")
    tb = await setup(dut)
    log = {"want": [], "got": [], "refused": 0}
    await scoreboard(tb, tb.ref, traffic(rng, tb.p["WIDTH"], 300, 0.8, 0.3, log, rst_at={50, 120, 121, 200}),
                     context="reset")


@pytest.mark.parametrize("head_reg", [0, 1])
def test_sync_fifo(sim, head_reg):
    run_cocotb(toplevel="sync_fifo", test_module="test_sync_fifo", sim=sim,
               parameters={"WIDTH": 8, "DEPTH": 3, "LW": 2, "HEAD_REG": head_reg},
               name=f"sync_fifo_d3_head{head_reg}")
