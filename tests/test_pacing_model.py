# SPDX-License-Identifier: Apache-2.0
"""The S-curve filter and step pacer models against their golden equations
(interp/models/pacing.py): moving sum, exact distance, every step once."""
import itertools
import random

from hypothesis import given, settings, strategies as st

from interp.models.pacing import JerkFilter, StepPacer, code_of, code_value, lecture_cost, moving_sum, pace


def run_filter(plan, quantum, jerk_shift, block_shift, mw=4, lead=0, phase=0, model=None, late=None):
    """Drive the filter with a ramp (a strobe with a block tick, the speed changing at
    the end of that clock); `late`: the last drop to 0 comes that many clocks after a
    tick, inside the block (as a stop's end may).  Returns (speeds, sums, F, model)."""
    size = 1 << block_shift
    f = model or JerkFilter(16, mw)
    if model is None:
        f.clock({"rst": 1, "jerk_shift": jerk_shift, "speed": 0, "up": 0, "down": 0, "block": 0,
                 "speed_quantum": quantum})
    n = k = t = quiet = 0
    speeds, sums, regs = [], [], []
    while quiet < ((1 << jerk_shift) + 1) * size + 1:
        tick = t >= lead and t % size == phase
        up = down = 0
        if late is not None and k >= len(plan) and n == 1:
            down = int(t >= lead and t % size == (phase + late) % size)
        elif tick:
            if k < len(plan):
                up, down = int(plan[k] > 0), int(plan[k] < 0 and n > 0)
                k += 1
            else:
                down = int(n > 0)
        i = {"speed": n * quantum, "up": up, "down": down, "block": int(tick),
             "speed_quantum": quantum, "jerk_shift": jerk_shift}
        f.set_inputs(i)
        speeds.append(n * quantum)
        sums.append(f.sum)
        regs.append(f.total)
        f.clock(i)
        n += up - down
        t += 1
        quiet = quiet + 1 if (k >= len(plan) and n == 0) else 0
    return speeds, sums, regs, f


plans = st.lists(st.sampled_from((1, 1, 0, -1)), min_size=0, max_size=60)


@settings(max_examples=150, deadline=None)
@given(plan=plans, quantum=st.integers(1, 1000), jerk_shift=st.integers(0, 4),
       block_shift=st.integers(0, 3), data=st.data())
def test_filter_is_the_moving_sum(plan, quantum, jerk_shift, block_shift, data):
    phase = data.draw(st.integers(0, (1 << block_shift) - 1))
    speeds, sums, regs, f = run_filter(plan, quantum, jerk_shift, block_shift, phase=phase)
    m, b = 1 << jerk_shift, 1 << block_shift
    assert regs == moving_sum(speeds, m, b)
    assert sum(regs) == m * sum(speeds)             # distance exactly M times
    assert sums == (speeds if jerk_shift == 0 else regs)
    assert f.empty and f.total == 0 and f.delta == 0


@settings(max_examples=150, deadline=None)
@given(plan=plans, quantum=st.integers(1, 1000), jerk_shift=st.integers(0, 4),
       block_shift=st.integers(1, 3), data=st.data())
def test_filter_drop_inside_a_block_keeps_the_distance(plan, quantum, jerk_shift, block_shift, data):
    """The last drop of a stop inside a block: the debt is paid back, the distance exact."""
    size = 1 << block_shift
    phase = data.draw(st.integers(0, size - 1))
    late = data.draw(st.integers(1, size - 1))
    speeds, sums, _, f = run_filter(plan + [1], quantum, jerk_shift, block_shift, phase=phase, late=late)
    assert sum(sums) == (1 << jerk_shift) * sum(speeds)
    assert f.empty and f.owed == 0 and not f.pending
    if jerk_shift == 0:
        assert sums == speeds


def test_filter_exhaustive_small():
    """Every plan of up to 7 blocks of {+1, 0, -1} at every shift 0..2, block_shift 0..1."""
    count = 0
    for length in range(8):
        for plan in itertools.product((1, 0, -1), repeat=length):
            for jerk_shift in range(3):
                for block_shift in range(2):
                    speeds, _, regs, f = run_filter(list(plan), 3, jerk_shift, block_shift, mw=2)
                    assert regs == moving_sum(speeds, 1 << jerk_shift, 1 << block_shift)
                    assert sum(regs) == (1 << jerk_shift) * sum(speeds) and f.empty
                    count += 1
    assert count == sum(3 ** n for n in range(8)) * 6


def test_filter_restart_masks_old_codes():
    """A deeper shift after a move: the old move's codes in the delay line are never read."""
    rng = random.Random(7)
    f = JerkFilter(16, 4)
    f.clock({"rst": 1, "jerk_shift": 1, "speed": 0, "up": 0, "down": 0, "block": 0, "speed_quantum": 1})
    for shift in (1, 4, 0, 3, 4, 2):
        plan = [1] * rng.randint(1, 9) + [0] * rng.randint(0, 20)
        speeds, _, regs, f = run_filter(plan, 5, shift, 0, mw=4, lead=1, model=f)
        assert f.shift == shift
        assert regs == moving_sum(speeds, 1 << shift, 1), shift


def test_codes():
    assert [code_value(code_of(u, d)) for u, d in ((0, 0), (1, 0), (0, 1), (1, 1))] == [0, 1, -1, 0]


@settings(max_examples=100, deadline=None)
@given(costs=st.lists(st.integers(1, 300), min_size=1, max_size=30),
       sums=st.lists(st.integers(0, 200), min_size=1, max_size=400),
       shift=st.integers(0, 3), seed=st.integers(0, 2 ** 32 - 1))
def test_pacer_model_is_pace(costs, sums, shift, seed):
    """The cycle model with every step waiting and the output ready = `pace`; with
    random readiness: every step once, in order, and phase = F given - charged."""
    rng = random.Random(seed)
    for random_ready in (False, True):
        ready = [1 if not random_ready else int(rng.random() < 0.7) for _ in sums]
        p = StepPacer(16, 8, 4, 8)
        fired, k, given_f, charged = [], 0, 0, 0
        for t, f in enumerate(sums):
            i = {"sum": f << shift, "jerk_shift": shift, "step_valid": int(k < len(costs)),
                 "step_axes": 1, "step_cost": costs[k] if k < len(costs) else 0, "drive_ready": ready[t]}
            p.set_inputs(i)
            if p.fire:
                fired.append(t)
                charged += costs[k] << shift
                k += 1
            p.clock(i)
            given_f += f << shift
            assert p.phase == given_f - charged
        want, phase = pace([f << shift for f in sums], costs, shift, ready)
        assert fired == want and p.phase == phase


def test_lecture_costs():
    assert [lecture_cost(a, 16) for a in (0, 1, 2, 3)] == [65536, 65536, 92682, 113512]


@settings(max_examples=60, deadline=None)
@given(top=st.integers(1, 12), cruise=st.integers(0, 30), quantum=st.integers(1, 50),
       jerk_shift=st.integers(0, 4), block_shift=st.integers(0, 2), steps=st.integers(1, 40))
def test_last_step_leaves_as_the_filtered_speed_reaches_zero(top, cruise, quantum, jerk_shift,
                                                             block_shift, steps):
    """Trapezoid -> S-curve filter -> pacer, the segment's length split into step costs
    that sum to it exactly (as the host sets them), the speed at most one step per
    clock: every step leaves, the last one in
    the clock after the filtered speed's last non-zero clock, and the phase ends at 0."""
    plan = [1] * top + [0] * cruise + [-1] * top
    speeds, sums, _, _ = run_filter(plan, quantum, jerk_shift, block_shift, mw=4)
    length = sum(speeds)
    cost = max(max(speeds), length // steps)          # at most one step per clock
    costs = [cost] * (length // cost - 1) + [length - cost * (length // cost - 1)]
    assert sum(costs) == length
    fired, phase = pace(sums + [0, 0], costs, jerk_shift)
    last_f = max(t for t, f in enumerate(sums) if f)
    assert len(fired) == len(costs) and fired[-1] == last_f + 1 and phase == 0
