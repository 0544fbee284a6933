# SPDX-License-Identifier: Apache-2.0
"""SU 1571551 linear interpolator: RTL vs cycle model vs the patent's equations.

The same benches run on the patent's circuit (su1571551, faithful and exact
mode) and on the production core lin_exact (the exact mode retimed, with the
portable and the iCE40 file list): one cycle model (interp/models/su1571551.py)
for all of them, compared in every cycle."""
import cocotb
import pytest

from interp.testing import corecheck
from interp.flows import synth
from interp.testing.corecheck import CoreTB, moves, start_while_busy
from interp.models.su1571551 import Su1571551, steps
from interp.simulation.runner import run_cocotb
from interp.testing.tbkit import seeded_rng

# make test runs this bench on Verilator alone, its faster simulator (make test-all: both)
QUICK_SIMULATOR = "verilator"

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


class LinearTB(CoreTB):
    def __init__(self, dut):
        self.width = int(dut.WIDTH.value)
        # lin_exact has no EXACT parameter: it is the exact mode
        self.exact = not hasattr(dut, "EXACT") or bool(int(dut.EXACT.value))
        self.mode = "exact" if self.exact else "faithful"
        super().__init__(dut, IDLE, lambda: Su1571551(self.width, self.exact))

    async def check_move(self, x, y, tick=lambda c: 1):
        """Scoreboard one whole move; check the steps against the equations."""
        samples = await self.run({"x": x, "y": y}, tick, context=f"{self.mode} ({x}, {y})")
        want = steps(x, y, self.mode)
        got = moves(samples)
        assert len(got) == len(want), f"({x}, {y}): {len(got)} steps, want {len(want)}"
        for n, ((dx, dy, s), w) in enumerate(zip(got, want)):
            assert (dx, dy, s["f"], s["ctr1"], s["ctr2"] + 1) == (w.dx, w.dy, w.f2, w.ctr1, w.ctr2), \
                f"({x}, {y}) step {n + 1}: rtl {s}, equations {w}"
        assert sum(abs(dx) for dx, _, _ in got) == abs(x) and sum(abs(dy) for _, dy, _ in got) == abs(y)
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
        got = [("diagonal" if dx and dy else "axial", s["f"] / 2, s["ctr1"], s["ctr2"] + 1)
               for dx, dy, s in moves(samples)]
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
    rng = seeded_rng(dut, "random_full_width")
    tb = await setup(dut)
    lo, hi = -(1 << (tb.width - 1)), (1 << (tb.width - 1)) - 1
    edges = [lo, lo + 1, -1, 0, 1, hi - 1, hi]
    vectors = [(a, b) for a in edges for b in edges]
    vectors += [(rng.randint(lo, hi), rng.randint(lo, hi)) for _ in range(60)]
    for x, y in vectors:
        await tb.run_cut({"x": x, "y": y}, 150, context=f"full width ({x}, {y})")
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
    """start held high with another move during a move changes nothing."""
    tb = await setup(dut)
    samples = await start_while_busy(tb, {"x": 9, "y": -4}, {"x": -20, "y": 20})
    assert sum(s["step_x"] for s in samples) == 9 and sum(s["step_y"] for s in samples) == 4


@cocotb.test()
async def reset_at_any_cycle(dut):
    """rst in any cycle of a move returns to idle; no step after it."""
    tb = await setup(dut)
    await corecheck.reset_at_any_cycle(tb, {"x": 11, "y": 6}, 11 + 5)


@pytest.mark.parametrize("width, mode", [(8, "faithful"), (32, "faithful"), (8, "exact"), (32, "exact")])
def test_su1571551(sim, width, mode):
    run_cocotb(toplevel="su1571551", test_module="test_su1571551", sim=sim,
               parameters={"WIDTH": width, "EXACT": int(mode == "exact")},
               name=f"su1571551_w{width}_{mode}")


# lin_exact: the portable file list (one carry chain per adder, operand_mux kept
# as its own module: the ECP5 build) and the iCE40 one (rtl/ice40/carry_select_add.v,
# carry select, and rtl/ice40/operand_mux.v, merged).
@pytest.mark.parametrize("width, family", [(8, None), (32, None), (32, "ice40")])
def test_lin_exact(sim, width, family):
    run_cocotb(toplevel="lin_exact", test_module="test_su1571551", sim=sim,
               parameters={"WIDTH": width}, name=f"lin_exact_w{width}_{family or 'portable'}",
               sources=synth.sources("lin_exact", family))
