# SPDX-License-Identifier: Apache-2.0
"""pytest set-up shared by every bench: `make test` runs each bench on one simulator
(Icarus, or the bench's QUICK_SIMULATOR where that one is faster), `make test-all`
(INTERP_TEST_ALL=1) on both; --sim chooses."""
import os

from interp.simulation.runner import SIMULATORS


def pytest_addoption(parser):
    parser.addoption("--sim", action="append", choices=SIMULATORS,
                     help="run on this simulator only (repeatable; default: make test one, make test-all all)")


def pytest_generate_tests(metafunc):
    if "sim" in metafunc.fixturenames:
        sims = metafunc.config.getoption("sim")
        if not sims:
            sims = list(SIMULATORS) if os.environ.get("INTERP_TEST_ALL") else \
                [getattr(metafunc.module, "QUICK_SIMULATOR", "icarus")]
        metafunc.parametrize("sim", sims)
