"""The first-quadrant datapath under circ_std / circ_accel, tested on its own.

The wrappers' benches cover (ACCEL 0, WIDTH 8) and (ACCEL 1, WIDTH 32); this
one runs the shared tests on `circ_quadrant` itself at the remaining corner.
"""
from interp.quadrant_bench import *  # noqa: F401,F403  (the cocotb tests)
from interp.simulation.runner import run_cocotb


def test_circ_quadrant(sim):
    run_cocotb(toplevel="circ_quadrant", test_module="test_circ_quadrant", sim=sim,
               parameters={"WIDTH": 8, "ACCEL": 1}, name="circ_quadrant_w8_accel",
               testcase=["lecture_example", "exhaustive_small", "bad_commands"])
