# SPDX-License-Identifier: Apache-2.0
"""The UART link's frames (docs/host-driver.md, docs/link-protocol.md).

Every frame, both directions (UART 8N1):

    SYNC 0xA5 | LEN | TYPE | SEQ | PAYLOAD (LEN bytes) | CRC_HI | CRC_LO

LEN = payload bytes, 0 .. LMAX (128); CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF,
no reflection, xorout 0) over LEN, TYPE, SEQ and PAYLOAD, high byte first.

`encode_frame` builds a frame; `FrameParser` is the streaming receiver: it hunts for
SYNC, drops a frame whose LEN is above LMAX or whose CRC is wrong (and hunts again
from the byte after that SYNC), and `expire()` drops a frame cut short (the caller
calls it when no byte came for the frame timeout).
"""
from __future__ import annotations

import struct
from dataclasses import dataclass

import crcmod.predefined

from . import registers as _registers

SYNC = 0xA5
LMAX = 128
HEADER = 4                  # SYNC LEN TYPE SEQ
OVERHEAD = HEADER + 2       # + CRC
FRAME_TIMEOUT_BYTES = 32    # the controller's default FRAME_TIMEOUT, in byte times
PROTOCOL_VERSION = 1

# host -> controller
HELLO, DATA, READ, WRITE = 0x01, 0x02, 0x03, 0x04
# controller -> host
ACK, NAK, REPLY = 0x81, 0x82, 0x83
SEQUENCED = (DATA, WRITE)
TYPE_NAMES = {HELLO: "HELLO", DATA: "DATA", READ: "READ", WRITE: "WRITE", ACK: "ACK", NAK: "NAK",
              REPLY: "REPLY"}

# NAK reasons
NAK_CRC, NAK_GAP, NAK_CREDIT, NAK_TYPE = 1, 2, 3, 4
NAK_TEXT = {NAK_CRC: "bad CRC, length or truncated frame", NAK_GAP: "sequence gap", NAK_CREDIT: "no credit",
            NAK_TYPE: "unknown TYPE or bad LEN for the TYPE"}

_crc16 = crcmod.predefined.mkCrcFun("crc-ccitt-false")


def crc16(data: bytes) -> int:
    """CRC-16/CCITT-FALSE of data (crc16(b"123456789") == 0x29B1)."""
    return _crc16(bytes(data))


@dataclass(frozen=True)
class Frame:
    type: int
    seq: int
    payload: bytes = b""

    def __str__(self) -> str:
        name = TYPE_NAMES.get(self.type, f"0x{self.type:02X}")
        return f"{name} seq {self.seq} [{self.payload.hex(' ')}]"


def encode_frame(ftype: int, seq: int, payload: bytes = b"") -> bytes:
    """The bytes of one frame on the wire."""
    payload = bytes(payload)
    if len(payload) > LMAX:
        raise ValueError(f"a payload is at most {LMAX} bytes, got {len(payload)}")
    if not 0 <= ftype <= 255 or not 0 <= seq <= 255:
        raise ValueError("TYPE and SEQ are single bytes")
    body = bytes([len(payload), ftype, seq]) + payload
    return bytes([SYNC]) + body + crc16(body).to_bytes(2, "big")


# ---------------- payloads ----------------

def ack_payload(free: int, state: int, error: int) -> bytes:
    return struct.pack("<HBB", free, state, error)


def nak_payload(reason: int, free: int) -> bytes:
    return struct.pack("<BH", reason, free)


def read_payload(address: int) -> bytes:
    return struct.pack("<H", address)


def write_payload(address: int, value: int) -> bytes:
    return struct.pack("<HI", address, value & 0xFFFFFFFF)


def reply_payload(address: int, value: int) -> bytes:
    return struct.pack("<HI", address, value & 0xFFFFFFFF)


@dataclass(frozen=True)
class Ack:
    seq: int            # the controller's next expected sequence number E
    free: int
    state: int
    error: int


@dataclass(frozen=True)
class Nak:
    seq: int
    reason: int
    free: int


@dataclass(frozen=True)
class Reply:
    seq: int            # echoes the READ's
    address: int
    value: int


def decode_reply(frame: Frame):
    """A controller frame -> Ack, Nak or Reply; ValueError if its LEN is wrong for its TYPE."""
    p = frame.payload
    if frame.type == ACK and len(p) == 4:
        free, state, error = struct.unpack("<HBB", p)
        return Ack(frame.seq, free, state, error)
    if frame.type == NAK and len(p) == 3:
        reason, free = struct.unpack("<BH", p)
        return Nak(frame.seq, reason, free)
    if frame.type == REPLY and len(p) == 6:
        address, value = struct.unpack("<HI", p)
        return Reply(frame.seq, address, value)
    raise ValueError(f"unexpected frame from the controller: {frame}")


# ---------------- the receiver ----------------

class FrameParser:
    """Streaming frame receiver.  feed(bytes) -> the good frames completed; the counters
    `bad_crc`, `bad_len`, `truncated` and `garbage` (bytes skipped while hunting)."""

    def __init__(self, lmax: int = LMAX):
        self.lmax = lmax
        self.buffer = bytearray()
        self.bad_crc = self.bad_len = self.truncated = self.garbage = 0

    def pending(self) -> bool:
        """A frame has begun (a SYNC and maybe more) but is not complete."""
        return bool(self.buffer)

    def expire(self) -> list[Frame]:
        """The frame timeout passed without a byte: drop the frame begun (counted as
        truncated) and hunt again in the bytes after its SYNC; the frames found there."""
        if not self.buffer:
            return []
        self.truncated += 1
        frames: list[Frame] = []
        while self.buffer:              # no byte is coming: whatever stays incomplete is dropped
            del self.buffer[:1]
            frames += self.feed(b"")
        return frames

    def feed(self, data: bytes) -> list[Frame]:
        frames: list[Frame] = []
        self.buffer += data
        buf = self.buffer
        while buf:
            if buf[0] != SYNC:
                at = buf.find(SYNC)
                skipped = len(buf) if at < 0 else at
                self.garbage += skipped
                del buf[:skipped]
                continue
            if len(buf) < 2:
                break
            length = buf[1]
            if length > self.lmax:
                self.bad_len += 1
                del buf[:1]             # hunt again from the byte after this SYNC
                continue
            total = OVERHEAD + length
            if len(buf) < total:
                break
            body = bytes(buf[1:HEADER + length])
            if crc16(body) != int.from_bytes(buf[HEADER + length:total], "big"):
                self.bad_crc += 1
                del buf[:1]
                continue
            frames.append(Frame(body[1], body[2], body[3:]))
            del buf[:total]
        return frames


# ---------------- register addresses: from the generated map (regs/controller.rdl) ----------------

REGISTER_ADDRESSES = dict(_registers.REGISTERS)
ID_VALUE = 0x494E5450          # "INTP"
STATE_NAMES = dict(_registers.ENUMS["STATUS.state"])
IDLE, RUN, HOLDING, HELD, ALARM = (next(k for k, v in STATE_NAMES.items() if v == name)
                                   for name in ("IDLE", "RUN", "HOLDING", "HELD", "ALARM"))
CONTROL_HOLD, CONTROL_ABORT, CONTROL_CLEAR, CONTROL_PROBE_ARM, CONTROL_ENABLE, CONTROL_FILL, CONTROL_PROBE_STOP = (
    1 << _registers.FIELDS[f"CONTROL.{name}"][0]
    for name in ("hold", "abort", "clear", "probe_arm", "enable", "fill", "probe_stop"))
STATUS_PROBE_VALID = 1 << _registers.FIELDS["STATUS.probe_valid"][0]
PROBE_INPUT = 1 << _registers.FIELDS["INPUTS.probe"][0]     # INPUTS' and INPUT_INVERT's probe bit
assert PROBE_INPUT == 1 << _registers.FIELDS["INPUT_INVERT.probe"][0]


# the pin setting registers (the machine file's polarity, input filter, spindle PWM period):
# their widths do not depend on the build
PIN_SETTINGS = ("INPUT_INVERT", "INPUT_FILTER", "OUTPUT_INVERT", "SPINDLE_PERIOD")


def kept_bits(register: str) -> int:
    """The bits of a register that hold what was written: its "rw" fields in the generated map."""
    return sum(((1 << width) - 1) << lsb for key, (lsb, width, access) in _registers.FIELDS.items()
               if key.split(".")[0] == register and access == "rw")


STATUS_REFUSED = 1 << _registers.FIELDS["STATUS.refused"][0]
# taken only while the controller is not busy (a write while busy: STATUS.refused)
SPEED_SETTINGS = ("QUANTUM_LO", "QUANTUM_HI", "MOTION", "LIMIT_SCALE", "RATE_SCALE")
# ERROR codes beyond motion_top's 1..10
ERROR_ABORT_AT_SPEED = 19     # CONTROL.abort while the machine moved (ALARM until CONTROL.clear)
ERROR_TEXT = {16: "e-stop", 17: "limit switch", 18: "record error (a bad record reached the unpacker)",
              19: "aborted at speed"}


def error_text(code: int) -> str:
    """The controller's ERROR code in words."""
    if code in ERROR_TEXT:
        return ERROR_TEXT[code]
    from ..models.motion import ERROR_TEXT as MOTION_ERRORS

    return MOTION_ERRORS.get(code, "unknown error")
