# SPDX-License-Identifier: Apache-2.0
"""step_dir: RTL vs cycle model every cycle; a monitor checks width/setup/hold in every cycle."""
import random

import cocotb

from interp.models.motion import StepDir, TimingMonitor
from interp.simulation.runner import run_cocotb
from interp.testing.tbkit import TB, scoreboard, seeded_rng

IDLE = {"rst": 0, "valid": 0, "step_in": 0, "dir_in": 0, "pulse_width": 1, "setup": 0, "hold": 0}


class DirTB(TB):
    async def start(self):
        await self.reset(IDLE)
        self.axes, self.tw = int(self.dut.AXES.value), int(self.dut.TW.value)
        self.ref = StepDir(self.axes, self.tw)
        return self

    async def run(self, timing, offers, p_valid=1.0, rng=None, context=""):
        """Offer the steps in `offers` [(step, dir)] at random; return (accepted, monitor)."""
        rng = rng or random.Random(0)
        mon = TimingMonitor(self.axes, timing["pulse_width"], timing["setup"], timing["hold"])
        accepted = []

        def stim():
            queue = list(offers)
            sample = yield {**IDLE, **timing}
            mon.sample(sample["step"], sample["dir"])
            while queue or sample["state"] != 0:
                valid = int(bool(queue) and rng.random() < p_valid)
                step, dirs = queue[0] if queue else (0, 0)
                if valid and sample["ready"]:
                    accepted.append(queue.pop(0))
                sample = yield {**timing, "valid": valid, "step_in": step, "dir_in": dirs}
                mon.sample(sample["step"], sample["dir"])
            for _ in range(3):
                sample = yield {**IDLE, **timing}
                mon.sample(sample["step"], sample["dir"])

        await scoreboard(self, self.ref, stim(), context=context)
        # every accepted step is one pulse on its axes, with its directions
        assert [(s, d & s) for s, d in accepted] == [(s, d) for _, s, d in mon.pulses], context
        return accepted, mon


def random_steps(rng, axes, n, p_turn):
    dirs, out = 0, []
    for _ in range(n):
        step = rng.randrange(1, 1 << axes)
        if rng.random() < p_turn:
            dirs ^= rng.randrange(1, 1 << axes)
        out.append((step, dirs))
    return out


@cocotb.test()
async def timing_never_violated(dut):
    """Random timing registers, random steps and direction changes, random offer gaps."""
    rng = seeded_rng(dut, "timing_never_violated")
    tb = await DirTB(dut).start()
    settings = [(1, 0, 0), (1, 1, 1), (2, 3, 4), (5, 0, 2), (3, 2, 0), (0, 0, 0)]
    settings += [(rng.randint(0, 9), rng.randint(0, 9), rng.randint(0, 9)) for _ in range(6)]
    for pulse, setup, hold in settings:
        timing = {"pulse_width": pulse, "setup": setup, "hold": hold}
        offers = random_steps(rng, tb.axes, 60, rng.choice([0.0, 0.3, 1.0]))
        await tb.run(timing, offers, p_valid=rng.choice([1.0, 0.5]), rng=rng, context=f"timing {timing}")


@cocotb.test()
async def rate_at_minimum_settings(dut):
    """Pulse 1, setup 0, hold 0: a step every 2 cycles, every 3 when the direction reverses."""
    tb = await DirTB(dut).start()
    timing = {"pulse_width": 1, "setup": 0, "hold": 0}
    _, mon = await tb.run(timing, [(1, 0)] * 20, context="same direction")
    rises = [c for c, _, _ in mon.pulses]
    assert {b - a for a, b in zip(rises, rises[1:])} == {2}
    _, mon = await tb.run(timing, [(1, k % 2) for k in range(20)], context="reversing")
    rises = [c for c, _, _ in mon.pulses]
    assert {b - a for a, b in zip(rises, rises[1:])} == {3}


@cocotb.test()
async def monitor_catches_violations(dut):
    """The monitor itself: a too-short hold or setup is reported (so the checks can fail)."""
    mon = TimingMonitor(1, pulse=2, setup=2, hold=2)
    try:
        for step, d in [(0, 0), (1, 0), (1, 0), (0, 0), (0, 1)]:
            mon.sample(step, d)
    except AssertionError as err:
        assert "hold" in str(err)
    else:
        raise AssertionError("hold violation not caught")
    mon = TimingMonitor(1, pulse=1, setup=2, hold=0)
    try:
        for step, d in [(0, 0), (0, 1), (1, 1)]:
            mon.sample(step, d)
    except AssertionError as err:
        assert "setup" in str(err)
    else:
        raise AssertionError("setup violation not caught")
    del dut


@cocotb.test()
async def reset_mid_pulse(dut):
    """rst in any cycle of a pulse or wait: outputs low at once, idle, no further pulse."""
    tb = await DirTB(dut).start()
    timing = {"pulse_width": 3, "setup": 2, "hold": 2}
    for k in range(1, 12):
        def stim():
            yield {**IDLE, **timing, "valid": 1, "step_in": 0b101, "dir_in": 0b100}
            for _ in range(k):
                yield {**IDLE, **timing}
            yield {**IDLE, **timing, "rst": 1}
            for _ in range(5):
                s = yield {**IDLE, **timing}
                assert s["step"] == 0 and s["ready"] == 1 and s["dir"] == 0
        await scoreboard(tb, tb.ref, stim(), context=f"reset after {k}")


def test_step_dir(sim):
    run_cocotb(toplevel="step_dir", test_module="test_step_dir", sim=sim,
               parameters={"AXES": 3, "TW": 4}, name="step_dir")
