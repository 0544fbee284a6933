# SPDX-License-Identifier: Apache-2.0
"""The link's frames (interp.link.protocol) and command records (interp.link.records)."""
from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from interp.link import protocol as p
from interp.link import records as r


def reference_crc(data: bytes) -> int:
    """CRC-16/CCITT-FALSE bit by bit (an independent check of the library's)."""
    crc = 0xFFFF
    for byte in data:
        crc ^= byte << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021 if crc & 0x8000 else crc << 1) & 0xFFFF
    return crc


# ---------------- CRC and the worked examples (docs/host-driver.md, docs/link-protocol.md) ----------------

def test_crc_check_value():
    assert p.crc16(b"123456789") == 0x29B1 == reference_crc(b"123456789")


@pytest.mark.parametrize("frame, text", [
    (p.encode_frame(p.HELLO, 0), "A5 00 01 00 FF AD"),
    (p.encode_frame(p.READ, 3, p.read_payload(0x04)), "A5 02 03 03 04 00 5B C7"),
    (p.encode_frame(p.WRITE, 0, p.write_payload(0x44, 150)), "A5 06 04 00 44 00 96 00 00 00 C0 20"),
    (p.encode_frame(p.ACK, 1, p.ack_payload(4096, 0, 0)), "A5 04 81 01 00 10 00 00 48 BA"),
])
def test_worked_examples(frame, text):
    assert frame == bytes.fromhex(text)
    assert int.from_bytes(frame[-2:], "big") == reference_crc(frame[1:-2])


def test_encode_refuses_long_payload():
    with pytest.raises(ValueError, match="at most 128"):
        p.encode_frame(p.DATA, 0, bytes(129))


# ---------------- the parser ----------------

def test_parser_garbage_split_and_back_to_back():
    a, b = p.encode_frame(p.ACK, 7, p.ack_payload(100, 1, 0)), p.encode_frame(p.NAK, 8, p.nak_payload(2, 50))
    parser = p.FrameParser()
    got = []
    for byte in b"\x00\x13\xff" + a + b:
        got += parser.feed(bytes([byte]))
    assert got == [p.Frame(p.ACK, 7, a[4:-2]), p.Frame(p.NAK, 8, b[4:-2])]
    assert parser.garbage == 3 and not parser.pending()
    assert p.decode_reply(got[0]) == p.Ack(7, 100, 1, 0)
    assert p.decode_reply(got[1]) == p.Nak(8, 2, 50)


def test_parser_bad_crc_dropped_then_next_frame():
    good = p.encode_frame(p.REPLY, 2, p.reply_payload(0x18, 0x301))
    bad = bytearray(p.encode_frame(p.ACK, 1, p.ack_payload(1, 2, 3)))
    bad[5] ^= 0x10
    parser = p.FrameParser()
    assert parser.feed(bytes(bad) + good) == [p.Frame(p.REPLY, 2, good[4:-2])]
    assert parser.bad_crc == 1
    assert p.decode_reply(parser.feed(good)[0]) == p.Reply(2, 0x18, 0x301)


def test_parser_over_long_len():
    good = p.encode_frame(p.HELLO, 0)
    parser = p.FrameParser()
    assert parser.feed(bytes([p.SYNC, 200, 1, 2, 3]) + good) == [p.Frame(p.HELLO, 0, b"")]
    assert parser.bad_len == 1


def test_parser_truncated_frame_expires_and_false_sync_recovers():
    good = p.encode_frame(p.DATA, 9, b"abc")
    parser = p.FrameParser()
    assert parser.feed(good[:5]) == [] and parser.pending()
    parser.expire()
    assert parser.truncated == 1 and not parser.pending()
    # a stray SYNC with a plausible LEN in front of a frame: found again once the frame times out
    assert parser.feed(bytes([p.SYNC, 40]) + good) == []
    assert parser.expire() == [p.Frame(p.DATA, 9, b"abc")]


def test_decode_reply_refuses_wrong_length():
    with pytest.raises(ValueError, match="unexpected"):
        p.decode_reply(p.Frame(p.ACK, 0, b"\x00"))


@settings(max_examples=60, deadline=None)
@given(ftype=st.integers(0, 255), seq=st.integers(0, 255), payload=st.binary(max_size=p.LMAX),
       junk=st.binary(max_size=20), cut=st.integers(1, 40))
def test_frame_round_trip(ftype, seq, payload, junk, cut):
    """Any frame after any junk, fed in chunks, comes out (at the latest when the line goes quiet)."""
    wire = junk + p.encode_frame(ftype, seq, payload)
    parser = p.FrameParser()
    got = []
    for at in range(0, len(wire), cut):
        got += parser.feed(wire[at:at + cut])
    got += parser.expire()
    assert got[-1] == p.Frame(ftype, seq, payload)


# ---------------- records ----------------

def test_record_bytes_default_build():
    assert r.record_bytes() == 68 == 1 + 5 + 28 + 5 + 3 + 3 + 5 + 9 + 9
    assert r.record_bytes({"W": 16, "FEED_W": 16, "NW": 16, "PF": 12, "LEN_W": 34, "ZW": 48}) == \
        1 + 2 + 14 + 2 + 2 + 2 + 2 + 5 + 6


def test_record_layout_by_hand():
    rec = r.encode({"kind": 2, "plane": 1, "feed": 0x0102, "x": -2, "l": 5, "rate": 1 << 16, "budget": 3})
    assert rec[0] == 0x12
    assert rec[1:6] == bytes([2, 1, 0, 0, 0])                       # feed, 5 bytes
    assert rec[6:10] == b"\xfe\xff\xff\xff"                          # x = -2, 4 bytes
    assert rec[30:34] == bytes([5, 0, 0, 0])                         # l
    assert rec[42:45] == bytes([0, 0, 1])                            # rate (PF + 1 = 17 bits, 3 bytes)
    assert rec[-9:] == bytes([3] + [0] * 8)                          # budget, 9 bytes
    # a DWELL's cycles (unsigned W bits) are the port's bit pattern
    assert r.encode({"kind": 4, "x": (1 << 32) - 1})[6:10] == b"\xff\xff\xff\xff"


@pytest.mark.parametrize("fields, word", [({"x": 1 << 32}, "x"), ({"y": -(1 << 31) - 1}, "y"), ({"feed": 1 << 34}, "feed"), ({"rate": -1}, "rate"),
                                          ({"kind": 8}, "kind"), ({"plane": 4}, "plane"), ({"speed": 1}, "speed")])
def test_record_out_of_range(fields, word):
    with pytest.raises(ValueError, match=word):
        r.encode(fields)


def test_decode_refuses_bad_records():
    with pytest.raises(ValueError, match="68 bytes"):
        r.decode(bytes(67))
    bad = bytearray(r.encode({"kind": 0}))
    bad[5] = 0xFF                                                    # above FEED_W's 34 bits
    with pytest.raises(ValueError, match="feed"):
        r.decode(bytes(bad))


FIELD_RANGES = {"kind": (0, 7), "plane": (0, 3), "feed": (0, (1 << 34) - 1), "limit": (0, (1 << 34) - 1),
                "exit": (0, (1 << 24) - 1), "rate": (0, (1 << 17) - 1), "cost": (0, (1 << 34) - 1),
                "length": (0, (1 << 66) - 1), "budget": (0, (1 << 68) - 1),
                **{f: (-(1 << 31), (1 << 31) - 1) for f in r.SIGNED}}


@settings(max_examples=80, deadline=None)
@given(st.fixed_dictionaries({k: st.integers(lo, hi) for k, (lo, hi) in FIELD_RANGES.items()}))
def test_record_round_trip(fields):
    data = r.encode(fields)
    assert len(data) == 68
    assert r.decode(data) == fields


def test_compiled_program_records():
    """The compiler's commands (interp gcode's path) become records field for field: plain,
    and compact (what interp send sends), read back as the controller's unpacker does."""
    from interp.commands.gcode import compile_text

    _, compiled = compile_text("G21 G90\nM3 S1000\nG1 X1 Y2 F600\nG2 X3 Y2 I1 J0\nG4 P0.1\nM5\nM2\n")
    stream = r.encode_program(compiled.commands, compact_records=False)
    assert len(stream) == 68 * len(compiled.commands)
    short = r.encode_program(compiled.commands)
    assert len(short) < len(stream) / 2
    reader, at, kinds = r.RecordReader(), 0, set()
    for n, cmd in enumerate(compiled.commands):
        fields = r.decode(stream[68 * n:68 * n + 68])
        assert tuple(fields[k] for k in r.FIELD_NAMES) == cmd.fields()
        size = reader.length(short[at:])
        assert short[at] & r.COMPACT and r.decode(reader.take(short[at:at + size])) == fields
        at += size
        kinds.add(cmd.kind)
    assert at == len(short) and reader.whole_records(short) == len(compiled.commands)
    assert {0, 1, 4, 5} <= kinds                                     # line, arc, dwell, event


@settings(max_examples=80, deadline=None)
@given(st.fixed_dictionaries({k: st.integers(lo, hi) for k, (lo, hi) in FIELD_RANGES.items()}),
       st.fixed_dictionaries({k: st.integers(lo, hi) for k, (lo, hi) in FIELD_RANGES.items()}),
       st.sets(st.sampled_from(sorted(FIELD_RANGES))))
def test_compact_round_trip(previous, fields, kept):
    """A compact record after any previous one reads back as its plain record; unchanged
    fields cost nothing (the table's 8 bytes and the changed fields' differences)."""
    fields = {k: previous[k] if k in kept else v for k, v in fields.items()}
    before, record = r.encode(previous), r.encode(fields)
    short = r.compact(record, before)
    reader = r.RecordReader()
    reader.bases[r.record_class(record[0])] = before
    assert reader.length(short) == len(short)
    assert reader.take(short) == record
    sizes = dict(r.layout())
    assert len(short) <= 8 + sum(r.nbytes(sizes[k]) for k in sizes if fields[k] != previous[k])


def test_decode_as_the_ports_see_it():
    """strict=False: the unused head bits and the bits above a field's width are dropped, as
    the controller's ports drop them (a plain head with bit 6 set, a length code's product
    above LEN_W); strict decoding refuses both."""
    b = r.DEFAULT_BUILD
    record = bytearray(r.encode({"kind": 1, "plane": 2, "x": -5, "length": 7}))
    record[0] |= 0x48
    at = 1 + sum(r.nbytes(bits) for name, bits in r.layout(b)[:r.LENGTH_FIELD])
    record[at + r.nbytes(b.LEN_W) - 1] |= 0x80                      # bit 8 B - 1 > LEN_W
    with pytest.raises(ValueError):
        r.decode(bytes(record), b)
    loose = r.decode(bytes(record), b, strict=False)
    assert (loose["kind"], loose["plane"], loose["x"], loose["length"]) == (1, 2, -5, 7)


def test_compact_refuses_long_difference():
    """A nibble above its field's bytes (exit: 3 bytes) is an error, like the controller's 18;
    the record is still taken (B bytes of that field)."""
    table = bytearray(7)
    table[4] = 6 << 4                                                # field 9, exit
    reader = r.RecordReader()
    with pytest.raises(ValueError, match="longer than its field"):
        reader.take(bytes([r.COMPACT]) + table + bytes(6))
    assert r.compact(r.encode({}), bytes(68)) == bytes([r.COMPACT | r.ZERO_IJKL]) + bytes(5)   # all zero: 6 bytes
    assert r.compact(r.encode({"i": 1}), bytes(68)) == bytes([r.COMPACT]) + bytes([0, 0, 1]) + bytes(4) + b"\x01"


def test_limit_and_rate_codes_of_a_compiled_program():
    """The compiler's scales give every line's limit and rate exactly, so interp send sends
    them as codes; the controller's reader, with those scales, forms the compiled fields,
    and with other scales it would not (the codes are the only bytes of those fields)."""
    from interp.commands.gcode import compile_text
    from interp.gcode.compile import scale_of

    moves = "".join(f"G1 X{x:.3f} Y{y:.3f} Z{z:.3f}\n" for x, y, z in
                    ((3.1, 0.7, 0), (1.2, 5.5, -0.3), (-2.2, 4.0, 0.1), (0.4, 0.1, 1.9), (7.7, -3.3, 0)))
    _, compiled = compile_text("G21 G90 F2400\n" + moves + "M2\n")
    codes = r.Codes.of(compiled)
    assert codes.limit_scale >> 31 == 1 and codes.rate_scale >> 31 == 1       # 32 significant bits
    assert scale_of(0.75) == (3 << 30, 32) and scale_of(0.0) == (0, 0)
    stream = r.encode_program(compiled.commands, codes=codes)
    reader, at, lines = r.RecordReader(codes=codes), 0, 0
    for cmd in compiled.commands:
        size = reader.length(stream[at:])
        record = stream[at:at + size]
        if cmd.kind == 0 and cmd.cost:
            nibbles = r.table_nibbles(record)
            assert nibbles[r.LIMIT_FIELD] == nibbles[r.RATE_FIELD] == r.SCALED_CODE
            lines += 1
            other = r.RecordReader(codes=r.Codes(codes.block_shift))
            other.bases = list(reader.bases)
            assert r.decode(other.take(record))["limit"] != cmd.limit
        assert r.decode(reader.take(record)) == dict(zip(r.FIELD_NAMES, cmd.fields()))
        at += size
    assert lines == 5 and at == len(stream)
    assert len(stream) < len(r.encode_program(compiled.commands, codes=codes.block_shift))


def test_scales_follow_the_binding_axis():
    """With a slow Z, the compiler picks X's and Y's top speed (most of the lines), and the
    Z-dominant line's limit goes as a difference."""
    from interp.commands.gcode import compile_text
    from interp.gcode.machine import load_machine

    machine = load_machine(sets=["axis.z.max_rate_mm_min=600"])
    moves = "G1 X3 Y1\nG1 X-1 Y4\nG1 X2 Y-2\nG1 X0.1 Z2\n"
    _, compiled = compile_text("G21 G91 F3000\n" + moves + "M2\n", machine)
    codes = r.Codes.of(compiled)
    stream = r.encode_program(compiled.commands, codes=codes)
    reader, at, coded = r.RecordReader(codes=codes), 0, []
    for cmd in compiled.commands:
        size = reader.length(stream[at:])
        if cmd.kind == 0 and cmd.cost:
            coded.append(r.table_nibbles(stream[at:at + size])[r.LIMIT_FIELD] == r.SCALED_CODE)
        assert r.decode(reader.take(stream[at:at + size])) == dict(zip(r.FIELD_NAMES, cmd.fields()))
        at += size
    assert coded == [True, True, True, False]


def test_cost_and_feed_codes():
    """Every line's cost goes as the code of its largest axis (the controller forms it from
    x, y, z: round(2^FRAC sqrt(x^2 + y^2 + z^2) / |axis|), the compiler's true length per
    step event), every flat arc's cost of 0 as the zero code, and a limit equal to the feed
    as the feed code; the reader forms the compiled fields exactly; a reader that took the
    cost code's axis for another would not."""
    from interp.commands.gcode import compile_text

    program = "G21 G90 F600\nG1 X3.1 Y0.7\nG2 X5.1 Y2.7 I0 J2\nG1 X4 Y9 Z-1\nG3 X2 Y7 I-2 J0\nG1 X0 Y0 Z-3.5\nM2\n"
    _, compiled = compile_text(program)
    codes = r.Codes.of(compiled)
    commands = [cmd.fields() for cmd in compiled.commands]
    commands.append(commands[0][:10] + (commands[0][2],) + commands[0][11:])      # limit = feed
    stream = r.encode_program(commands, codes=codes)
    reader, at, seen = r.RecordReader(codes=codes), 0, []
    for fields in commands:
        size = reader.length(stream[at:])
        record, want = stream[at:at + size], dict(zip(r.FIELD_NAMES, fields))
        nibbles = r.table_nibbles(record)
        if want["kind"] in (0, 1, 2):
            axes = [abs(want[a]) for a in "xyz"]
            seen.append((want["kind"], nibbles[r.COST_FIELD], nibbles[r.LIMIT_FIELD]))
            if want["kind"] == 0:
                assert nibbles[r.COST_FIELD] == 13 + axes.index(max(axes))
                other = r.RecordReader(codes=codes)
                other.bases = list(reader.bases)
                wrong = bytearray(record)
                place = 1 + r.COST_FIELD // 2 - (2 if record[0] & r.ZERO_IJKL else 0)   # (a table of 5 bytes)
                axis = {13: 14, 14: 15, 15: 13}[nibbles[r.COST_FIELD]]                 # another axis
                wrong[place] = wrong[place] & 0x0F | axis << 4
                assert r.decode(other.take(bytes(wrong)))["cost"] != want["cost"]
            else:
                assert nibbles[r.COST_FIELD] == r.ZERO_COST_CODE
        assert r.decode(reader.take(record)) == want
        at += size
    assert at == len(stream)
    assert [k for k, _, _ in seen] == [0, 1, 0, 2, 0, 0] and seen[-1][2] == r.FEED_CODE
    assert r.derived_cost(3, -4, 0, "y") == 5 << 30 and r.derived_cost(0, 0, 0, "x") == 0


def test_bases_by_class():
    """A compact record's base is the last record of its class (arcs, kinds 1 and 2, or the
    others): an arc after a line is sent as its difference from the arc before, so the
    arcs' repeated feed, limit and rate cost no bytes; a reader with one base for all
    would read it wrong; a flush (a new Encoder, a new RecordReader) zeroes both."""
    line = {"kind": 0, "feed": 1000, "x": 5, "y": 3, "limit": 5000, "exit": 900, "rate": 200, "cost": 7}
    arc = {"kind": 2, "feed": 1200, "x": -1, "y": 1, "i": -20, "j": -45, "k": 2, "limit": 1250, "exit": 900,
           "rate": 50, "length": 1 << 33}
    commands = [line, arc, {**line, "x": 6}, {**arc, "i": -21}, {**line, "x": 4}, {**arc, "kind": 1}]
    encoder, reader = r.Encoder(), r.RecordReader()
    for n, fields in enumerate(commands):
        sent = encoder.record(fields)
        if n >= 2:            # the head, the table (5 bytes for a line) and the one field that changed
            assert len(sent) == {2: 7, 3: 9, 4: 7, 5: 9}[n], f"record {n}: {sent.hex()}"
        if n == 3:
            single = r.RecordReader()
            single.bases = [reader.bases[0]] * 2    # (the line before as the base)
            assert r.decode(single.take(sent)) != r.decode(r.encode(fields))
        assert reader.take(sent) == r.encode(fields)
        assert [r.record_class(b[0]) for b in reader.bases] == [0, 1] or n == 0
    assert [r.record_class(k) for k in range(8)] == [0, 1, 1, 0, 0, 0, 0, 0]
