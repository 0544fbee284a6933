# SPDX-License-Identifier: Apache-2.0
"""Lecture's accelerated linear interpolator: RTL vs cycle model vs the lecture's equations.

The generic line tests are shared with lin_std (interp/linear_bench.py).
"""
import cocotb
import pytest

from interp.testing.corecheck import moves
from interp.linear_bench import LinearSuite
from interp.models.lecture import LinAccel, lin_accel_steps
from interp.simulation.runner import run_cocotb


def one_step_per_tick(tb, x, y, samples, got):
    assert len(got) == max(abs(x), abs(y)), "one step per tick along the leading axis"


suite = LinearSuite(LinAccel, lin_accel_steps, one_step_per_tick, reset_cycles=10)
globals().update(suite.tests())     # the shared cocotb tests, bound here for cocotb to find


@cocotb.test()
async def lecture_example(dut):
    """dX = 5, dY = 3 worked by hand from the lecture's rules: X D D X D, F -3 -1 1 -2 0."""
    tb = await suite.setup(dut)
    samples = await suite.check_move(tb, 5, 3)
    assert [(dx, dy) for dx, dy, _ in moves(samples)] == [(1, 0), (1, 1), (1, 1), (1, 0), (1, 1)]
    assert [s["f"] for _, _, s in moves(samples)] == [-3, -1, 1, -2, 0]
    samples = await suite.check_move(tb, -4, -4)                   # 45 degrees: all diagonal
    assert [(dx, dy) for dx, dy, _ in moves(samples)] == [(-1, -1)] * 4


@pytest.mark.parametrize("width", [8, 32])
def test_lin_accel(sim, width):
    run_cocotb(toplevel="lin_accel", test_module="test_lin_accel", sim=sim,
               parameters={"WIDTH": width}, name=f"lin_accel_w{width}")
