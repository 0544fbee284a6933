"""SU 1571551 linear interpolator: RTL vs cycle model vs the patent's equations."""
import os
import random

import cocotb
import pytest
from cocotb.triggers import FallingEdge

from interp.models.base import drive, move, steps_of
from interp.models.su1571551 import Su1571551, steps
from interp.sim import run_cocotb
from interp.tbkit import TB, scoreboard

# The patent's table, |X| = 7, |Y| = 3: (kind, F after, counter 1, counter 2).
PATENT_TABLE = [
    ("axial", -2.5, 3, 3), ("diagonal", 0.5, 3, 2), ("axial", -1.5, 2, 2),
    ("diagonal", 0.5, 2, 1), ("axial", -0.5, 1, 1), ("diagonal", 0.5, 1, 0),
    ("axial", 0.5, 0, 0),
]
# The same move by expression (1): the same steps, F moves by the held S and L - S.
EXACT_TABLE = [
    ("axial", -2.5, 3, 3), ("diagonal", 1.5, 3, 2), ("axial", -1.5, 2, 2),
    ("diagonal", 2.5, 2, 1), ("axial", -0.5, 1, 1), ("diagonal", 3.5, 1, 0),
    ("axial", 0.5, 0, 0),
]
IDLE = {"start": 0, "tick": 0, "x": 0, "y": 0}


class LinearTB(TB):
    def __init__(self, dut):
        super().__init__(dut)
        self.width = int(dut.WIDTH.value)
        self.exact = bool(int(dut.EXACT.value))
        self.mode = "exact" if self.exact else "faithful"

    async def reset(self, idle=IDLE, cycles=2):
        await super().reset(idle, cycles)
        self.ref = Su1571551(self.width, self.exact)   # the model follows the DUT across moves

    async def check_move(self, x, y, tick=lambda c: 1):
        """Scoreboard one whole move; check the steps against the equations."""
        samples = await scoreboard(self, self.ref, move({"x": x, "y": y}, tick),
                                   context=f"{self.mode} ({x}, {y})")
        want = steps(x, y, self.mode)
        got = [s for s in samples if s["step_x"] or s["step_y"]]
        assert len(got) == len(want), f"({x}, {y}): {len(got)} steps, want {len(want)}"
        for n, (s, w) in enumerate(zip(got, want)):
            dx = (-1 if s["dir_x"] else 1) * s["step_x"]
            dy = (-1 if s["dir_y"] else 1) * s["step_y"]
            assert (dx, dy, s["f"], s["ctr1"], s["ctr2"] + 1) == (w.dx, w.dy, w.f2, w.ctr1, w.ctr2), \
                f"({x}, {y}) step {n + 1}: rtl {s}, equations {w}"
        assert sum(s["step_x"] for s in got) == abs(x) and sum(s["step_y"] for s in got) == abs(y)
        return samples


async def setup(dut):
    tb = LinearTB(dut)
    await tb.reset()
    return tb


@cocotb.test()
async def patent_table(dut):
    """|X| = 7, |Y| = 3 in all four quadrants reproduces the patent's table."""
    tb = await setup(dut)
    table = EXACT_TABLE if tb.exact else PATENT_TABLE
    for x, y in [(7, 3), (-7, 3), (7, -3), (-7, -3), (3, 7)]:
        samples = await tb.check_move(x, y)
        rows = [s for s in samples if s["step_x"] or s["step_y"]]
        got = [("diagonal" if s["step_x"] and s["step_y"] else "axial", s["f"] / 2, s["ctr1"], s["ctr2"] + 1)
               for s in rows]
        assert got == table, f"({x}, {y}): {got}"


@cocotb.test()
async def exhaustive_small(dut):
    """Every |X|, |Y| <= 32 with all four sign combinations."""
    tb = await setup(dut)
    r = min(32, (1 << (tb.width - 1)) - 1)
    for x in range(-r, r + 1):
        for y in range(-r, r + 1):
            await tb.check_move(x, y)


@cocotb.test()
async def random_full_width(dut):
    """Random full-width vectors: the first cycles of each move, then reset."""
    seed = int(os.environ.get("SEED", random.randrange(1 << 32)))
    dut._log.info("random_full_width seed=%d (re-run with SEED=%d)", seed, seed)
    rng = random.Random(seed)
    tb = await setup(dut)
    lo, hi = -(1 << (tb.width - 1)), (1 << (tb.width - 1)) - 1
    edges = [lo, lo + 1, -1, 0, 1, hi - 1, hi]
    vectors = [(a, b) for a in edges for b in edges]
    vectors += [(rng.randint(lo, hi), rng.randint(lo, hi)) for _ in range(60)]
    for x, y in vectors:
        stim = move({"x": x, "y": y}, max_cycles=150)
        try:
            await scoreboard(tb, tb.ref, stim, context=f"full width ({x}, {y})")
        except RuntimeError:
            pass                              # move not finished: cut it short
        await tb.reset()
    # and whole moves of random length at full-width positions of the sign bits
    for _ in range(30):
        x, y = rng.randint(max(lo, -300), min(hi, 300)), rng.randint(max(lo, -300), min(hi, 300))
        await tb.check_move(x, y, tick=lambda c: rng.random() < 0.7)


@cocotb.test()
async def zero_length(dut):
    """X = Y = 0: done at once, no step."""
    tb = await setup(dut)
    samples = await tb.check_move(0, 0)
    assert not any(s["step_x"] or s["step_y"] for s in samples)
    assert sum(s["done"] for s in samples) == 1


@cocotb.test()
async def start_while_busy_is_ignored(dut):
    """A second start during a move changes nothing: the first move completes."""
    tb = await setup(dut)

    def stim():
        sample = yield {"x": 9, "y": -4, "start": 1, "tick": 1}
        cycle = 1
        while not sample["done"]:
            sample = yield {"x": -20, "y": 20, "start": int(cycle % 3 == 0), "tick": 1}
            cycle += 1
        yield {"x": 0, "y": 0, "start": 0, "tick": 1}

    samples = await scoreboard(tb, tb.ref, stim(), context="start while busy")
    assert steps_of(samples) and sum(s["step_x"] for s in samples) == 9
    assert sum(s["step_y"] for s in samples) == 4


@cocotb.test()
async def reset_at_any_cycle(dut):
    """rst in any cycle of a move returns to idle; no step after it."""
    tb = await setup(dut)
    x, y = 11, 6
    for k in range(0, 11 + 5):
        await tb.reset()
        stim = move({"x": x, "y": y}, max_cycles=k)
        try:
            await scoreboard(tb, tb.ref, stim, context=f"reset at {k}")
        except RuntimeError:
            pass
        tb.drive({"rst": 1, "start": 0})
        await FallingEdge(dut.clk)
        tb.drive({"rst": 0, "tick": 1})
        for _ in range(20):
            await FallingEdge(dut.clk)
            s = tb.sample(Su1571551.watch)
            assert not (s["step_x"] or s["step_y"] or s["busy"] or s["done"]), f"reset at {k}: {s}"


@pytest.mark.parametrize("width", [8, 32])
@pytest.mark.parametrize("mode", ["faithful", "exact"])
def test_su1571551(sim, width, mode):
    run_cocotb(toplevel="su1571551", test_module="test_su1571551", sim=sim,
               parameters={"WIDTH": width, "EXACT": int(mode == "exact")},
               name=f"su1571551_w{width}_{mode}")
