# SPDX-License-Identifier: Apache-2.0
"""step_pacer: RTL vs cycle model every cycle; every offered step leaves exactly once,
in order; the phase never loses distance; path speed = F / cost."""
import cocotb

from interp.models.pacing import StepPacer, lecture_cost, pace
from interp.testing.tbkit import TB, scoreboard, seeded_rng

IDLE = {"sum": 0, "jerk_shift": 0, "step_valid": 0, "step_axes": 0, "step_cost": 0, "drive_ready": 1}


class PacerTB(TB):
    async def restart(self):
        """rst, and the model and the bench's totals with it."""
        await self.reset(IDLE)
        self.ref.clock({**IDLE, "rst": 1})
        self.ref.inputs = {}
        self.total = self.charged = 0

    async def start(self):
        await self.reset(IDLE)
        self.feed_w = int(self.dut.FEED_W.value)
        self.frac = int(self.dut.FRAC.value)
        self.mw = int(self.dut.MW.value)
        self.guard = int(self.dut.GUARD.value)
        self.widest = (1 << self.feed_w) - 1     # the largest step_cost
        self.ref = StepPacer(self.feed_w, self.frac, self.mw, self.guard)
        self.ref.clock({**IDLE, "rst": 1})
        self.ref.inputs = {}
        self.total = 0          # sum of F given since reset
        self.charged = 0        # sum of cost << shift of the steps gone
        return self

    def need(self, step, shift):
        cost, axes = step
        return (cost or lecture_cost(axes, self.frac)) << min(shift, self.mw)

    async def run(self, steps, sums, shift=0, waiting=lambda c: 1, ready=lambda c: 1,
                  context="", tail=0):
        """steps: [(cost, axes)] offered in order (a step waits when waiting(c));
        sums(c): F of clock c.  Runs until every step left, then `tail` clocks.
        Returns (clocks at which the steps left, samples)."""
        fired = []
        queue = list(steps)

        def stim():
            sample = yield dict(IDLE, jerk_shift=shift)
            c = 0
            extra = tail
            while queue or extra > 0:
                if not queue:
                    extra -= 1
                offer = bool(queue) and bool(waiting(c))
                cost, axes = queue[0] if queue else (0, 0)
                go = int(bool(ready(c)))
                f = sums(c)
                inputs = {"sum": f, "jerk_shift": shift, "step_valid": int(offer),
                          "step_axes": axes, "step_cost": cost, "drive_ready": go}
                # phase in this clock is the sample's; the step leaves if due (one per clock)
                if offer and go and sample["phase"] >= self.need(queue[0], shift):
                    fired.append(c)
                    self.charged += self.need(queue.pop(0), shift)
                self.total += f
                sample = yield inputs
                assert sample["overrun"] or sample["phase"] == self.total - self.charged, \
                    f"{context}: clock {c}: phase {sample['phase']} != F given - charged"
                c += 1
                if c > 200_000:
                    raise AssertionError(f"{context}: steps left waiting: {len(queue)}")
            yield dict(IDLE, jerk_shift=shift)

        samples = await scoreboard(self, self.ref, stim(), context=context)
        return fired, samples


@cocotb.test()
async def golden_pace(dut):
    """Every step waiting, output always ready: the clocks equal the golden `pace`."""
    rng = seeded_rng(dut, "golden_pace")
    tb = await PacerTB(dut).start()
    one = 1 << tb.frac
    for shift in (0, 1, tb.mw):
        await tb.restart()
        steps = [(rng.choice([0, min(one // 2 + rng.randrange(one), tb.widest)]), rng.randint(1, 3)) for _ in range(25)]
        sums = [rng.randrange(one // 3 << shift) for _ in range(4000)]
        fired, _ = await tb.run(steps, lambda c: sums[c], shift, context=f"golden J {shift}")
        want, _ = pace([0] + sums, [tb.need(s, 0) for s in steps], shift)
        # the bench's clock 0 is the golden's clock 1 (phase 0 before it in both)
        assert fired == [w - 1 for w in want[: len(fired)]] and len(want) >= len(fired), \
            f"J {shift}: {fired[:6]} vs {want[:6]}"


@cocotb.test()
async def path_speed(dut):
    """Constant F: the interval after a step is cost << J / F (whole clocks, fraction carried)."""
    tb = await PacerTB(dut).start()
    one = 1 << tb.frac
    for shift, axes, cost in ((0, 1, 0), (0, 2, 0), (0, 3, 0), (2, 1, min(one + one // 3, tb.widest)), (tb.mw, 2, 0)):
        f = (one // 7) << shift
        steps = [(cost, axes)] * 30
        fired, _ = await tb.run(steps, lambda c: f, shift, context=f"speed J {shift} axes {axes}")
        need = tb.need(steps[0], shift)
        clocks = fired[-1] - fired[0]
        assert abs(clocks * f - 29 * need) < f, f"J {shift}: {clocks} clocks for 29 steps of {need}"
        gaps = {b - a for a, b in zip(fired, fired[1:])}
        assert gaps <= {need // f, need // f + 1}, gaps


@cocotb.test()
async def random_offers_hold_and_stalls(dut):
    """Random offers, output stage busy at random, F going to 0 (hold) and back:
    every step leaves once, in order; phase = F given - charged in every clock."""
    rng = seeded_rng(dut, "random_offers_hold_and_stalls")
    tb = await PacerTB(dut).start()
    one = 1 << tb.frac
    for round_ in range(4):
        shift = rng.randint(0, tb.mw)
        steps = []
        for _ in range(6):                                   # segments: one cost each
            cost = rng.choice([0, rng.randint(one // 2, min(2 * one, tb.widest))])
            steps += [(cost, rng.randint(1, 3)) for _ in range(rng.randint(1, 8))]
        level = [rng.randrange(one // 2) << shift]
        holds = sorted(rng.sample(range(3000), 6))

        def sums(c):
            if any(h <= c < h + 80 for h in holds):            # hold: F is 0 for a while
                return 0
            if rng.random() < 0.05:
                level[0] = rng.randrange(one // 2) << shift
            return level[0]

        fired, samples = await tb.run(steps, sums, shift, waiting=lambda c: rng.random() < 0.7,
                                      ready=lambda c: rng.random() < 0.8,
                                      context=f"random round {round_} J {shift}", tail=5)
        assert len(fired) == len(steps) and fired == sorted(set(fired)), "a step lost or doubled"
        assert not any(s["overrun"] for s in samples)


@cocotb.test()
async def no_step_waiting_keeps_distance(dut):
    """F runs while no step waits: the phase grows, then the steps leave one per clock."""
    tb = await PacerTB(dut).start()
    one = 1 << tb.frac
    steps = [(0, 1)] * 12
    fired, _ = await tb.run(steps, lambda c: one // 4, 0, waiting=lambda c: c >= 40,
                            context="late steps")
    # 40 clocks at 1/4 step per clock: 10 steps of credit, one per clock from clock 40
    assert fired[:10] == list(range(40, 50)), fired


@cocotb.test()
async def overrun_saturates(dut):
    """Far more F than steps for longer than the guard allows: phase saturates, overrun sticks."""
    tb = await PacerTB(dut).start()
    top = (1 << int(tb.ref.phase_w)) - 1
    big = (1 << (tb.feed_w + tb.mw)) - 1
    clocks = top // big + 3
    _, samples = await tb.run([(0, 1)], lambda c: big, 0, waiting=lambda c: c >= clocks,
                              context="overrun")
    assert any(s["overrun"] for s in samples) and samples[-1]["overrun"] == 1
    await tb.restart()
    assert int(dut.overrun.value) == 0 and int(dut.phase.value) == 0


@cocotb.test()
async def reset_mid_interval(dut):
    """rst between steps: phase 0, the next steps pace from scratch."""
    tb = await PacerTB(dut).start()
    one = 1 << tb.frac
    await tb.run([(0, 2)] * 3, lambda c: one // 5, 0, context="before reset", tail=3)
    await tb.restart()
    fired, _ = await tb.run([(0, 1)] * 3, lambda c: one // 5, 0, context="after reset")
    want, _ = pace([one // 5] * 40, [one] * 3)
    assert fired == want and want[0] == -(-one // (one // 5)), (fired, want)


def _run(sim, parameters, name, testcase=None):
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="step_pacer", test_module="test_step_pacer", sim=sim,
               parameters=parameters, name=name, testcase=testcase)


def test_step_pacer(sim):
    _run(sim, {"FEED_W": 16, "FRAC": 16, "MW": 6, "SUM_W": 22, "GUARD": 8}, "step_pacer")


def test_step_pacer_guard(sim):
    """One guard bit: the saturation is reached in a few clocks."""
    _run(sim, {"FEED_W": 12, "FRAC": 10, "MW": 2, "SUM_W": 14, "GUARD": 1}, "step_pacer_guard")


def test_step_pacer_wide(sim):
    """The G-code build's widths: FEED_W 34, FRAC 32, MW 12."""
    _run(sim, {"FEED_W": 34, "FRAC": 32, "MW": 12, "SUM_W": 46, "GUARD": 8}, "step_pacer_wide",
         ["golden_pace", "path_speed", "random_offers_hold_and_stalls"])
