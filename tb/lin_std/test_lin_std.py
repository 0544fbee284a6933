# SPDX-License-Identifier: Apache-2.0
"""Lecture's standard linear interpolator: RTL vs cycle model vs the lecture's equations.

The generic line tests are shared with lin_accel (interp/linear_bench.py).
"""
import cocotb
import pytest

from interp.testing.corecheck import moves
from interp.linear_bench import LinearSuite
from interp.models.lecture import LinStd, lin_std_steps
from interp.simulation.runner import run_cocotb


def one_axis_and_registers(tb, x, y, samples, got):
    """One axis per tick; registers 3, 4 move by exactly (x, y)."""
    assert all(not (dx and dy) for dx, dy, _ in got), "the standard algorithm steps one axis at a time"
    mask = (1 << tb.width) - 1
    before, end = samples[0], samples[-1]
    assert ((end["pos_x"] - before["pos_x"] - x) & mask, (end["pos_y"] - before["pos_y"] - y) & mask) == (0, 0)


suite = LinearSuite(LinStd, lin_std_steps, one_axis_and_registers, reset_cycles=14)
globals().update(suite.tests())     # the shared cocotb tests, bound here for cocotb to find


@cocotb.test()
async def lecture_example(dut):
    """dX = 5, dY = 3 worked by hand from the lecture's rules: X Y X Y X X Y X."""
    tb = await suite.setup(dut)
    samples = await suite.check_move(tb, 5, 3)
    assert [(dx, dy) for dx, dy, _ in moves(samples)] == [(1, 0), (0, 1), (1, 0), (0, 1), (1, 0), (1, 0), (0, 1), (1, 0)]
    assert [s["f"] for _, _, s in moves(samples)] == [-3, 2, -1, 4, 1, -2, 3, 0]


@pytest.mark.parametrize("width", [8, 32])
def test_lin_std(sim, width):
    run_cocotb(toplevel="lin_std", test_module="test_lin_std", sim=sim,
               parameters={"WIDTH": width}, name=f"lin_std_w{width}")
