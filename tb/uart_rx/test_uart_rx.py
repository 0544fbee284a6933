# SPDX-License-Identifier: Apache-2.0
"""uart_rx: bytes from cocotbext-uart's UartSource arrive intact; framing errors drop the
byte and are reported; glitches shorter than half a bit are ignored; +-3 % baud error is taken."""

import cocotb
import pytest
from cocotb.triggers import FallingEdge, Timer
from cocotbext.uart import UartSource

from interp.simulation.runner import run_cocotb
from interp.testing.linkkit import FAST_CLOCK
from interp.testing.tbkit import TB, seeded_rng

PERIOD_NS = 10


class Monitor:
    """Collects received bytes and framing errors, clock by clock."""

    def __init__(self, dut):
        self.dut, self.bytes, self.errors = dut, [], 0
        cocotb.start_soon(self.run())

    async def run(self):
        while True:
            await FallingEdge(self.dut.clk)
            if int(self.dut.valid.value):
                self.bytes.append(int(self.dut.data.value))
            if int(self.dut.frame_error.value):
                self.errors += 1


async def setup(dut):
    tb = TB(dut, PERIOD_NS)
    dut.rx.value = 1
    await tb.reset({})
    bit_ns = PERIOD_NS * int(dut.CLKS_PER_BIT.value)
    return tb, Monitor(dut), bit_ns


async def send_bits(dut, byte: int, bit_ns: float, stop: int = 1):
    """One character driven by hand: start bit, 8 data bits LSB first, the given stop bit."""
    for level in [0] + [(byte >> i) & 1 for i in range(8)] + [stop]:
        dut.rx.value = level
        await Timer(round(bit_ns * 1000), "ps")
    dut.rx.value = 1


@cocotb.test()
async def random_bytes(dut):
    """300 random bytes back to back from UartSource."""
    rng = seeded_rng(dut, "random_bytes")
    tb, mon, bit_ns = await setup(dut)
    source = UartSource(dut.rx, baud=round(1e9 / bit_ns), bits=8)
    data = bytes(rng.randrange(256) for _ in range(300))
    await source.write(data)
    await source.wait()
    await Timer(3 * bit_ns, "ns")
    assert bytes(mon.bytes) == data
    assert mon.errors == 0


@cocotb.test()
async def framing_error(dut):
    """A stop bit 0 drops the byte and pulses frame_error once; after a break the next byte is good."""
    tb, mon, bit_ns = await setup(dut)
    await send_bits(dut, 0x5A, bit_ns, stop=0)
    await Timer(2 * bit_ns, "ns")
    assert mon.bytes == [] and mon.errors == 1
    dut.rx.value = 0                            # a break: the line low for 30 bits
    await Timer(30 * bit_ns, "ns")
    dut.rx.value = 1
    await Timer(2 * bit_ns, "ns")
    assert mon.bytes == [] and mon.errors == 2, "a break is one framing error"
    await send_bits(dut, 0xC3, bit_ns)
    await Timer(2 * bit_ns, "ns")
    assert mon.bytes == [0xC3] and mon.errors == 2


@cocotb.test()
async def glitch_ignored(dut):
    """A low pulse shorter than half a bit is no start bit."""
    tb, mon, bit_ns = await setup(dut)
    clocks = int(dut.CLKS_PER_BIT.value)
    for width in range(1, clocks // 2):
        dut.rx.value = 0
        await Timer(width * PERIOD_NS, "ns")
        dut.rx.value = 1
        await Timer(2 * bit_ns, "ns")
    assert mon.bytes == [] and mon.errors == 0
    await send_bits(dut, 0x81, bit_ns)
    await Timer(2 * bit_ns, "ns")
    assert mon.bytes == [0x81]


@cocotb.test()
async def baud_error(dut):
    """Senders 3 % slow and 3 % fast (2 % at 4 clocks per bit: a clock is a quarter bit), bytes back to back."""
    rng = seeded_rng(dut, "baud_error")
    tb, mon, bit_ns = await setup(dut)
    data = [rng.randrange(256) for _ in range(40)]
    error = 0.03 if int(dut.CLKS_PER_BIT.value) >= 7 else 0.02
    for factor in (1 + error, 1 - error):
        mon.bytes.clear()
        for byte in data:
            await send_bits(dut, byte, bit_ns * factor)
        await Timer(2 * bit_ns, "ns")
        assert mon.bytes == data, f"bit time x{factor}"
    assert mon.errors == 0


@pytest.mark.parametrize("clocks", [4, 7])
@pytest.mark.parametrize("simulator", ["icarus", pytest.param("verilator", marks=pytest.mark.slow)])
def test_uart_rx(simulator, clocks):
    run_cocotb(toplevel="uart_rx", test_module="test_uart_rx", sim=simulator,
               parameters={"CLKS_PER_BIT": clocks}, name=f"uart_rx_{clocks}",
               env=FAST_CLOCK)
