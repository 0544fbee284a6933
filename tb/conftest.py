# SPDX-License-Identifier: Apache-2.0
"""pytest set-up shared by every bench: each bench runs on both simulators."""
from interp.simulation.runner import SIMULATORS


def pytest_addoption(parser):
    parser.addoption("--sim", action="append", choices=SIMULATORS,
                     help="run on this simulator only (repeatable; default: all)")


def pytest_generate_tests(metafunc):
    if "sim" in metafunc.fixturenames:
        sims = metafunc.config.getoption("sim") or list(SIMULATORS)
        metafunc.parametrize("sim", sims)
