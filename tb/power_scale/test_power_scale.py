# SPDX-License-Identifier: Apache-2.0
"""power_scale: every cycle against a cycle model (a sequence of 17 x (SPEED_W + 2) + 17
clocks; at its last clock `scaled` = duty * ratio >> 16 of the inputs taken at the end of the
sequence before, ratio = speed * 65536 // (feed << shift); duty itself at or above that, 0
at feed 0), with seeded random duty, speed, shift and feed at full width, held for a while
or changed every clock, and reset at random cycles; at the controller's widths (FEED_W 34,
SPEED_W 46) and at 6 and 9."""
import cocotb
import pytest

from interp.models.base import CycleModel
from interp.simulation.runner import run_cocotb
from interp.testing.tbkit import TB, scoreboard, seeded_rng

IDLE = {"duty": 0, "speed": 0, "feed": 0, "shift": 0}


def scaled_power(duty: int, speed: int, feed: int, shift: int = 0) -> int:
    """Grbl's dynamic laser power: duty x speed / (feed << shift), the ratio in 16 bits."""
    whole = feed << shift
    if feed == 0:
        return 0
    return duty if speed >= whole else duty * ((speed << 16) // whole) >> 16


class PowerScale(CycleModel):
    watch = {"scaled": False}

    def __init__(self, speed_w: int):
        self.speed_w, self.rounds = speed_w, 17 * (speed_w + 2) + 17
        self.round, self.taken, self.scaled = 0, (0, 0, 0, 0), 0
        self.divided = getattr(self, "divided", 0)      # sequences with 0 < speed < feed and duty > 1

    def clock(self, i) -> None:
        if i.get("rst"):
            self.__init__(self.speed_w)
            return
        if self.round == self.rounds - 1:
            self.scaled = scaled_power(*self.taken)
            duty, speed, feed, shift = self.taken
            self.divided += int(duty > 1 and 0 < speed < feed << shift)
            self.taken = (i["duty"], i["speed"], i["feed"], i["shift"])
        self.round = (self.round + 1) % self.rounds


def inputs(rng, cycles: int, feed_w: int, speed_w: int):
    held, top, widths = dict(IDLE), 1 << feed_w, {"duty": 16, "feed": feed_w, "speed": speed_w}
    for _ in range(cycles):
        if rng.random() < 0.004:
            shift = rng.randint(0, speed_w - feed_w)
            feed = rng.choice([0, 1, top - 1, rng.randrange(1 << min(16, feed_w))] + [rng.randrange(top)] * 4)
            whole = feed << shift
            speed = rng.choice([0, whole, whole + 1, rng.randrange(1 << speed_w)] + [rng.randrange(whole + 1)] * 6)
            held = {"duty": rng.choice([0, 1, 65535] + [rng.randrange(1 << 16)] * 5), "speed": speed % (1 << speed_w),
                    "feed": feed, "shift": shift}
        if rng.random() < 0.05:                         # a clock of random inputs
            step = {k: rng.randrange(1 << w) for k, w in widths.items()}
            step["shift"] = rng.randint(0, speed_w - feed_w)
        else:
            step = held
        yield {**step, "rst": int(rng.random() < 0.00005)}


@cocotb.test()
async def against_the_model(dut):
    rng = seeded_rng(dut, "against_the_model")
    feed_w, speed_w = int(dut.FEED_W.value), int(dut.SPEED_W.value)
    model = PowerScale(speed_w)
    tb = TB(dut)
    await tb.reset(IDLE)
    await scoreboard(tb, model, inputs(rng, 200 * model.rounds, feed_w, speed_w), context="power_scale")
    assert model.divided > 20, f"only {model.divided} sequences divided"


def test_scaled_power_examples():
    assert scaled_power(65535, 50, 100) == 32767               # half the speed: half the power
    assert scaled_power(40000, 100, 100) == 40000 and scaled_power(40000, 7, 0) == 0
    assert scaled_power(65535, 1, 3) == 21844 and scaled_power(65535, 400, 100, 3) == 32767


@pytest.mark.parametrize("feed_w, speed_w", [(34, 46), (6, 9)])
def test_power_scale(sim, feed_w, speed_w):
    run_cocotb(toplevel="power_scale", test_module="test_power_scale", sim=sim,
               parameters={"FEED_W": feed_w, "SPEED_W": speed_w}, name=f"power_scale_{feed_w}")
