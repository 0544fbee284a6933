# SPDX-License-Identifier: Apache-2.0
"""The path-speed profile generator's cycle model (interp.models.speed_ramp) on its
own: exact distance, the acceleration bound, braking to rest exactly at the end with a
short crawl, hold, override, underrun, the braking bound R(n, u) itself."""
import math
import random

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from interp.testing.seeds import seeded_random
from interp.models.speed_ramp import (Segment, SpeedRamp, braking_need, clamp_override,
                                      plan_exits, profile_stimulus, random_segments,
                                      run_profile, segment_budget)

BENCH = {"feed_w": 16, "nw": 16, "pf": 12, "len_w": 34, "zw": 48}
PF = BENCH["pf"]


def rng_for(name: str) -> random.Random:
    return seeded_random(name)[0]


def run(segments, **options):
    model = SpeedRamp(**BENCH)
    return run_profile(segments, model=model, **options), model


def rules(samples, segments, quantum, *, late_ok=False):
    """Exact distance, n by one a clock after a block end (or to 0 at the end of a
    segment with no successor yet or with exit 0), no late stop.  Returns the number of n changes (for sanity)."""
    total = sum(s["speed"] for s in samples)
    length = sum(g.length for g in segments if not g.barrier)
    assert total == length - samples[-1]["remaining"]
    assert 0 <= -samples[-1]["remaining"] < quantum
    moves = [g for g in segments if not g.barrier]
    changes = ended = 0
    for prev, cur in zip(samples, samples[1:]):
        dn = cur["n"] - prev["n"]
        changes += dn != 0
        if not late_ok:
            assert abs(dn) <= 1
        # n drops to 0 at the end of a segment with no successor yet (the queue ran dry)
        # or one that stops (exit 0), also with a successor loaded in the same clock
        crossing = bool(prev["segment"]) and prev["remaining"] <= prev["speed"]
        stops = crossing and (cur["remaining"] <= 0 or moves[ended].exit == 0)
        if dn and not (cur["n"] == 0 and stops):
            assert prev["block"]
        ended += crossing
    if not late_ok:
        assert not any(s["late"] for s in samples)
    return changes


def test_braking_need_bounds_every_phase():
    """R(n, u) is at least the budget braking at every DDA tick really uses, for every
    start phase (the DDA simulated tick by tick), and at most 2 n p above n^2 + n - f^2 - f."""
    one = 1 << 6
    for rate in (1, 5, 17, 40, 63, 64):
        for n in range(1, 12):
            for floor in range(1, n + 1):
                for acc in range(0, one, 3):
                    used, level, phase = 0, n, acc
                    while level > floor:
                        used += 2 * rate * level          # one block at this level
                        phase += rate
                        if phase >= one:
                            phase -= one
                            level -= 1
                    need = braking_need(n, floor, rate, acc, 6)
                    assert used <= need, (rate, n, floor, acc)
                    assert need <= ((n * n + n - floor * floor - floor) << 6) + 2 * n * rate


def test_trapezoid_crawl_and_peak():
    """Rest to rest, p = 1 .. 1/8, block shift 2 .. 4: the cruise speed is reached and the
    crawl at one quantum before the stop lasts at most 2/p + 2 blocks."""
    for quantum, shift, rate in ((16, 2, 1 << PF), (3, 3, 3000), (1, 4, 1 << PF - 3), (7, 2, 999)):
        feed = 60 * quantum
        length = feed * (200 + (3 * 60 << shift) * (1 << PF) // rate)
        seg = Segment(feed, feed, 0, rate, length, segment_budget(rate, length, quantum, shift))
        samples, _ = run([seg], quantum=quantum, block_shift=shift)
        rules(samples, [seg], quantum)
        ns = [s["n"] for s in samples]
        assert max(ns) == 60
        top = max(i for i, n in enumerate(ns) if n >= 2)
        crawl = sum(1 for n in ns[top:] if n == 1)
        assert crawl <= (2 * (1 << PF) / rate + 2) * (1 << shift), (quantum, shift, rate, crawl)


@pytest.mark.parametrize("block_shift", [2, 3, 4])
def test_random_programs(block_shift):
    """Random planned programs with barriers: the rules hold, junctions planned above
    one quantum are passed without a stop."""
    rng = rng_for(f"random_programs bs={block_shift}")
    for _ in range(15):
        quantum = rng.choice([1, 3, 16, 100])
        segs = random_segments(rng, count=6, quantum=quantum, pf=PF, block_shift=block_shift,
                               feed_w=16, len_w=34, barriers=0.15, min_clocks=48,
                               max_quanta=min(200, 0xFFFF // (2 * quantum)),
                               max_length=rng.choice([2000, 60000, 400000]))
        samples, _ = run(segs, quantum=quantum, block_shift=block_shift)
        rules(samples, segs, quantum)


@settings(max_examples=40, deadline=None)
@given(feeds=st.lists(st.integers(2, 120), min_size=1, max_size=4),
       rates=st.lists(st.integers(1 << PF - 4, 1 << PF), min_size=4, max_size=4),
       clocks=st.lists(st.integers(50, 3000), min_size=4, max_size=4),
       quantum=st.sampled_from([1, 2, 5, 64]), shift=st.integers(2, 4),
       safe=st.booleans())
def test_hypothesis_programs(feeds, rates, clocks, quantum, shift, safe):
    segs = [Segment(f * quantum, f * quantum, 0, r, c * f * quantum,
                    segment_budget(r, c * f * quantum, quantum, shift))
            for f, r, c in zip(feeds, rates, clocks)]
    segs = plan_exits(segs, quantum, PF, underrun_safe=safe)
    samples, _ = run(segs, quantum=quantum, block_shift=shift)
    rules(samples, segs, quantum)


def test_underrun_controlled_stop():
    """Segments that arrive after the previous one ended (underrun-safe plan): each ends
    in a braked stop, the next starts from rest, nothing late."""
    rng = rng_for("underrun")
    for _ in range(5):
        quantum = rng.choice([1, 4, 30])
        segs = random_segments(rng, count=5, quantum=quantum, pf=PF, block_shift=2, feed_w=16,
                               len_w=34, min_clocks=48, max_length=30000, underrun_safe=True,
                               max_quanta=100)
        arrivals = {k: rng.randrange(0, 4000) * k for k in range(len(segs))}
        samples, _ = run(segs, quantum=quantum, arrivals=arrivals)
        rules(samples, segs, quantum)


def test_hold_stop_distance():
    """hold at a random clock: the speed falls at p to 0 (`stopped`) within
    v^2 / (2 a) + v 2^bs (1 / (2 p) + 2) + v, the position is kept, resume finishes."""
    rng = rng_for("hold")
    for _ in range(8):
        quantum, shift = rng.choice([1, 8, 50]), rng.choice([2, 3, 4])
        rate = rng.randint(1 << PF - 3, 1 << PF)
        feed = rng.randint(20, 150) * quantum
        length = feed * rng.randint(400, 2500)
        seg = Segment(feed, feed, 0, rate, length, segment_budget(rate, length, quantum, shift))
        at = rng.randrange(30, length // feed)
        samples, _ = run([seg], quantum=quantum, block_shift=shift,
                         controls=[(at, "hold", 1), (at + 12000, "resume", 0)])
        rules(samples, [seg], quantum)
        h = at                                         # the first clock with hold high
        if samples[h]["remaining"] <= 0:
            continue
        v0 = samples[h]["speed"]
        stop = next(i for i in range(h, len(samples)) if samples[i]["stopped"])
        travel = sum(s["speed"] for s in samples[h:stop])
        p, a = rate / (1 << PF), rate / (1 << PF) * quantum / (1 << shift)
        bound = v0 * v0 / (2 * a) + v0 * (1 << shift) * (1 / (2 * p) + 2) + v0
        assert travel <= bound, (travel, bound)
        assert all(s["speed"] == 0 for s in samples[stop:stop + 100])


def test_override_cap():
    """Override 0 / 37 / 100 / 180 / 255 %: n only rises (above the first quantum) while
    100 v <= feed * clamp(o) and v <= limit; after a change the speed settles at the cap."""
    rng = rng_for("override")
    quantum = 10
    seg = Segment(800, 1300, 0, 1 << PF, 800 * 20000, segment_budget(1 << PF, 800 * 20000, 10, 2))
    for ovr in (0, 37, 100, 180, 255):
        controls = [(3000, "override", ovr), (9000, "override", rng.choice([50, 150]))]
        model = SpeedRamp(**BENCH)
        stim = profile_stimulus([seg], quantum=quantum, controls=controls)
        inputs = next(stim)
        samples = []
        while True:
            before = model.speed
            model.clock(inputs)
            if model.speed > before and before:          # (0 -> 1 quantum: the start)
                assert model.speed * 100 <= model.fo and model.speed <= model.limit
            samples.append(model.sample())
            try:
                inputs = stim.send(samples[-1])
            except StopIteration:
                break
        cap = min(800 * clamp_override(ovr) // 100, 1300)
        assert max(s["speed"] for s in samples[6000:8000]) == max(cap // quantum, 1) * quantum
        rules([SpeedRamp(**BENCH).sample()] + samples, [seg], quantum)


def test_reset_anywhere_is_idle():
    """rst at any clock: the next clock is idle (speed 0, nothing in progress)."""
    rng = rng_for("reset")
    segs = random_segments(rng, count=3, quantum=4, pf=PF, block_shift=3, feed_w=16, len_w=34,
                           min_clocks=48, max_length=20000, max_quanta=80)
    clocks = len(run_profile(segs, widths=BENCH, quantum=4, block_shift=3))
    for at in rng.sample(range(1, clocks), 10):
        samples = run_profile(segs, widths=BENCH, quantum=4, block_shift=3, resets=(at,),
                              max_cycles=200000)
        s = samples[at + 1]
        assert s["speed"] == 0 and not s["moving"] and not s["next_pop"] and s["remaining"] == 0


def test_long_run_speed():
    """10^5 clocks of the model take a few seconds (it is used inside MotionTop)."""
    import time
    seg = Segment(2000, 2000, 0, 1 << PF, 2000 * 100000, segment_budget(1 << PF, 2000 * 100000, 20, 2))
    start = time.perf_counter()
    samples, _ = run([seg], quantum=20)
    elapsed = time.perf_counter() - start
    assert len(samples) > 100000
    print(f"{len(samples)} clocks in {elapsed:.2f} s")


def test_entry_margin_covers_the_unseen_tick():
    """A tick within three clocks of a switch keeps n unchecked (the decision pipeline has
    not seen the new segment).  Two moves, the first entering the second at its braking
    reach less M quanta, the switch at every phase of a block: with the compiler's margin
    (EXIT_MARGIN) none ends late; with no margin some do (the case is tight)."""
    from interp.gcode.compile import EXIT_MARGIN

    rng = rng_for("entry margin")
    quantum, shift = 1, 2
    late = {0: 0, EXIT_MARGIN: 0}
    for _ in range(12):
        cruise = rng.randint(20, 60)
        r1, r2 = rng.randint(1 << PF - 2, 1 << PF), rng.randint(1 << PF - 2, 1 << PF)
        length2 = rng.randint(40, 400) * cruise * quantum // 3
        budget2 = segment_budget(r2, length2, quantum, shift)
        for margin in late:
            entry = min(math.isqrt(budget2 >> PF) - margin, cruise)
            if entry < 3:
                continue
            base = (entry * 4 * (1 << PF) // r1 + 50) * entry * quantum * 2
            for offset in range(8):                  # the switch at every clock of two blocks
                length1 = base + offset * entry * quantum
                segs = [Segment(entry * quantum, entry * quantum, entry, r1, length1,
                                segment_budget(r1, length1, quantum, shift)),
                        Segment(cruise * quantum, cruise * quantum, 0, r2, length2, budget2)]
                samples = run_profile(segs, widths=BENCH, quantum=quantum, block_shift=shift,
                                      max_cycles=200_000)
                late[margin] += any(s["late"] for s in samples)
    assert late[EXIT_MARGIN] == 0 and late[0] > 0, late
