# SPDX-License-Identifier: Apache-2.0
"""Test helpers for the UART link's benches (tb/uart_link, tb/frame_rx, tb/frame_tx, ...).

Frames as docs/link-protocol.md defines them, a receiver for the controller's
answers, and `FrameRxModel`, a byte-level reference of rtl/frame_rx.v's decisions
(what each frame is answered with, which payload bytes are released), for a
receiver that is never busy (payload released before the next frame's payload).
"""
from __future__ import annotations

import crcmod.predefined

SYNC = 0xA5
HELLO, DATA, READ, WRITE = 0x01, 0x02, 0x03, 0x04
ACK, NAK, REPLY = 0x81, 0x82, 0x83
NAK_FRAME, NAK_GAP, NAK_CREDIT, NAK_TYPE = 1, 2, 3, 4
LMAX = 128
# run_cocotb's env for these benches: cocotb's clock in C instead of a Python coroutine
# (about 3x faster; the benches drive at falling edges, where inertial writes are safe).
FAST_CLOCK = {"COCOTB_TRUST_INERTIAL_WRITES": 1}

crc16 = crcmod.predefined.mkPredefinedCrcFun("crc-ccitt-false")


def frame(kind: int, seq: int, payload: bytes = b"") -> bytes:
    """One frame: SYNC LEN TYPE SEQ PAYLOAD CRC_HI CRC_LO."""
    body = bytes([len(payload) & 0xFF, kind, seq & 0xFF]) + bytes(payload)
    return bytes([SYNC]) + body + crc16(body).to_bytes(2, "big")


def read_frame(seq: int, address: int) -> bytes:
    return frame(READ, seq, address.to_bytes(2, "little"))


def write_frame(seq: int, address: int, value: int) -> bytes:
    return frame(WRITE, seq, address.to_bytes(2, "little") + (value & 0xFFFFFFFF).to_bytes(4, "little"))


class AnswerParser:
    """Splits the controller's byte stream into good frames (kind, seq, payload); counts bad ones."""

    def __init__(self):
        self.buffer = bytearray()
        self.frames: list[tuple[int, int, bytes]] = []
        self.bad = 0

    def feed(self, data: bytes) -> list[tuple[int, int, bytes]]:
        self.buffer += data
        new = []
        while True:
            start = self.buffer.find(bytes([SYNC]))
            if start < 0:
                self.buffer.clear()
                break
            del self.buffer[:start]
            if len(self.buffer) < 2:
                break
            size = self.buffer[1] + 6
            if len(self.buffer) < size:
                break
            raw = bytes(self.buffer[:size])
            if crc16(raw[1:-2]) == int.from_bytes(raw[-2:], "big"):
                new.append((raw[2], raw[3], raw[4:-2]))
                del self.buffer[:size]
            else:
                self.bad += 1
                del self.buffer[:1]
        self.frames += new
        return new


def ack_fields(payload: bytes) -> dict:
    return {"free": int.from_bytes(payload[0:2], "little"), "state": payload[2], "error": payload[3]}


def nak_fields(payload: bytes) -> dict:
    return {"reason": payload[0], "free": int.from_bytes(payload[1:3], "little")}


def reply_fields(payload: bytes) -> dict:
    return {"address": int.from_bytes(payload[0:2], "little"), "value": int.from_bytes(payload[2:6], "little")}


class FrameRxModel:
    """What rtl/frame_rx.v does with a byte stream (never busy, `free` credit bytes).

    feed(byte, gap): `gap` = clocks without a byte before this one (a frame
    open for `timeout` clocks or more is dropped first).  Returns the events of
    this byte: ("answer", reason) (0 = ACK), ("read", address, seq),
    ("write", address, value); `released` collects the released payload bytes.
    """

    def __init__(self, lmax: int = LMAX, timeout: int = 1 << 30, free: int = 1 << 16):
        self.lmax, self.timeout, self.free = lmax, timeout, free
        self.expected = 0
        self.released = bytearray()
        self.state = "hunt"
        self.body = bytearray()

    def error(self) -> list:
        """A framing error (a byte lost) reported by the UART receiver."""
        if self.state != "hunt":
            self.state = "hunt"
            return [("answer", NAK_FRAME)]
        return []

    def feed(self, byte: int, gap: int = 0) -> list:
        events = []
        if self.state != "hunt" and gap >= self.timeout:
            self.state = "hunt"
            events.append(("answer", NAK_FRAME))
        if self.state == "hunt":
            if byte == SYNC:
                self.state, self.body = "frame", bytearray()
            return events
        self.body.append(byte)
        if len(self.body) == 1 and byte > self.lmax:
            self.state = "hunt"
            return events + [("answer", NAK_FRAME)]
        if len(self.body) < 3 or len(self.body) < self.body[0] + 5:
            return events
        self.state = "hunt"
        return events + self.decide(bytes(self.body))

    def decide(self, body: bytes) -> list:
        length, kind, seq, payload = body[0], body[1], body[2], body[3:-2]
        if crc16(body[:-2]) != int.from_bytes(body[-2:], "big"):
            return [("answer", NAK_FRAME)]
        if not ((kind == HELLO and length == 0) or kind == DATA or (kind == READ and length == 2)
                or (kind == WRITE and length == 6)):
            return [("answer", NAK_TYPE)]
        if kind == HELLO:
            return [("answer", 0)]
        address = int.from_bytes(payload[0:2], "little")
        if kind == READ:
            return [("read", address, seq)]
        distance = (seq - self.expected) % 256
        if distance >= 128:
            return [("answer", 0)]
        if distance:
            return [("answer", NAK_GAP)]
        if kind == DATA and length > self.free:
            return [("answer", NAK_CREDIT)]
        self.expected = (self.expected + 1) % 256
        if kind == DATA:
            self.released += payload
            return [("answer", 0)]
        return [("answer", 0), ("write", address, int.from_bytes(payload[2:6], "little"))]
