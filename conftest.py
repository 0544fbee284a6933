# SPDX-License-Identifier: Apache-2.0
"""pytest set-up for tb/ and tests/: `slow` tests (long sweeps) run only in `make test-all`."""
import os

import pytest


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: a long sweep, run by `make test-all` (INTERP_TEST_ALL=1)")


def pytest_collection_modifyitems(config, items):
    if os.environ.get("INTERP_TEST_ALL"):
        return
    skip = pytest.mark.skip(reason="a long sweep: run with `make test-all`")
    for item in items:
        if "slow" in item.keywords:
            item.add_marker(skip)
