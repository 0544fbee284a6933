# SPDX-License-Identifier: Apache-2.0
"""speed_ramp: RTL vs the cycle model (interp.models.speed_ramp) in every cycle, on
planned trapezoid programs, random programs (seed printed), hold, override, barriers,
look-ahead underruns and resets; the profile's own rules checked on the samples.  Its
submodules are verified through it: speed_ramp_setup (the successor's p' n, f (f + 1) and
feed x override), speed_ramp_mul (the shift-add multiplier they use) — the model
computes those products exactly, so any wrong product shows as a different speed — and
speed_ramp_decide (the decision pipeline: the model's Decide, register for register, so a
wrong threshold or comparison shows as a different step of n) and speed_ramp_refine (the
give-back 2 p' floor(S / A) after a switch or load, which the model adds bit for bit, so a
wrong quotient bit shows as a different budget, hence a different step of n)."""
import cocotb
import pytest

from interp.models.speed_ramp import (BLOCK_SHIFT_MIN, Segment, SpeedRamp, profile_stimulus, random_segments,
                                      segment_budget, plan_exits)
from interp.testing.tbkit import TB, scoreboard, seeded_rng

IDLE = {"next_valid": 0, "next_barrier": 0, "next_feed": 0, "next_limit": 0, "next_exit": 0,
        "next_rate": 0, "next_length": 0, "next_budget": 0, "barrier_done": 0,
        "speed_quantum": 1, "block_shift": BLOCK_SHIFT_MIN, "override": 100, "hold": 0}


class RampTB:
    def __init__(self, dut):
        self.dut = dut
        self.w = {k: int(getattr(dut, k).value) for k in ("FEED_W", "NW", "PF", "LEN_W", "ZW")}

    async def start(self):
        self.tb = TB(self.dut)
        await self.tb.reset(IDLE)
        self.model = SpeedRamp(self.w["FEED_W"], self.w["NW"], self.w["PF"], self.w["LEN_W"],
                               self.w["ZW"])
        return self

    def seg(self, feed, length, *, quantum, block_shift=BLOCK_SHIFT_MIN, rate=None, limit=None):
        rate = rate or 1 << self.w["PF"]
        return Segment(feed, limit or feed, 0, rate, length,
                       segment_budget(rate, length, quantum, block_shift))

    def random(self, rng, count, quantum, block_shift, **kw):
        return random_segments(rng, count=count, quantum=quantum, pf=self.w["PF"],
                               block_shift=block_shift, feed_w=self.w["FEED_W"],
                               len_w=self.w["LEN_W"], **kw)

    async def run(self, segments, context, **options):
        samples = await scoreboard(self.tb, self.model, profile_stimulus(segments, **options),
                                   context=context)
        check(samples, segments, options, context)
        return samples


def check(samples, segments, options, context):
    """The profile's rules on a run without resets: exact distance, n by at most one
    a clock and only after a block end (or the last quantum at a stop: the clock the
    segment's remainder crosses 0, where a successor may load in the same clock), no
    `late`.  With late arrivals the queue can run dry after a segment planned to go on at
    its exit speed and too short to stop in: then, and only with `late`, the speed drops
    to 0 at once."""
    if options.get("resets"):
        return
    quantum = options["quantum"]
    total = sum(s["speed"] for s in samples)
    length = sum(g.length for g in segments if not g.barrier)
    carry_in, carry_out = samples[0]["remaining"], samples[-1]["remaining"]
    assert total == length + carry_in - carry_out, f"{context}: travel {total} for lengths {length}"
    assert 0 <= -carry_out < quantum, f"{context}: overshoot {-carry_out} at the end"
    for prev, cur in zip(samples, samples[1:]):
        if options.get("arrivals") and cur["late"] and cur["n"] == 0:
            continue                                    # (the documented late stop)
        dn = cur["n"] - prev["n"]
        assert abs(dn) <= 1, f"{context}: n jumped {prev['n']} -> {cur['n']}"
        if dn and not (dn == -1 and cur["n"] == 0 and (cur["remaining"] <= 0 or cur["next_pop"])):
            assert prev["block"], f"{context}: n changed inside a block"
    if not options.get("arrivals"):
        assert not any(s["late"] for s in samples), f"{context}: a stop came late"


@cocotb.test()
async def trapezoid(dut):
    """One long move from rest to rest: accelerate, cruise, brake, exact distance;
    the crawl at one quantum before the stop lasts a few blocks."""
    t = await RampTB(dut).start()
    for quantum, shift in ((16, 2), (3, 3), (1, 4)):
        feed = min(90 * quantum, (1 << t.w["FEED_W"]) - 1)
        segs = [t.seg(feed, (100 + (3 * feed // quantum << shift)) * feed, quantum=quantum,
                      block_shift=shift)]
        samples = await t.run(segs, f"trapezoid A={quantum} bs={shift}", quantum=quantum,
                              block_shift=shift)
        ns = [s["n"] for s in samples]
        assert max(ns) == feed // quantum
        top = max(i for i, s in enumerate(ns) if s >= 2)
        crawl = sum(1 for s in ns[top:] if s == 1)
        assert crawl <= 4 << shift, f"crawl {crawl} clocks at one quantum"


@cocotb.test()
async def planned_chain(dut):
    """Moves with planned exit speeds pass their junctions without stopping."""
    t = await RampTB(dut).start()
    quantum, pf = 8, t.w["PF"]
    feeds = [60, 100, 40, 80]
    segs = [t.seg(f * quantum, 200 * f * quantum, quantum=quantum, rate=(1 << pf) * (k + 2) // 5)
            for k, f in enumerate(feeds)]
    segs = plan_exits(segs, quantum, pf)
    samples = await t.run(segs, "chain", quantum=quantum)
    moving = [s["n"] for s in samples if s["moving"]]
    block = 1 << BLOCK_SHIFT_MIN                 # (the start and the final crawl: a few blocks)
    assert min(moving[8 * block:-4 * block]) > 1, "stopped at a junction"


@cocotb.test()
async def random_programs(dut):
    """Random planned programs, barriers, block shifts 2 .. 4, quanta 1 .. 100."""
    t = await RampTB(dut).start()
    rng = seeded_rng(dut, "random_programs")
    for k in range(6):
        quantum, shift = rng.choice([1, 3, 16, 100]), rng.choice([2, 2, 3, 4])
        segs = t.random(rng, 5, quantum, shift, barriers=0.2, min_clocks=3 * t.w["NW"],
                        max_quanta=min(200, ((1 << t.w["FEED_W"]) - 1) // (2 * quantum)),
                        max_length=rng.choice([2000, 60000]))
        await t.run(segs, f"random {k} A={quantum} bs={shift}", quantum=quantum,
                    block_shift=shift)


@cocotb.test()
async def hold_and_override(dut):
    """Feed hold decelerates to rest and resumes; override 0 / 50 / 250 % ramps."""
    t = await RampTB(dut).start()
    rng = seeded_rng(dut, "hold_and_override")
    quantum = 4
    segs = t.random(rng, 4, quantum, BLOCK_SHIFT_MIN, min_clocks=3 * t.w["NW"], max_length=80000,
                    max_quanta=120)
    controls = sorted([(rng.randrange(50, 600), "override", rng.choice([0, 50, 150, 250])),
                       (rng.randrange(600, 900), "hold", 1), (rng.randrange(1200, 1500), "resume", 0),
                       (rng.randrange(1500, 2000), "override", 100)])
    samples = await t.run(segs, "hold/override", quantum=quantum, controls=controls)
    assert any(s["stopped"] for s in samples) or samples[-1]["n"] == 0
    # a hold at cruise: stopped within v0^2 / (2 a) + v0 2^bs (1 / (2 p) + 2) + v0
    rate = 1 << t.w["PF"]
    seg = t.seg(100 * quantum, 100 * quantum * 3000, quantum=quantum, rate=rate // 2)
    at = 2400                                # (cruise after 100 ticks of 2 blocks)
    samples = await t.run([seg], "hold at cruise", quantum=quantum,
                          controls=[(at, "hold", 1), (at + 4000, "resume", 0)])
    h = at                                   # the first clock with hold high
    v0 = samples[h]["speed"]
    stop = next(i for i in range(h, len(samples)) if samples[i]["stopped"])
    travel = sum(s["speed"] for s in samples[h:stop])
    block = 1 << BLOCK_SHIFT_MIN
    p, a = 0.5, 0.5 * quantum / block
    assert v0 == 100 * quantum and travel <= v0 * v0 / (2 * a) + v0 * block * (1 / (2 * p) + 2) + v0, travel
    dut._log.info("hold at v0 = %d: %d path units to stopped, v0^2/2a = %.0f", v0, travel,
                  v0 * v0 / (2 * a))


@cocotb.test()
async def underrun_and_reset(dut):
    """Segments that arrive late (controlled stop, then start from rest), and resets."""
    t = await RampTB(dut).start()
    rng = seeded_rng(dut, "underrun_and_reset")
    quantum = 2
    segs = t.random(rng, 5, quantum, BLOCK_SHIFT_MIN, min_clocks=3 * t.w["NW"], max_length=20000, max_quanta=80)
    arrivals = {k: 400 * k for k in range(len(segs))}
    await t.run(segs, "underrun", quantum=quantum, arrivals=arrivals)
    resets = tuple(sorted(rng.sample(range(5, 1500), 3)))
    await t.run(segs, "resets", quantum=quantum, resets=resets)


WIDTHS = {"bench": {"FEED_W": 16, "NW": 16, "PF": 12, "LEN_W": 34, "ZW": 48},
          "cli": {"FEED_W": 34, "NW": 24, "PF": 16, "LEN_W": 66, "ZW": 68}}


@pytest.mark.parametrize("build", sorted(WIDTHS))
def test_speed_ramp(sim, build):
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="speed_ramp", test_module="test_speed_ramp", sim=sim,
               parameters=WIDTHS[build], name=f"speed_ramp_{build}")
