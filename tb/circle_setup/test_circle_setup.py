# SPDX-License-Identifier: Apache-2.0
"""Circle set-up sequencer: RTL vs cycle model every cycle; the band test vs Python."""
import itertools
import math

import cocotb
import pytest

from interp.models.blocks import CircleSetup
from interp.models.lecture import within_half_step
from interp.testing.tbkit import TB, scoreboard, seeded_rng

IDLE = {"start": 0, "x0": 0, "y0": 0, "x1": 0, "y1": 0}


async def setup(dut):
    tb = TB(dut)
    await tb.reset(IDLE)
    return tb, int(dut.MW.value), int(dut.SW.value)


def commands(stims):
    """Each command's inputs held from its start until `check`, then one idle cycle.

    Records (cycle of check, its sample) in stim["seen"]."""
    for stim in stims:
        inputs = {name: stim[name] for name in IDLE if name != "start"}
        sample = yield {**inputs, "rst": 0, "start": 1}
        cycles = 1
        while not sample["check"]:
            sample = yield {**inputs, "rst": 0, "start": 0}
            cycles += 1
        stim["seen"] = (cycles, sample)
        yield {**inputs, "rst": 0, "start": 0}


def command(mw, x0, y0, x1, y1):
    ones = (1 << mw) - 1
    return {"x0": x0 & ones, "y0": y0 & ones, "x1": x1 & ones, "y1": y1 & ones, "point": (x0, y0, x1, y1)}


def check_results(stims, mw):
    """check in cycle 2*MW + 15; on_band = the exact band test."""
    for stim in stims:
        cycles, sample = stim["seen"]
        x0, y0, x1, y1 = stim["point"]
        assert cycles == 2 * mw + 15, f"{stim['point']}: check in cycle {cycles}"
        want = within_half_step(x0 * x0 + y0 * y0, x1 * x1 + y1 * y1)
        assert sample["on_band"] == want, f"{stim['point']}: on_band {sample['on_band']}"


@cocotb.test()
async def exhaustive_small(dut):
    """Every start and end point with coordinates in [-2, 2] (the smallest range of any width)."""
    tb, mw, sw = await setup(dut)
    span = range(-2, 3) if mw < 33 else range(0, 3)
    stims = [command(mw, *p) for p in itertools.product(span, repeat=4)]
    await scoreboard(tb, CircleSetup(mw, sw), commands(stims), context="exhaustive")
    check_results(stims, mw)


@cocotb.test()
async def random_commands(dut):
    """Random start points up to |x| < 2^(SW/2 - 2) (a, b < 2^(SW-2)), end points mostly near the circle."""
    tb, mw, sw = await setup(dut)
    rng = seeded_rng(dut, "random_commands")
    limit = (1 << (sw // 2 - 2)) - 1
    stims = []
    for _ in range(60):
        x0, y0 = rng.randint(-limit, limit), rng.randint(-limit, limit)
        if rng.random() < 0.7:                      # near the circle: within a step or two of it
            r, angle = math.hypot(x0, y0) + rng.uniform(-1.5, 1.5), rng.uniform(0, 2 * math.pi)
            x1 = max(-limit, min(limit, round(r * math.cos(angle))))
            y1 = max(-limit, min(limit, round(r * math.sin(angle))))
        else:
            x1, y1 = rng.randint(-limit, limit), rng.randint(-limit, limit)
        stims.append(command(mw, x0, y0, x1, y1))
    await scoreboard(tb, CircleSetup(mw, sw), commands(stims), context="random")
    check_results(stims, mw)
    assert 0 < sum(s["seen"][1]["on_band"] for s in stims) < len(stims)


@cocotb.test()
async def random_inputs(dut):
    """Every input random in every cycle (start while busy, operands changing), rare resets."""
    tb, mw, sw = await setup(dut)
    rng = seeded_rng(dut, "random_inputs")

    def stimulus():
        for _ in range(25 * (2 * mw + 16)):
            yield {"rst": int(rng.random() < 0.002), "start": int(rng.random() < 0.2),
                   **{n: rng.randrange(1 << mw) for n in ("x0", "y0", "x1", "y1")}}

    samples = await scoreboard(tb, CircleSetup(mw, sw), stimulus(), context="random inputs")
    assert sum(s["check"] for s in samples) >= 10


# (MW, SW) as circ_quadrant (WIDTH + 1, 2 WIDTH + 2) and circ_arc (WIDTH + 1, 2 WIDTH - 2) use
# them.  The sums' iCE40 form (rtl/ice40/chain_add.v) is proved equivalent by `make formal`.
@pytest.mark.parametrize("mw,sw", [(4, 8), (9, 18), (33, 66), (7, 10), (33, 62)])
def test_circle_setup(sim, mw, sw):
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="circle_setup", test_module="test_circle_setup", sim=sim,
               parameters={"MW": mw, "SW": sw}, name=f"circle_setup_m{mw}_s{sw}")
