# SPDX-License-Identifier: Apache-2.0
"""uart_tx: the line clock by clock equals the ideal 8N1 waveform; bytes offered back to back
leave without a gap; random bytes at random times reach cocotbext-uart's UartSink intact."""

import cocotb
import pytest
from cocotb.triggers import Timer
from cocotbext.uart import UartSink

from interp.simulation.runner import run_cocotb
from interp.testing.linkkit import FAST_CLOCK
from interp.testing.tbkit import TB, seeded_rng

PERIOD_NS = 10
IDLE = {"valid": 0, "data": 0}


def waveform(data: bytes, clocks: int) -> list[int]:
    out = []
    for byte in data:
        for level in [0] + [(byte >> i) & 1 for i in range(8)] + [1]:
            out += [level] * clocks
    return out


@cocotb.test()
async def exact_waveform(dut):
    """Three bytes offered back to back: the line equals the ideal waveform, clock for clock."""
    tb = TB(dut, PERIOD_NS)
    await tb.reset(IDLE)
    clocks = int(dut.CLKS_PER_BIT.value)
    assert int(dut.tx.value) == 1 and int(dut.ready.value) == 1
    data = bytes([0x55, 0x00, 0xF1])
    line, taken = [], []
    pending = list(data)
    for _ in range(len(data) * 10 * clocks + 3 * clocks):
        inputs = {"valid": 1, "data": pending[0]} if pending else IDLE
        if pending and int(dut.ready.value):
            taken.append(pending.pop(0))
        await tb.tick(inputs)
        line.append(int(dut.tx.value))
    assert bytes(taken) == data
    want = waveform(data, clocks) + [1] * (3 * clocks)
    assert line == want, f"line {line} != {want}"


@cocotb.test()
async def random_bytes(dut):
    """200 random bytes offered at random times reach UartSink in order."""
    rng = seeded_rng(dut, "random_bytes")
    tb = TB(dut, PERIOD_NS)
    await tb.reset(IDLE)
    bit_ns = PERIOD_NS * int(dut.CLKS_PER_BIT.value)
    sink = UartSink(dut.tx, baud=round(1e9 / bit_ns), bits=8)
    data = bytes(rng.randrange(256) for _ in range(200))
    pending = list(data)
    while pending:
        if rng.random() < 0.2:
            await tb.tick(IDLE)
            continue
        inputs = {"valid": 1, "data": pending[0]}
        if int(dut.ready.value):
            pending.pop(0)
        await tb.tick(inputs)
    await tb.tick(IDLE)
    await Timer(12 * bit_ns, "ns")
    got = sink.read_nowait()
    assert bytes(got) == data


@pytest.mark.parametrize("clocks", [4, 9])
@pytest.mark.parametrize("simulator", ["icarus", pytest.param("verilator", marks=pytest.mark.slow)])
def test_uart_tx(simulator, clocks):
    run_cocotb(toplevel="uart_tx", test_module="test_uart_tx", sim=simulator,
               parameters={"CLKS_PER_BIT": clocks}, name=f"uart_tx_{clocks}",
               env=FAST_CLOCK)
