# SPDX-License-Identifier: Apache-2.0
"""Start-stop trigger (SU1571551 node 21 trigger 14, SU1665343 trigger 4)."""
import itertools

import cocotb

from interp.models.base import sequence
from interp.models.blocks import StartStop
from interp.testing.tbkit import TB, scoreboard, seeded_rng


@cocotb.test()
async def every_transition(dut):
    """All start/stop/rst combinations from both states, then a random run."""
    tb = TB(dut)
    await tb.reset({"start": 0, "stop": 0})
    combos = [dict(zip(("rst", "start", "stop"), bits)) for bits in itertools.product((0, 1), repeat=3)]
    stim = []
    for c in combos:                       # from idle, and from running
        stim += [c, {"rst": 0, "start": 1, "stop": 0}, c, {"rst": 1, "start": 0, "stop": 0}]
    rng = seeded_rng(dut, "every_transition")
    stim += [{"rst": int(rng.random() < 0.05), "start": rng.randint(0, 1), "stop": rng.randint(0, 1)}
             for _ in range(500)]
    samples = await scoreboard(tb, StartStop(), sequence(stim), context="start_stop")
    assert any(s["accept"] for s in samples) and any(s["finish"] for s in samples)


def test_start_stop(sim):
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="start_stop", test_module="test_start_stop", sim=sim)
