# SPDX-License-Identifier: Apache-2.0
"""feed_rate: RTL vs cycle model every cycle; constant path speed; glitch-free feed change."""
import math

import cocotb

from interp.models.motion import FeedRate, interval_costs
from interp.simulation.runner import run_cocotb
from interp.testing.tbkit import TB, scoreboard, seeded_rng

IDLE = {"feed": 0, "axes": 0, "take": 0}


class FeedTB(TB):
    async def start(self):
        await self.reset(IDLE)
        self.frac = int(self.dut.FRAC.value)
        self.feed_w = int(self.dut.FEED_W.value)
        self.ref = FeedRate(self.frac)
        return self

    async def run(self, segments, waiting=lambda c: 1, context=""):
        """segments: [(feed, [axes of each step])]; a step waits when waiting(cycle).
        Returns the cycles at which steps left."""
        taken = []

        def stim():
            queue = [(feed, n) for feed, axes in segments for n in axes]
            sample = yield dict(IDLE)
            c = 0
            while queue:
                feed, n = queue[0]
                take = int(bool(waiting(c)))
                if take and sample["tick"]:
                    taken.append(c)
                    queue.pop(0)
                sample = yield {"feed": feed, "axes": n, "take": take}
                c += 1
            yield dict(IDLE)

        await scoreboard(self, self.ref, stim(), context=context)
        return taken


@cocotb.test()
async def constant_path_speed(dut):
    """Axial, 2-axis and 3-axis steps: the path speed equals feed / 2^FRAC within 2^-FRAC."""
    tb = await FeedTB(dut).start()
    one = 1 << tb.frac
    slow = 1 << (tb.frac - 16)                 # feeds below 2^FRAC / 13: slow ones at any FRAC
    for feed in (one // 3, one // 10 + 7, 997 * slow + 1):
        for n in (1, 2, 3):
            steps = 200 if feed > 5000 * slow else 20
            taken = await tb.run([(feed, [n] * (steps + 1))], context=f"feed {feed} axes {n}")
            cycles = taken[-1] - taken[0]
            speed = steps * math.sqrt(n) / cycles
            want = feed / one
            # the first and the last step each leave within one cycle, plus the rounded sqrt
            tol = want * 2 / cycles + 2 ** -tb.frac
            assert abs(speed - want) <= tol, f"feed {feed} axes {n}: {speed} vs {want}"


@cocotb.test()
async def interval_after_diagonal(dut):
    """The interval after a step is sqrt(axes) times the axial one (exactly, at feed = 2^FRAC / k)."""
    tb = await FeedTB(dut).start()
    one = 1 << tb.frac
    feed = one // 8
    taken = await tb.run([(feed, [1, 1, 2, 1, 3, 1, 1])], context="sqrt pattern")
    gaps = [b - a for a, b in zip(taken, taken[1:])]
    costs = interval_costs(tb.frac)
    # after an axial step 8 cycles; after a diagonal ceil(8 * 1.414); after 3 axes ceil(8 * 1.732), +-1 phase
    assert gaps[0] == gaps[1] == gaps[3] == 8 and gaps[2] in (11, 12) and gaps[4] in (13, 14), gaps
    assert costs[2] == round(math.sqrt(2) * one) and costs[3] == round(math.sqrt(3) * one)


@cocotb.test()
async def feed_change_without_glitch(dut):
    """Feed changes between segments: every interval belongs to one feed, none is short or lost."""
    rng = seeded_rng(dut, "feed_change_without_glitch")
    tb = await FeedTB(dut).start()
    one = 1 << tb.frac
    segments = [(rng.choice([one // 4, one // 7, one // 2, 3000 << (tb.frac - 16)]), [rng.choice([1, 2, 3]) for _ in range(6)])
                for _ in range(12)]
    taken = await tb.run(segments, context="feed change")
    flat = [(feed, n) for feed, axes in segments for n in axes]
    costs = interval_costs(tb.frac)
    for k, (a, b) in enumerate(zip(taken, taken[1:])):
        feed, n = flat[k]                 # the interval after step k runs at step k's feed
        assert math.floor(costs[n] / feed) <= b - a <= math.ceil(costs[n] / feed), \
            f"step {k}: interval {b - a} at feed {feed}, axes {n}"


@cocotb.test()
async def back_pressure_holds_phase(dut):
    """Steps waiting at random: tick stays up, no burst after a pause (one step per tick)."""
    rng = seeded_rng(dut, "back_pressure_holds_phase")
    tb = await FeedTB(dut).start()
    one = 1 << tb.frac
    taken = await tb.run([(one // 3, [rng.choice([1, 2, 3]) for _ in range(80)])],
                         waiting=lambda c: rng.random() < 0.3, context="random waiting")
    gaps = [b - a for a, b in zip(taken, taken[1:])]
    assert min(gaps) >= 3, "two steps closer than the feed allows"


@cocotb.test()
async def reset_mid_interval(dut):
    """rst in the middle of an interval: tick is high at once afterwards, the model agrees."""
    tb = await FeedTB(dut).start()
    await tb.run([(1000 << (tb.frac - 16), [3, 1])], context="before reset")
    await tb.reset(IDLE)
    tb.ref.reset()
    assert int(dut.tick.value) == 1 and dut.acc.value.to_signed() == 0


def test_feed_rate(sim):
    run_cocotb(toplevel="feed_rate", test_module="test_feed_rate", sim=sim,
               parameters={"FEED_W": 16, "FRAC": 16}, name="feed_rate")


def test_feed_rate_wide(sim):
    """The G-code build's speed block: FRAC = 32 (costs from the exact integer square root)."""
    run_cocotb(toplevel="feed_rate", test_module="test_feed_rate", sim=sim,
               parameters={"FEED_W": 34, "FRAC": 32}, name="feed_rate_wide")
