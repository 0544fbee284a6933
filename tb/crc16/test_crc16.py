# SPDX-License-Identifier: Apache-2.0
"""crc16: CRC-16/CCITT-FALSE one byte per clock against crcmod; a frame's CRC appended leaves 0."""

import cocotb
import pytest

from interp.simulation.runner import run_cocotb
from interp.testing.linkkit import crc16 as reference
from interp.testing.linkkit import FAST_CLOCK
from interp.testing.tbkit import TB, seeded_rng

IDLE = {"clear": 0, "valid": 0, "data": 0}


async def shift(tb, message: bytes, rng=None) -> int:
    """Clear, then shift `message` in (random idle clocks between bytes); the CRC after it."""
    first = True
    for byte in message:
        while rng and rng.random() < 0.3:
            await tb.tick({**IDLE})
        await tb.tick({"clear": int(first), "valid": 1, "data": byte})
        first = False
    if not message:
        await tb.tick({**IDLE, "clear": 1})
    await tb.tick({**IDLE})
    return int(tb.dut.crc.value)


@cocotb.test()
async def check_value(dut):
    """The standard check string and the documented HELLO frame's CRC."""
    tb = TB(dut)
    await tb.reset(IDLE)
    assert int(dut.crc.value) == 0xFFFF, "reset value"
    assert await shift(tb, b"123456789") == 0x29B1
    assert await shift(tb, bytes([0x00, 0x01, 0x00])) == 0xFFAD == reference(bytes([0, 1, 0]))
    assert await shift(tb, b"") == 0xFFFF


@cocotb.test()
async def random_messages(dut):
    """Random messages with idle clocks between bytes; residue 0 after the CRC (high byte first)."""
    rng = seeded_rng(dut, "random_messages")
    tb = TB(dut)
    await tb.reset(IDLE)
    for n in range(60):
        message = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 40)))
        want = reference(message)
        got = await shift(tb, message, rng)
        assert got == want, f"message {n} {message.hex()}: {got:#06x} != {want:#06x}"
        assert await shift(tb, message + want.to_bytes(2, "big"), rng) == 0, "residue"


@cocotb.test()
async def clear_with_byte(dut):
    """`clear` and `valid` together start a new message with that byte (no idle clock needed)."""
    tb = TB(dut)
    await tb.reset(IDLE)
    await shift(tb, b"abc")
    await tb.tick({"clear": 1, "valid": 1, "data": ord("x")})
    await tb.tick({"clear": 0, "valid": 1, "data": ord("y")})
    await tb.tick({**IDLE})
    assert int(dut.crc.value) == reference(b"xy")


@pytest.mark.parametrize("simulator", ["icarus", pytest.param("verilator", marks=pytest.mark.slow)])
def test_crc16(simulator):
    run_cocotb(toplevel="crc16", test_module="test_crc16", sim=simulator, env=FAST_CLOCK)
