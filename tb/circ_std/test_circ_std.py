"""The lecture's std circular interpolator: RTL vs cycle model vs the lecture's equations.

The cocotb tests are shared with the other first-quadrant core (interp/quadrant_bench.py).
"""
import pytest

from interp.quadrant_bench import *  # noqa: F401,F403  (the cocotb tests)
from interp.simulation.runner import run_cocotb


@pytest.mark.parametrize("width", [8])
def test_circ_std(sim, width):
    run_cocotb(toplevel="circ_std", test_module="test_circ_std", sim=sim,
               parameters={"WIDTH": width}, name=f"circ_std_w{width}")
