# SPDX-License-Identifier: Apache-2.0
"""jerk_filter: RTL vs cycle model every cycle; the output is the moving sum of the
block speeds over 2^jerk_shift blocks and preserves the distance exactly.  The delay
line it holds, code_delay (the block-RAM of 2-bit codes), is verified through it: the
moving sum is wrong if any code comes back late, early or changed."""
import cocotb

from interp.models.pacing import JerkFilter, moving_sum
from interp.testing.tbkit import TB, scoreboard, seeded_rng

IDLE = {"speed": 0, "up": 0, "down": 0, "block": 0, "speed_quantum": 1, "jerk_shift": 0}


def trapezoid(top, cruise):
    """Block plan of a trapezoid: climb to `top` quanta, cruise, descend to 0."""
    return [1] * top + [0] * cruise + [-1] * top


def ramp(rng, quantum, jerk_shift, block_shift, blocks, top=None, phase=None, lead=0, plan=None,
         late=None):
    """Inputs of a virtual trapezoid (random climbs, cruises, descents) ending at speed 0.

    Strobes come with the block ticks (every 2^block_shift clocks, at `phase`);
    the speed changes at the end of the strobe's clock (the ramp's contract).
    `lead` idle clocks first.  `late`: after the plan, the last drop (1 -> 0) comes
    `late` clocks after a tick, inside a block, as a stop's end may.  Long enough
    for the filter to empty afterwards.
    """
    size = 1 << block_shift
    phase = rng.randrange(size) if phase is None else phase
    top = top if top is not None else rng.randint(1, 40)
    n, t, out = 0, 0, []
    if plan is None:
        plan = []
        while len(plan) < blocks:
            run = rng.randint(1, 12)
            plan += [rng.choice((1, 1, 0, -1))] * run
        plan = plan[:blocks]
    quiet = 0
    k = 0
    while quiet < ((1 << jerk_shift) + 2) * size + lead:
        tick = t % size == phase and t >= lead
        up = down = 0
        if late is not None and k >= len(plan) and n == 1:
            down = int(t >= lead and t % size == (phase + late) % size)
        elif tick:
            if k < len(plan):
                want = plan[k]
                up = int(want > 0 and n < top)
                down = int(want < 0 and n > 0)
                k += 1
            else:
                down = int(n > 0)
        out.append({"speed": n * quantum, "up": up, "down": down, "block": int(tick),
                    "speed_quantum": quantum, "jerk_shift": jerk_shift})
        n += up - down
        quiet = quiet + 1 if (k >= len(plan) and n == 0) else 0
        t += 1
    return out


class FilterTB(TB):
    async def start(self, jerk_shift=0):
        await self.reset({**IDLE, "jerk_shift": jerk_shift})
        self.feed_w = int(self.dut.FEED_W.value)
        self.mw = int(self.dut.MW.value)
        self.ref = JerkFilter(self.feed_w, self.mw)
        self.ref.clock({**IDLE, "jerk_shift": jerk_shift, "rst": 1})
        self.ref.inputs = {}
        return self

    async def run(self, inputs, context=""):
        def stim():
            for item in inputs:
                yield item
        return await scoreboard(self, self.ref, stim(), context=context)


def check_sum(samples, inputs, jerk_shift, block_shift, context):
    """F (the register) in clock k = sum of the speeds of the last 2^J blocks; distance x 2^J."""
    speeds = [i["speed"] for i in inputs]
    want = moving_sum(speeds, 1 << jerk_shift, 1 << block_shift)
    got = [s["total"] for s in samples[1:len(inputs)]]      # sample k+1 holds F of clock k+1
    bad = [(k + 1, g, w) for k, (g, w) in enumerate(zip(got, want[1:])) if g != w]
    assert not bad, f"{context}: F != moving sum (clock, F, want): {bad[:4]}"
    assert sum(s["total"] for s in samples) == (1 << jerk_shift) * sum(speeds), \
        f"{context}: distance not preserved"
    assert samples[-1]["empty"] == 1 and samples[-1]["total"] == 0, f"{context}: not empty at the end"


@cocotb.test()
async def trapezoid_is_the_speed(dut):
    """jerk_shift 0: sum = speed in every clock, at block_shift 0 and 2."""
    rng = seeded_rng(dut, "trapezoid_is_the_speed")
    tb = await FilterTB(dut).start(0)
    for block_shift in (0, 2):
        inputs = ramp(rng, rng.randint(1, 300), 0, block_shift, 60)
        samples = await tb.run(inputs, context=f"trapezoid block_shift {block_shift}")
        assert all(s["sum"] == i["speed"] for s, i in zip(samples[1:], inputs)), "sum != speed"
        check_sum(samples, inputs, 0, block_shift, "trapezoid")


@cocotb.test()
async def moving_sum_random(dut):
    """Random profiles, every jerk_shift 0 .. MW, block_shift 0 (jerk_shift 0 only) .. 3: F is
    the moving sum."""
    rng = seeded_rng(dut, "moving_sum_random")
    tb = await FilterTB(dut).start(0)
    mw = tb.mw
    for jerk_shift in range(mw + 1):
        for block_shift in (0 if jerk_shift == 0 else 1, rng.randint(1, 3)):   # shift > 0: blocks >= 2 clocks
            quantum = rng.randint(1, (1 << (tb.feed_w - 6)) - 1)
            inputs = ramp(rng, quantum, jerk_shift, block_shift, rng.randint(20, 90), lead=2)
            context = f"J {jerk_shift} block_shift {block_shift} A {quantum}"
            samples = await tb.run(inputs, context=context)
            assert samples[-1]["shift"] == jerk_shift
            if jerk_shift:
                # the first command after the jerk change sees the new shift only once empty
                check_sum(samples, inputs, jerk_shift, block_shift, context)


@cocotb.test()
async def drop_inside_a_block(dut):
    """Stops whose last drop comes inside a block: the filter keeps the speed to the
    block's end, books the extra as a debt and pays it back; distance exact, empty."""
    rng = seeded_rng(dut, "drop_inside_a_block")
    tb = await FilterTB(dut).start(0)
    for jerk_shift in (0, 1, rng.randint(2, tb.mw)):
        for block_shift in (1, rng.randint(2, 4)):
            size = 1 << block_shift
            late = rng.randint(1, size - 1)
            ups = rng.randint(1, 6)           # ends at 1 quantum or more: the late drop happens
            plan = [1] * ups + [0] * rng.randint(0, 9) + [-1] * rng.randint(0, ups - 1)
            # top = ups: a lower top would cap the climb and let the plan end at 0 (no late drop)
            inputs = ramp(rng, rng.randint(1, 500), jerk_shift, block_shift, 0, top=ups, lead=2,
                          plan=plan, late=late)
            context = f"late drop J {jerk_shift} block_shift {block_shift} late {late}"
            samples = await tb.run(inputs, context=context)
            speeds = [i["speed"] for i in inputs]
            assert sum(s["sum"] for s in samples[1:]) == (1 << jerk_shift) * sum(speeds), \
                f"{context}: distance not preserved"
            assert max(s["owed"] for s in samples) > 0 or jerk_shift == 0, f"{context}: no debt booked"
            assert samples[-1]["empty"] and samples[-1]["owed"] == 0, f"{context}: not empty at the end"


@cocotb.test()
async def full_speed_and_quantum(dut):
    """The widest words: speed near 2^FEED_W - 1 at the deepest shift (no overflow of F)."""
    rng = seeded_rng(dut, "full_speed_and_quantum")
    tb = await FilterTB(dut).start(0)
    mw = tb.mw
    quantum = ((1 << tb.feed_w) - 1) // 7
    inputs = ramp(rng, quantum, mw, 1, 0, top=7, lead=2, plan=trapezoid(7, (1 << mw) + 3))
    samples = await tb.run(inputs, context="full speed")
    check_sum(samples, inputs, mw, 1, "full speed")
    assert max(s["total"] for s in samples) == 7 * quantum << mw, "never at the top"


@cocotb.test()
async def shift_changes_only_when_empty(dut):
    """A new jerk_shift while moving waits until empty; a deeper one after a move
    never reads the old move's codes (the restart masks them)."""
    rng = seeded_rng(dut, "shift_changes_only_when_empty")
    tb = await FilterTB(dut).start(1)
    move = ramp(rng, 5, 1, 1, 0, top=20, lead=1, plan=trapezoid(20, rng.randint(0, 30)))
    # ask for shift 3 in the middle of the move: ignored until the filter is empty
    asked = [dict(i, jerk_shift=3) if k > len(move) // 3 else i for k, i in enumerate(move)]
    samples = await tb.run(asked, context="shift asked while moving")
    changed = [k for k, s in enumerate(samples) if s["shift"] == 3]
    assert changed, "the new shift was never taken"
    first = changed[0]
    assert first > len(move) - 4 and samples[first - 1]["empty"], f"taken at {first} while busy"
    speeds = [i["speed"] for i in asked]
    assert sum(s["total"] for s in samples) == 2 * sum(speeds), "distance not preserved"
    # a deeper shift now: the delay line still holds the first move's codes
    second = ramp(rng, 5, 3, 1, 40, top=20, lead=1)
    samples = await tb.run(second, context="after the shift change")
    check_sum(samples, second, 3, 1, "after the shift change")


@cocotb.test()
async def reset_mid_move(dut):
    """rst in the middle of a move: empty at once, the next move is exact."""
    rng = seeded_rng(dut, "reset_mid_move")
    tb = await FilterTB(dut).start(2)
    move = ramp(rng, 9, 2, 1, 60, top=15, lead=1)
    await tb.run(move[: len(move) // 2], context="before reset")
    await tb.reset({**IDLE, "jerk_shift": 2})
    tb.ref.clock({**IDLE, "jerk_shift": 2, "rst": 1})
    tb.ref.inputs = {}
    assert int(dut.empty.value) == 1 and int(dut.sum.value) == 0
    samples = await tb.run(move, context="after reset")
    check_sum(samples, move, 2, 1, "after reset")


def test_jerk_filter(sim):
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="jerk_filter", test_module="test_jerk_filter", sim=sim,
               parameters={"FEED_W": 16, "MW": 6, "SUM_W": 22}, name="jerk_filter")


def test_jerk_filter_wide(sim):
    """The G-code build's widths: FEED_W 34, MW 12 (a 4096-block delay line)."""
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="jerk_filter", test_module="test_jerk_filter", sim=sim,
               parameters={"FEED_W": 34, "MW": 12, "SUM_W": 46}, name="jerk_filter_wide",
               testcase=["trapezoid_is_the_speed", "full_speed_and_quantum", "shift_changes_only_when_empty",
                         "drop_inside_a_block"])
