# SPDX-License-Identifier: Apache-2.0
"""power_scale: every cycle against a cycle model (a sequence of 17 x (FEED_W + 2) + 17
clocks; at its last clock `scaled` = duty * ratio >> 16 of the inputs taken at the end of the
sequence before, ratio = min(speed, feed) * 65536 // feed, 65535 at or above the feed, 0 at
feed 0), with seeded random duty, speed and feed at full width, held for a while or changed
every clock, and reset at random cycles; at the controller's FEED_W 50 and at 6."""
import cocotb
import pytest

from interp.models.base import CycleModel
from interp.simulation.runner import run_cocotb
from interp.testing.tbkit import TB, scoreboard, seeded_rng

IDLE = {"duty": 0, "speed": 0, "feed": 0}


def scaled_power(duty: int, speed: int, feed: int) -> int:
    """Grbl's dynamic laser power: duty x speed / feed, the ratio in 16 bits."""
    ratio = 0 if feed == 0 else 0xFFFF if speed >= feed else (speed << 16) // feed
    return duty * ratio >> 16


class PowerScale(CycleModel):
    watch = {"scaled": False}

    def __init__(self, feed_w: int):
        self.feed_w, self.rounds = feed_w, 17 * (feed_w + 2) + 17
        self.round, self.taken, self.scaled = 0, (0, 0, 0), 0
        self.divided = getattr(self, "divided", 0)      # sequences with 0 < speed < feed and duty > 1

    def clock(self, i) -> None:
        if i.get("rst"):
            self.__init__(self.feed_w)
            return
        if self.round == self.rounds - 1:
            self.scaled = scaled_power(*self.taken)
            duty, speed, feed = self.taken
            self.divided += int(duty > 1 and 0 < speed < feed)
            self.taken = (i["duty"], i["speed"], i["feed"])
        self.round = (self.round + 1) % self.rounds


def inputs(rng, cycles: int, feed_w: int):
    held, top = dict(IDLE), 1 << feed_w
    for _ in range(cycles):
        if rng.random() < 0.004:
            feed = rng.choice([0, 1, top - 1, rng.randrange(1 << min(16, feed_w))] + [rng.randrange(top)] * 4)
            speed = rng.choice([0, feed, feed + 1, rng.randrange(top)] + [rng.randrange(feed + 1)] * 6)
            held = {"duty": rng.choice([0, 1, 65535] + [rng.randrange(1 << 16)] * 5), "speed": speed % top, "feed": feed}
        changing = rng.random() < 0.05
        step = {k: rng.randrange(1 << 16 if k == "duty" else top) for k in held} if changing else held
        yield {**step, "rst": int(rng.random() < 0.00005)}


@cocotb.test()
async def against_the_model(dut):
    rng = seeded_rng(dut, "against_the_model")
    feed_w = int(dut.FEED_W.value)
    model = PowerScale(feed_w)
    tb = TB(dut)
    await tb.reset(IDLE)
    await scoreboard(tb, model, inputs(rng, 100 * model.rounds, feed_w), context="power_scale")
    assert model.divided > 20, f"only {model.divided} sequences divided"


def test_scaled_power_examples():
    assert scaled_power(65535, 50, 100) == 32767               # half the speed: half the power
    assert scaled_power(40000, 100, 100) == 39999 and scaled_power(40000, 7, 0) == 0
    assert scaled_power(65535, 1, 3) == 21844


@pytest.mark.parametrize("feed_w", [50, 6])
def test_power_scale(sim, feed_w):
    run_cocotb(toplevel="power_scale", test_module="test_power_scale", sim=sim, parameters={"FEED_W": feed_w},
               name=f"power_scale_{feed_w}")
