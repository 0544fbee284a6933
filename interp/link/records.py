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
difference from the same field of its base, the previous record of its class (arcs,
kinds 1 and 2, or the others; all zero after a reset or a flush): the head, 7 bytes
of nibbles (the difference length n of field 2t in the low nibble of byte t, 0 .. B,
or a code below), then each field's n bytes, two's complement, little-endian; the
controller sign-extends them and adds them to the field's bytes modulo 2^(8 B).  A
compact head with bit 6 set (ZERO_IJKL) says i, j, k and l are zero:
its table has 5 bytes (none for those four fields) and no bytes follow for them.
Codes send no bytes and have the controller form the field: limit 15 and rate 15
(floor(cost x LIMIT_SCALE / 2^limit_shift), floor(cost x RATE_SCALE / 2^rate_shift), modulo
2^FEED_W and 2^(PF + 1): a line's axis ceiling and acceleration), limit 14 (the record's
feed), cost 12 (zero: a flat arc's), cost 13, 14, 15 (round(2^FRAC sqrt(x^2 + y^2 + z^2) /
|x|, |y|, |z|): a line's true length per step event), length 13, 14, 15 (|x|, |y|, |z| x
cost: a line's step events x cost) and budget 15 (floor(rate x length / 2^(block_shift -
1)), the compiler's budget when the speed quantum is 1).  The driver sends compact records,
with the codes wherever they give the field's value exactly (a ninth to a third of the
bytes of plain ones on CAM programs); the controller's record unpacker takes
RECORD_BYTES + 8 + DERIVE_CLOCKS clocks for one (DERIVE_CLOCKS = 4 W + FRAC + 7 for the
cost, then max(W, 64 + max(FEED_W, PF + 1)) + ZW + 15, codes or not), RECORD_BYTES + 1
for a plain one.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from functools import lru_cache

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
LENGTH_CODES = {13: "x", 14: "y", 15: "z"}     # length formed as |axis| x cost
BUDGET_CODE = 15                # budget formed as floor(rate x length / 2^(block_shift - 1))
SCALED_CODE = 15                # limit, rate formed as floor(cost x scale / 2^shift)
FEED_CODE = 14                  # limit formed as the record's feed
ZERO_COST_CODE = 12             # cost formed as 0 (a flat arc's)
COST_CODES = {13: "x", 14: "y", 15: "z"}       # cost formed from x, y, z (a line's: line_cost)
COST_FIELD = 11
LIMIT_FIELD, RATE_FIELD = 8, 10                 # places in the nibble table
LENGTH_FIELD, BUDGET_FIELD = 12, 13
SPAN = 64                       # the unpacker's clock of a scaled field's first bit (shifts 0 .. 63)
ZERO_IJKL = 0x40                # compact head bit 6: i, j, k, l zero, a table of 5 bytes
SHORT_TABLE_BYTES = 5
IJKL = ("i", "j", "k", "l")     # (fields 4 .. 7: the table's bytes 2 and 3)


@dataclass(frozen=True)
class Codes:
    """What the controller forms coded fields with: MOTION.block_shift (the budget code),
    LIMIT_SCALE, RATE_SCALE and MOTION's limit_shift, rate_shift (the limit and rate codes;
    a scale of 0 forms 0).  The controller's values after a reset are the defaults."""

    block_shift: int = 2
    limit_scale: int = 0
    limit_shift: int = 0
    rate_scale: int = 0
    rate_shift: int = 0

    def __post_init__(self):
        for name, top in (("block_shift", 15), ("limit_scale", 0xFFFFFFFF), ("limit_shift", 63),
                          ("rate_scale", 0xFFFFFFFF), ("rate_shift", 63)):
            if not 0 <= getattr(self, name) <= top:
                raise ValueError(f"{name} {getattr(self, name)} is not 0 .. {top}")

    @classmethod
    def of(cls, source) -> "Codes | None":
        """None (no codes), a Codes, a block_shift, a dict of the fields, or a compiled
        program (interp.gcode.compile.Compiled: its settings' block_shift and its codes)."""
        if source is None or isinstance(source, Codes):
            return source
        if isinstance(source, int):
            return cls(block_shift=source)
        if hasattr(source, "settings") and hasattr(source, "codes"):
            source = {**source.codes, "block_shift": source.settings.get("block_shift", 2)}
        return cls(**{k: int(v) for k, v in dict(source).items() if k in cls.__dataclass_fields__})

    def limit(self, cost: int, build=None) -> int:
        """The limit code's value for this cost."""
        return derived_scaled(cost, self.limit_scale, self.limit_shift, _build(build).FEED_W, build)

    def rate(self, cost: int, build=None) -> int:
        """The rate code's value for this cost."""
        return derived_scaled(cost, self.rate_scale, self.rate_shift, _build(build).PF + 1, build)


def cost_clocks(build=None) -> int:
    """Clocks of the cost code's arithmetic (rtl/line_cost.v, and the clock its result is
    taken): 4 W + FRAC + 7 (167 at the default build)."""
    b = _build(build)
    return 4 * b.W + b.FRAC + 7


def derive_clocks(build=None) -> int:
    """Clocks the record unpacker spends after a compact record's last byte forming its
    coded fields (the same with or without codes): the cost's, then max(W, 64 + max(FEED_W,
    PF + 1)) + ZW + 15 for the others (348 at the default build)."""
    b = _build(build)
    return cost_clocks(b) + max(b.W, SPAN + max(b.FEED_W, b.PF + 1)) + b.ZW + 15


def derived_scaled(cost: int, scale: int, shift: int, bits: int, build=None) -> int:
    """A limit or rate code's value: floor(cost x scale / 2^shift) modulo 2^bits (cost FEED_W
    bits, scale 32 bits, shift 6 bits)."""
    b = _build(build)
    product = (cost & ((1 << b.FEED_W) - 1)) * (scale & 0xFFFFFFFF)
    return (product >> (shift & 63)) & ((1 << bits) - 1)


def _magnitude(value: int, bits: int) -> int:
    """|value| of a two's complement word of `bits` bits."""
    value &= (1 << bits) - 1
    return (1 << bits) - value if value >> (bits - 1) else value


def derived_cost(x: int, y: int, z: int, axis: str, build=None) -> int:
    """A cost code's value, a line's true length per step event when its step events are
    |axis|: round(2^FRAC sqrt(x^2 + y^2 + z^2) / |axis|) (halves up) modulo 2^FEED_W, as
    rtl/line_cost.v forms it: q = floor(isqrt((x^2 + y^2 + z^2) 4^(FRAC + 1)) / |axis|)
    modulo 2^(FEED_W + 1) (|axis| = 0: all W + FRAC + 1 bits one), then (q + 1) / 2."""
    b = _build(build)
    x, y, z = (_magnitude(v, b.W) for v in (x, y, z))
    n = {"x": x, "y": y, "z": z}[axis]
    root_bits = b.W + b.FRAC + 1
    q = math.isqrt((x * x + y * y + z * z) << (2 * b.FRAC + 2)) // n if n else (1 << root_bits) - 1
    q &= (1 << (b.FEED_W + 1)) - 1
    return ((q + 1) >> 1) & ((1 << b.FEED_W) - 1)


def derived_length(axis: int, cost: int, build=None) -> int:
    """A length code's value: |axis| x cost (axis as signed W bits, cost FEED_W bits)."""
    b = _build(build)
    return _magnitude(axis, b.W) * (cost & ((1 << b.FEED_W) - 1))


def derived_budget(rate: int, length: int, block_shift: int, build=None) -> int:
    """The budget code's value: floor(rate x length / 2^(block_shift - 1)) modulo 2^ZW
    (rate PF + 1 bits, length LEN_W bits; block_shift 0 counts as 1)."""
    b = _build(build)
    product = (rate & ((1 << (b.PF + 1)) - 1)) * (length & ((1 << b.LEN_W) - 1))
    return (product >> max(block_shift - 1, 0)) & ((1 << b.ZW) - 1)


def unpack_interval(build=None, compact_records: bool = True) -> int:
    """Clocks between two records the controller's record unpacker hands to motion_top
    from a filled queue: RECORD_BYTES clocks to form the bytes (one a clock) and one to
    push, and for a compact record (the link's) the 7 clocks of its nibble table and the
    DERIVE_CLOCKS of its coded fields (424 at the default build; 69 for plain records).
    interp gcode pushes its commands no faster."""
    return record_bytes(build) + 1 + (TABLE_BYTES + derive_clocks(build) if compact_records else 0)


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


def decode(data: bytes, build=None, strict: bool = True) -> dict[str, int]:
    """Record bytes -> the 16 fields (x .. l signed W bits; the inverse of encode for
    signed values).  ValueError on a wrong length or non-zero unused bits; with strict
    False the unused bits are dropped instead, as the controller's ports drop them."""
    b = _build(build)
    if len(data) != record_bytes(b):
        raise ValueError(f"a record is {record_bytes(b)} bytes, got {len(data)}")
    head = data[0]
    if head & 0xC8 and strict:
        raise ValueError(f"head byte 0x{head:02X}: bits 3 and 7:6 must be 0")
    out = {"kind": head & 7, "plane": (head >> 4) & 3}
    at = 1
    for name, bits in layout(b):
        size = nbytes(bits)
        chunk = data[at:at + size]
        at += size
        value = int.from_bytes(chunk, "little", signed=name in SIGNED)
        if not strict:                      # the field's low bits, signed ones as such
            value &= (1 << bits) - 1
            if name in SIGNED and value >> (bits - 1):
                value -= 1 << bits
        elif name in SIGNED:
            if not -(1 << (bits - 1)) <= value < (1 << (bits - 1)):
                raise ValueError(f"{name}: bits above {bits} are not a sign extension")
        elif value >> bits:
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


@lru_cache(maxsize=None)
def _offsets(build: Build) -> dict[str, tuple[int, int]]:
    """{field: (byte offset in the record, bytes)} (formed once per build)."""
    out, at = {}, 1
    for name, bits in layout(build):
        out[name] = (at, nbytes(bits))
        at += nbytes(bits)
    return out


def compact(record: bytes, previous: bytes, build=None, codes=None) -> bytes | None:
    """A plain record -> its compact form against the base `previous` (the last plain record
    of its class, record_class, or zeros after a reset or flush: Encoder keeps them); None
    when a field's difference needs more than 15 bytes.  With the controller's Codes (or
    anything Codes.of takes), a field its code gives exactly is sent as the code."""
    b = _build(build)
    settings, codes = Codes.of(codes), {}
    if settings is not None:
        f = decode(record, b)
        if f["cost"] == 0:
            codes["cost"] = ZERO_COST_CODE
        else:
            for code, axis in COST_CODES.items():
                if derived_cost(f["x"], f["y"], f["z"], axis, b) == f["cost"]:
                    codes["cost"] = code
                    break
        if settings.limit(f["cost"], b) == f["limit"]:
            codes["limit"] = SCALED_CODE
        elif f["limit"] == f["feed"]:
            codes["limit"] = FEED_CODE
        if settings.rate(f["cost"], b) == f["rate"]:
            codes["rate"] = SCALED_CODE
        for code, axis in LENGTH_CODES.items():
            if derived_length(f[axis], f["cost"], b) == f["length"]:
                codes["length"] = code
                break
        if derived_budget(f["rate"], f["length"], settings.block_shift, b) == f["budget"]:
            codes["budget"] = BUDGET_CODE
    zero = not any(any(record[at:at + size]) for at, size in (_offsets(b)[name] for name in IJKL))
    nibbles, body, at = [], bytearray(), 1
    for name, bits in layout(b):
        size = nbytes(bits)
        if zero and name in IJKL:
            nibbles.append(0)
            at += size
            continue
        if name in codes:
            nibbles.append(codes[name])
            at += size
            continue
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
    table = bytes(nibbles[2 * t] | nibbles[2 * t + 1] << 4 for t in range(TABLE_BYTES) if not (zero and t in (2, 3)))
    return bytes([record[0] | COMPACT | (ZERO_IJKL if zero else 0)]) + table + bytes(body)


def record_class(head: int) -> int:
    """A record's class by its head's kind: 1 arcs (kinds 1, 2), 0 the others.  A compact
    record's base is the last record of its class: a CAM program's arcs and lines
    alternate, and each repeats its own feed, limit and rate."""
    return 1 if head & 7 in (1, 2) else 0


class Encoder:
    """The host's side of the bases: each command's record, compact (against the last
    record of its class) or plain, as the controller's record unpacker reads them after
    a reset or a flush (with the controller's Codes, or anything Codes.of takes, the
    codes wherever they are exact)."""

    def __init__(self, build=None, codes=None):
        self.build = _build(build)
        self.codes = Codes.of(codes)
        self.bases = [bytes(record_bytes(self.build))] * 2

    def record(self, command, compact_record: bool = True) -> bytes:
        """The bytes to send for one command: compact unless `compact_record` is false or
        a difference would need more than 15 bytes."""
        record = encode(fields_of(command), self.build)
        which = record_class(record[0])
        short = compact(record, self.bases[which], self.build, self.codes) if compact_record else None
        self.bases[which] = record
        return short if short is not None else record


def table_bytes(head: int) -> int:
    """Nibble-table bytes of a compact record with this head: 5 under ZERO_IJKL, else 7."""
    return SHORT_TABLE_BYTES if head & ZERO_IJKL else TABLE_BYTES


def table_nibbles(data) -> list[int] | None:
    """The 14 nibbles of the compact record at the start of `data` (zeros for i .. l under
    ZERO_IJKL); None while its table is not all there."""
    size = table_bytes(data[0])
    if len(data) < 1 + size:
        return None
    table = bytes(data[1:1 + size])
    if size < TABLE_BYTES:
        table = table[:2] + bytes(2) + table[2:]
    return [byte >> shift & 15 for byte in table for shift in (0, 4)]


def is_code(field: int, n: int) -> bool:
    """A nibble that is a code (no bytes follow)."""
    return ((field == LENGTH_FIELD and n in LENGTH_CODES) or (field == BUDGET_FIELD and n == BUDGET_CODE)
            or (field in (LIMIT_FIELD, RATE_FIELD) and n == SCALED_CODE)
            or (field == LIMIT_FIELD and n == FEED_CODE)
            or (field == COST_FIELD and (n == ZERO_COST_CODE or n in COST_CODES)))


class RecordReader:
    """The controller's record unpacker on the host: whole plain records out of a stream of
    plain and compact records, the last record of each class kept as its base (bases[1]
    the arcs', bases[0] the others'; zeros at first, as after a reset or flush)."""

    def __init__(self, build=None, codes=None):
        self.build = _build(build)
        self.size = record_bytes(self.build)
        self.bases = [bytes(self.size)] * 2
        self.codes = Codes.of(codes) or Codes()     # the controller's, for the coded fields

    def length(self, data) -> int | None:
        """Bytes the record at the start of `data` takes; None while that is not known yet
        (no head, or a compact record's table not all there)."""
        if not data:
            return None
        if not data[0] & COMPACT:
            return self.size
        nibbles = table_nibbles(data)
        if nibbles is None:
            return None
        return 1 + table_bytes(data[0]) + sum(0 if is_code(f, n) else n for f, n in enumerate(nibbles))

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
        kept as its class's base.  ValueError when a difference is longer than its field
        (the controller's error 18)."""
        data = bytes(data)
        which = record_class(data[0])
        if not data[0] & COMPACT:
            if len(data) != self.size:
                raise ValueError(f"a record is {self.size} bytes, got {len(data)}")
            self.bases[which] = data
            return data
        if len(data) != self.length(data):
            raise ValueError("a compact record's length differs from its table's")
        zero = bool(data[0] & ZERO_IJKL)
        out, at = bytearray([data[0] & ~(COMPACT | ZERO_IJKL) & 0xFF]), 1
        body = 1 + table_bytes(data[0])
        nibbles = table_nibbles(data)
        bad, coded = False, []
        for field, (n, (name, bits)) in enumerate(zip(nibbles, layout(self.build))):
            size = nbytes(bits)
            if zero and name in IJKL:
                out += bytes(size)
                at += size
                continue
            if is_code(field, n):               # formed once all the bytes are in, as the unpacker does
                coded.append((name, n, at, size))
                n = 0
            bad |= n > size
            n = min(n, size)                    # the unpacker takes B bytes of a longer difference
            difference = int.from_bytes(data[body:body + n], "little", signed=True) if n else 0
            value = (int.from_bytes(self.bases[which][at:at + size], "little") + difference) % (1 << (8 * size))
            out += value.to_bytes(size, "little")
            at, body = at + size, body + n
        # the cost first (the others use it), then limit, rate, length, budget in record order
        for name, code, at, size in sorted(coded, key=lambda c: c[0] != "cost"):
            out[at:at + size] = self._coded_value(name, code, bytes(out)).to_bytes(size, "little")
        self.bases[which] = bytes(out)
        if bad:
            raise ValueError("a compact record's difference is longer than its field")
        return self.bases[which]

    def _coded_value(self, name: str, code: int, formed: bytes) -> int:
        """A coded field's value from the record's other fields and the coded ones before it."""
        places = _offsets(self.build)

        def field(which: str, signed: bool = False) -> int:
            at, size = places[which]
            return int.from_bytes(formed[at:at + size], "little", signed=signed)
        c, b = self.codes, self.build
        if name == "cost":
            return 0 if code == ZERO_COST_CODE else derived_cost(field("x", True), field("y", True),
                                                                 field("z", True), COST_CODES[code], b)
        if name == "limit" and code == FEED_CODE:
            return field("feed")
        if name in ("limit", "rate"):
            return getattr(c, name)(field("cost"), b)
        if name == "length":
            return derived_length(field(LENGTH_CODES[code], True), field("cost"), b)
        return derived_budget(field("rate"), field("length"), c.block_shift, b)


def encode_program(commands, build=None, compact_records: bool = True, codes=None) -> bytes:
    """All commands' records, concatenated (the DATA frames' byte stream): compact ones
    (plain where a difference would need more than 15 bytes; with the controller's Codes,
    or the compiled program they come from, the codes wherever they are exact), or plain
    ones."""
    encoder = Encoder(build, codes)
    return b"".join(encoder.record(c, compact_records) for c in commands)
