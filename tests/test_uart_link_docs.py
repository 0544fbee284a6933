# SPDX-License-Identifier: Apache-2.0
"""docs/link-protocol.md and docs/cores/uart_link.md stay true: every example frame is a
well-formed frame of its TYPE (LEN, CRC), the CRC worked example's steps are the CRC's,
the datasheet's ports table is rtl/uart_link.v's ports.  Each check is also shown to fail
on a broken copy."""
from __future__ import annotations

import re

import pytest

from interp import docs
from interp.testing.linkkit import crc16, frame

ROOT = docs.ROOT
PROTOCOL = ROOT / "docs" / "link-protocol.md"
TYPES = {"HELLO": 0x01, "DATA": 0x02, "READ": 0x03, "WRITE": 0x04, "ACK": 0x81, "NAK": 0x82, "REPLY": 0x83}
EXAMPLE = re.compile(r"^([A-Z]+)\s.*?\s((?:[0-9a-f]{2} )+[0-9a-f]{2})$")
CRC_STEP = re.compile(r"^\| 0x([0-9A-F]{2}) \(\w+\) \| 0x([0-9A-F]{4}) \|$")


def example_frames(text: str) -> list[tuple[str, bytes]]:
    block = text.split("## Example exchanges", 1)[1].split("```")[1]
    return [(m.group(1), bytes.fromhex(m.group(2))) for m in map(EXAMPLE.match, block.splitlines()) if m]


def frame_problems(text: str) -> list[str]:
    problems = []
    examples = example_frames(text)
    if len(examples) < 7:
        problems.append(f"only {len(examples)} example frames")
    for name, raw in examples:
        if raw[0] != 0xA5 or raw[1] + 6 != len(raw) or raw[2] != TYPES.get(name):
            problems.append(f"{name}: bad SYNC, LEN or TYPE: {raw.hex(' ')}")
        elif crc16(raw[1:-2]) != int.from_bytes(raw[-2:], "big"):
            problems.append(f"{name}: bad CRC: {raw.hex(' ')}")
    return problems


def crc_problems(text: str) -> list[str]:
    steps = [(int(m.group(1), 16), int(m.group(2), 16))
             for m in map(CRC_STEP.match, text.splitlines()) if m]
    message = bytes(b for b, _ in steps)
    problems = [] if len(steps) == 3 else [f"{len(steps)} CRC steps in the worked example"]
    for n, (_, value) in enumerate(steps):
        if crc16(message[:n + 1]) != value:
            problems.append(f"CRC after {message[:n + 1].hex(' ')}: {value:#06x} != {crc16(message[:n + 1]):#06x}")
    if frame(0x01, 0).hex(" ") not in text:
        problems.append("the worked example's frame is not HELLO SEQ 0")
    return problems


def test_example_frames_are_frames():
    assert frame_problems(PROTOCOL.read_text()) == []


def test_crc_worked_example():
    text = PROTOCOL.read_text()
    assert "| (start) | 0xFFFF |" in text
    assert crc_problems(text) == []


def test_checks_catch_a_broken_copy():
    text = PROTOCOL.read_text()
    assert frame_problems(text.replace("a5 00 01 00 ff ad", "a5 00 01 00 ff ae"))
    assert frame_problems(text.replace("a5 02 03 00 18 00 44 89", "a5 02 03 00 18 01 44 89"))
    assert crc_problems(text.replace("| 0x0D2E |", "| 0x0D2F |"))


@pytest.mark.parametrize("module", ["uart_link"])
def test_ports_table(module):
    assert docs.ports_diff(module) == []
