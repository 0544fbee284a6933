# SPDX-License-Identifier: Apache-2.0
"""The lecture's first-quadrant circular interpolator, rtl/circ_quadrant.v: RTL vs cycle
model vs the lecture's equations, in both forms: standard (ACCEL = 0, the CLI's
circ-std) and accelerated (ACCEL = 1, circ-accel).  The tests are
interp/quadrant_bench.py's."""
import pytest

from interp.quadrant_bench import quadrant_suite
from interp.simulation.runner import run_cocotb

# make test runs this bench on Verilator alone, its faster simulator (make test-all: both)
QUICK_SIMULATOR = "verilator"

globals().update(quadrant_suite())      # the cocotb tests, bound here for cocotb to find


@pytest.mark.parametrize("width, accel", [(8, 0), (32, 1), (8, 1)])
def test_circ_quadrant(sim, width, accel):
    # (8, 1) only adds the accelerated octant logic at the small width
    testcase = ["lecture_example", "exhaustive_small", "bad_commands"] if (width, accel) == (8, 1) else None
    run_cocotb(toplevel="circ_quadrant", test_module="test_circ_quadrant", sim=sim,
               parameters={"WIDTH": width, "ACCEL": accel},
               name=f"circ_quadrant_w{width}_{'accel' if accel else 'std'}", testcase=testcase)
