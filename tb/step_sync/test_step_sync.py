# SPDX-License-Identifier: Apache-2.0
"""step_sync: RTL vs cycle model every cycle; every step leaves exactly once, in order."""
import random

import cocotb
import pytest

from interp.models.motion import StepSync
from interp.simulation.runner import run_cocotb
from interp.testing.tbkit import TB, scoreboard, seeded_rng

IDLE = {"in_step": 0, "in_dir": 0, "in_data": 0, "tick": 0}


class SyncTB(TB):
    async def start(self):
        await self.reset(IDLE)
        d = self.dut
        self.p = {k: int(getattr(d, k).value) for k in ("AXES", "DEPTH", "LATENCY", "DATA_W", "LW")}
        self.ref = StepSync(self.p["AXES"], self.p["DEPTH"], self.p["LATENCY"], self.p["DATA_W"], self.p["LW"])
        return self


def core_and_drive(rng, p, cycles, p_step, tick_of, log, honour_stop=True, rst_at=()):
    """A core that steps LATENCY cycles after each tick it gets (tick = not STOP) with
    probability p_step; feed ticks by tick_of(cycle).  Logs what goes in and out."""
    lat, axes = p["LATENCY"], p["AXES"]
    pending = {}                       # cycle -> step the core shows then
    sample = yield dict(IDLE)
    for c in range(cycles):
        if c in rst_at:
            pending.clear()
            log["in"].clear()
            log["out"].clear()
            sample = yield {**IDLE, "rst": 1}
            continue
        if (not sample["stop"] or not honour_stop) and rng.random() < p_step:
            bits = rng.randrange(1, 1 << axes)
            pending[c + lat] = (bits, rng.randrange(1 << axes), rng.randrange(1 << p["DATA_W"]))
        step, dirs, data = pending.pop(c, (0, 0, 0))
        tick = int(tick_of(c))
        if tick and sample["out_valid"]:
            log["out"].append((sample["out_step"], sample["out_dir"], sample["out_data"]))
        if step:
            log["in"].append((step, dirs, data))
        sample = yield {"rst": 0, "in_step": step, "in_dir": dirs, "in_data": data, "tick": tick}
    # drain
    for _ in range(p["DEPTH"] + 2):
        if sample["out_valid"]:
            log["out"].append((sample["out_step"], sample["out_dir"], sample["out_data"]))
        sample = yield {**IDLE, "rst": 0, "tick": 1}
    log["last"] = sample


@cocotb.test()
async def back_pressure_fuzz(dut):
    """Random tick (back-pressure) patterns and core step patterns: 0 lost, 0 duplicated, in order."""
    rng = seeded_rng(dut, "back_pressure_fuzz")
    tb = await SyncTB(dut).start()
    patterns = [lambda c: 1, lambda c: 0 if c < 40 else 1, lambda c: c % 7 == 0,
                lambda c: rng.random() < 0.5, lambda c: rng.random() < 0.05,
                lambda c: (c // 13) % 2]
    for n in range(24):
        tick_of = patterns[n % len(patterns)]
        log = {"in": [], "out": []}
        await scoreboard(tb, tb.ref, core_and_drive(rng, tb.p, 300, rng.choice([0.3, 0.9, 1.0]), tick_of, log),
                         context=f"fuzz {n}")
        assert log["out"] == log["in"], f"fuzz {n}: {len(log['in'])} in, {len(log['out'])} out"
        assert log["in"], "no steps made"
        assert not log["last"]["overflow"]


@cocotb.test()
async def full_speed_until_full(dut):
    """No feed tick: the core runs until the store is full, then STOP holds it; no step is refused."""
    tb = await SyncTB(dut).start()
    log = {"in": [], "out": []}
    stim = core_and_drive(random.Random(1), tb.p, 60, 1.0, lambda c: 0, log)
    samples = await scoreboard(tb, tb.ref, stim, context="fill")
    assert max(s["level"] for s in samples) == tb.p["DEPTH"]
    assert len(log["in"]) == tb.p["DEPTH"] and log["out"] == log["in"]


@cocotb.test()
async def core_ignoring_stop_sets_overflow(dut):
    """A core that ignores STOP: the extra steps are refused and `overflow` is set (sticky)."""
    tb = await SyncTB(dut).start()
    log = {"in": [], "out": []}
    stim = core_and_drive(random.Random(2), tb.p, 30, 1.0, lambda c: 0, log, honour_stop=False)
    samples = await scoreboard(tb, tb.ref, stim, context="overflow")
    assert samples[-1]["overflow"] == 1
    assert log["out"] == log["in"][:tb.p["DEPTH"]]      # the stored ones are intact


@cocotb.test()
async def reset_with_full_buffer(dut):
    """rst at any point, also with a full store: empty afterwards, stale steps never come out."""
    rng = seeded_rng(dut, "reset_with_full_buffer")
    tb = await SyncTB(dut).start()
    for at in (5, 17, 40):
        log = {"in": [], "out": []}
        await scoreboard(tb, tb.ref, core_and_drive(rng, tb.p, 80, 0.8, lambda c: c > 30 and c % 3 == 0,
                                                    log, rst_at={at}), context=f"rst at {at}")
        assert log["out"] == log["in"]


@pytest.mark.parametrize("depth,latency", [(2, 1), (3, 2)])
def test_step_sync(sim, depth, latency):
    run_cocotb(toplevel="step_sync", test_module="test_step_sync", sim=sim,
               parameters={"AXES": 3, "DEPTH": depth, "LATENCY": latency, "DATA_W": 4, "LW": 2},
               name=f"step_sync_d{depth}_l{latency}")
