# SPDX-License-Identifier: Apache-2.0
"""power_scale: every cycle against a cycle model (the inputs taken at round 0 of each
34-clock sequence, `scaled` set at round 33 to duty * ratio >> 16, ratio = min(speed, feed)
* 65536 // feed, 65535 at or above the feed, 0 at feed 0), with seeded random duty, speed
and feed at full width, held for a while or changed every clock, and reset at random cycles."""
import cocotb

from interp.models.base import CycleModel
from interp.simulation.runner import run_cocotb
from interp.testing.tbkit import TB, scoreboard, seeded_rng

FEED_W = 50
ROUNDS = 34
IDLE = {"duty": 0, "speed": 0, "feed": 0}


def scaled_power(duty: int, speed: int, feed: int) -> int:
    """Grbl's dynamic laser power: duty x speed / feed, the ratio in 16 bits."""
    ratio = 0 if feed == 0 else 0xFFFF if speed >= feed else (speed << 16) // feed
    return duty * ratio >> 16


class PowerScale(CycleModel):
    watch = {"scaled": False}

    def __init__(self):
        self.round, self.taken, self.scaled = 0, (0, 0, 0), 0

    def clock(self, i) -> None:
        if i.get("rst"):
            self.__init__()
            return
        if self.round == 0:
            self.taken = (i["duty"], i["speed"], i["feed"])
        elif self.round == ROUNDS - 1:
            self.scaled = scaled_power(*self.taken)
        self.round = (self.round + 1) % ROUNDS


def inputs(rng, cycles: int):
    held = dict(IDLE)
    for _ in range(cycles):
        if rng.random() < 0.01 or rng.random() < 0.001:
            feed = rng.choice([0, 1, rng.randrange(1 << 16), rng.randrange(1 << FEED_W), (1 << FEED_W) - 1])
            speed = rng.choice([0, feed, feed + 1, rng.randrange(feed + 1), rng.randrange(1 << FEED_W)])
            held = {"duty": rng.choice([0, 1, 65535, rng.randrange(1 << 16)]), "speed": speed % (1 << FEED_W),
                    "feed": feed}
        changing = rng.random() < 0.05
        step = {k: rng.randrange(1 << (16 if k == "duty" else FEED_W)) for k in held} if changing else held
        yield {**step, "rst": int(rng.random() < 0.0005)}


@cocotb.test()
async def against_the_model(dut):
    rng = seeded_rng(dut, "against_the_model")
    tb = TB(dut)
    await tb.reset(IDLE)
    samples = await scoreboard(tb, PowerScale(), inputs(rng, 30000), context="power_scale")
    assert len({s["scaled"] for s in samples}) > 50, "the output hardly moved"


def test_scaled_power_examples():
    assert scaled_power(65535, 50, 100) == 32767               # half the speed: half the power
    assert scaled_power(40000, 100, 100) == 39999 and scaled_power(40000, 7, 0) == 0
    assert scaled_power(65535, 1, 3) == 21844


def test_power_scale(sim):
    run_cocotb(toplevel="power_scale", test_module="test_power_scale", sim=sim, parameters={"FEED_W": FEED_W},
               name="power_scale")
