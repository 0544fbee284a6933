# SPDX-License-Identifier: Apache-2.0
"""Command records: one rtl/motion_top.v command as the bytes the controller's
record_unpack reads (docs/host-driver.md, "Records").

Fields in this order, little-endian, each B(bits) = ceil(bits / 8) bytes (unused high
bits zero; signed fields sign-extended to their bytes):

    head   1 byte: bits 2:0 kind, bits 5:4 plane, bits 7:6 zero
    feed   B(FEED_W)      x y z i j k l   B(W) each (signed)
    limit  B(FEED_W)      exit  B(NW)     rate B(PF + 1)     cost B(FEED_W)
    length B(LEN_W)       budget B(ZW)

At the default build (W 32, FEED_W 50, NW 40, PF 24, LEN_W 82, ZW 108) a record is
1 + 7 + 28 + 7 + 5 + 4 + 7 + 11 + 14 = 84 bytes.  The order is the native harness's
16-field command line: kind plane feed x y z i j k l limit exit rate cost length budget.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass

from ..gcode import compile as _gc

# the 16 fields of a command, in record order (head = kind + plane)
FIELD_NAMES = ("kind", "plane", "feed", "x", "y", "z", "i", "j", "k", "l",
               "limit", "exit", "rate", "cost", "length", "budget")
SIGNED = ("x", "y", "z", "i", "j", "k", "l")


@dataclass(frozen=True)
class Build:
    """The controller's build widths (defaults: the build the G-code compiler emits
    commands for, interp/gcode/compile.py's constants)."""

    W: int = _gc.W
    FEED_W: int = _gc.FEED_W
    FRAC: int = _gc.FRAC
    NW: int = _gc.NW
    PF: int = _gc.PF
    LEN_W: int = _gc.LEN_W
    ZW: int = _gc.ZW
    MW: int = _gc.MW
    TW: int = 16
    POS_W: int = 32

    def as_dict(self) -> dict[str, int]:
        return asdict(self)


DEFAULT_BUILD = Build()


def _build(build) -> Build:
    if build is None:
        return DEFAULT_BUILD
    if isinstance(build, Build):
        return build
    if isinstance(build, dict):
        known = {k: int(v) for k, v in build.items() if k in Build.__dataclass_fields__}
        return Build(**known)
    raise TypeError(f"build: a records.Build or a dict of widths, not {type(build).__name__}")


def nbytes(bits: int) -> int:
    """B(bits) = ceil(bits / 8)."""
    return (bits + 7) // 8


def layout(build=None) -> list[tuple[str, int]]:
    """[(field, bits)] after the head byte, in record order."""
    b = _build(build)
    return ([("feed", b.FEED_W)] + [(name, b.W) for name in SIGNED]
            + [("limit", b.FEED_W), ("exit", b.NW), ("rate", b.PF + 1), ("cost", b.FEED_W),
               ("length", b.LEN_W), ("budget", b.ZW)])


def record_bytes(build=None) -> int:
    """Bytes of one record (84 at the default build)."""
    return 1 + sum(nbytes(bits) for _, bits in layout(build))


def unpack_interval(build=None) -> int:
    """Clocks between two records the controller's record unpacker hands to motion_top
    from a filled queue: RECORD_BYTES clocks to take the bytes (one a clock) and one to
    push (85 at the default build).  interp gcode pushes its commands no faster."""
    return record_bytes(build) + 1


def fields_of(command) -> dict[str, int]:
    """A command as the dict encode() takes: a dict (returned as is), an object with
    fields() / row() (interp.gcode.compile.Cmd, interp.models.motion.Command: the
    16 integers in record order) or a sequence of the 16 integers."""
    if isinstance(command, dict):
        return command
    for method in ("fields", "row"):
        if hasattr(command, method):
            return dict(zip(FIELD_NAMES, getattr(command, method)()))
    values = tuple(command)
    if len(values) != len(FIELD_NAMES):
        raise ValueError(f"a command has {len(FIELD_NAMES)} fields, got {len(values)}")
    return dict(zip(FIELD_NAMES, values))


def encode(cmd_fields, build=None) -> bytes:
    """One command (a dict of the 16 fields; missing fields are 0) -> its record bytes.
    A value that does not fit its field raises ValueError naming the field."""
    b = _build(build)
    f = fields_of(cmd_fields)
    unknown = set(f) - set(FIELD_NAMES)
    if unknown:
        raise ValueError(f"unknown record field(s): {', '.join(sorted(unknown))}")
    kind, plane = int(f.get("kind", 0)), int(f.get("plane", 0))
    if not 0 <= kind <= 7:
        raise ValueError(f"kind {kind} does not fit 3 bits")
    if not 0 <= plane <= 3:
        raise ValueError(f"plane {plane} does not fit 2 bits")
    out = bytearray([kind | plane << 4])
    for name, bits in layout(b):
        value = int(f.get(name, 0))
        size = nbytes(bits)
        if name in SIGNED:
            # the port's bit pattern: signed W bits, or an unsigned W-bit value (a DWELL's cycles)
            if not -(1 << (bits - 1)) <= value < (1 << bits):
                raise ValueError(f"{name} {value} does not fit {bits} bits")
            value &= (1 << bits) - 1
            if value >> (bits - 1):
                value -= 1 << bits          # sign-extend to the field's bytes
            out += value.to_bytes(size, "little", signed=True)
        else:
            if not 0 <= value < (1 << bits):
                raise ValueError(f"{name} {value} does not fit {bits} bits (unsigned)")
            out += value.to_bytes(size, "little")
    return bytes(out)


def decode(data: bytes, build=None) -> dict[str, int]:
    """Record bytes -> the 16 fields (x .. l signed W bits; the inverse of encode for
    signed values).  ValueError on a wrong length or non-zero unused bits."""
    b = _build(build)
    if len(data) != record_bytes(b):
        raise ValueError(f"a record is {record_bytes(b)} bytes, got {len(data)}")
    head = data[0]
    if head & 0xC8:
        raise ValueError(f"head byte 0x{head:02X}: bits 3 and 7:6 must be 0")
    out = {"kind": head & 7, "plane": (head >> 4) & 3}
    at = 1
    for name, bits in layout(b):
        size = nbytes(bits)
        chunk = data[at:at + size]
        at += size
        if name in SIGNED:
            value = int.from_bytes(chunk, "little", signed=True)
            if not -(1 << (bits - 1)) <= value < (1 << (bits - 1)):
                raise ValueError(f"{name}: bits above {bits} are not a sign extension")
        else:
            value = int.from_bytes(chunk, "little")
            if value >> bits:
                raise ValueError(f"{name}: bits above {bits} are not zero")
        out[name] = value
    return out


def encode_program(commands, build=None) -> bytes:
    """All commands' records, concatenated (the DATA frames' byte stream)."""
    return b"".join(encode(fields_of(c), build) for c in commands)
