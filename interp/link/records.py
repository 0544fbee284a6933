# SPDX-License-Identifier: Apache-2.0
"""Command records: one rtl/motion_top.v command as the bytes the controller's
record_unpack reads (docs/host-driver.md, "Records").

Fields in this order, little-endian, each B(bits) = ceil(bits / 8) bytes (unused high
bits zero; signed fields sign-extended to their bytes):

    head   1 byte: bits 2:0 kind, bits 5:4 plane, bits 7:6 zero
    feed   B(FEED_W)      x y z i j k l   B(W) each (signed)
    limit  B(FEED_W)      exit  B(NW)     rate B(PF + 1)     cost B(FEED_W)
    length B(LEN_W)       budget B(ZW)

At the default build (W 32, FEED_W 34, NW 24, PF 16, LEN_W 66, ZW 68) a record is
1 + 5 + 28 + 5 + 3 + 3 + 5 + 9 + 9 = 68 bytes.  The order is the native harness's
16-field command line: kind plane feed x y z i j k l limit exit rate cost length budget.

A compact record (head bit 7 set) carries each of the 14 fields after the head as its
difference from the same field of the previous record (all zero after a reset or a
flush): the head, 7 bytes of nibbles (the difference length n of field 2t in the low
nibble of byte t, 0 .. min(15, B)), then each field's n bytes, two's complement,
little-endian; the controller sign-extends them and adds them to the field's bytes
modulo 2^(8 B).  The driver sends compact records (about half the bytes of plain ones
on CAM programs); the controller's record unpacker takes RECORD_BYTES + 8 clocks for
one, RECORD_BYTES + 1 for a plain one.
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
    """Bytes of one record (68 at the default build)."""
    return 1 + sum(nbytes(bits) for _, bits in layout(build))


COMPACT = 0x80                  # head bit 7: a compact record
TABLE_BYTES = 7                 # its nibble table: 14 fields, one nibble each


def unpack_interval(build=None, compact_records: bool = True) -> int:
    """Clocks between two records the controller's record unpacker hands to motion_top
    from a filled queue: RECORD_BYTES clocks to form the bytes (one a clock) and one to
    push, and for a compact record (the link's) the 7 clocks of its nibble table (92 at
    the default build; 85 for plain records).  interp gcode pushes its commands no faster."""
    return record_bytes(build) + 1 + (TABLE_BYTES if compact_records else 0)


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


def _difference_bytes(difference: int) -> int:
    """Bytes of the shortest two's complement form of a difference (0 for 0)."""
    if difference == 0:
        return 0
    n = 1
    while not -(1 << (8 * n - 1)) <= difference < (1 << (8 * n - 1)):
        n += 1
    return n


def compact(record: bytes, previous: bytes, build=None) -> bytes | None:
    """A plain record -> its compact form after `previous` (a plain record, or zeros after a
    reset or flush); None when a field's difference needs more than 15 bytes."""
    b = _build(build)
    nibbles, body, at = [], bytearray(), 1
    for _, bits in layout(b):
        size = nbytes(bits)
        modulus = 1 << (8 * size)
        difference = (int.from_bytes(record[at:at + size], "little")
                      - int.from_bytes(previous[at:at + size], "little")) % modulus
        if difference >= modulus >> 1:
            difference -= modulus
        n = _difference_bytes(difference)
        if n > 15:
            return None
        nibbles.append(n)
        body += difference.to_bytes(n, "little", signed=True)
        at += size
    table = bytes(nibbles[2 * t] | nibbles[2 * t + 1] << 4 for t in range(TABLE_BYTES))
    return bytes([record[0] | COMPACT]) + table + bytes(body)


class RecordReader:
    """The controller's record unpacker on the host: whole plain records out of a stream of
    plain and compact records, the previous record kept (zeros at first, as after a
    reset or flush)."""

    def __init__(self, build=None):
        self.build = _build(build)
        self.size = record_bytes(self.build)
        self.previous = bytes(self.size)

    def length(self, data) -> int | None:
        """Bytes the record at the start of `data` takes; None while that is not known yet
        (no head, or a compact record's table not all there)."""
        if not data:
            return None
        if not data[0] & COMPACT:
            return self.size
        if len(data) < 1 + TABLE_BYTES:
            return None
        return 1 + TABLE_BYTES + sum((byte & 15) + (byte >> 4) for byte in data[1:1 + TABLE_BYTES])

    def whole_records(self, data) -> int:
        """Whole records at the start of `data` (the controller's STATUS.records)."""
        count, at = 0, 0
        while True:
            size = self.length(data[at:at + 1 + TABLE_BYTES])
            if size is None or at + size > len(data):
                return count
            count, at = count + 1, at + size

    def take(self, data) -> bytes:
        """The record that is exactly `data` -> its plain bytes (the head's bit 7 cleared),
        kept as the previous record.  ValueError when a difference is longer than its
        field (the controller's error 18)."""
        data = bytes(data)
        if not data[0] & COMPACT:
            if len(data) != self.size:
                raise ValueError(f"a record is {self.size} bytes, got {len(data)}")
            self.previous = data
            return data
        if len(data) != self.length(data):
            raise ValueError("a compact record's length differs from its table's")
        out, at, body = bytearray([data[0] & ~COMPACT & 0xFF]), 1, 1 + TABLE_BYTES
        nibbles = [data[1 + f // 2] >> (4 * (f % 2)) & 15 for f in range(2 * TABLE_BYTES)]
        bad = False
        for n, (_, bits) in zip(nibbles, layout(self.build)):
            size = nbytes(bits)
            bad |= n > size
            n = min(n, size)                    # the unpacker takes B bytes of a longer difference
            difference = int.from_bytes(data[body:body + n], "little", signed=True) if n else 0
            value = (int.from_bytes(self.previous[at:at + size], "little") + difference) % (1 << (8 * size))
            out += value.to_bytes(size, "little")
            at, body = at + size, body + n
        self.previous = bytes(out)
        if bad:
            raise ValueError("a compact record's difference is longer than its field")
        return self.previous


def encode_program(commands, build=None, compact_records: bool = True) -> bytes:
    """All commands' records, concatenated (the DATA frames' byte stream): compact ones
    (plain where a difference would need more than 15 bytes), or plain ones."""
    b = _build(build)
    out, previous = bytearray(), bytes(record_bytes(b))
    for c in commands:
        record = encode(fields_of(c), b)
        short = compact(record, previous, b) if compact_records else None
        out += short if short is not None else record
        previous = record
    return bytes(out)
