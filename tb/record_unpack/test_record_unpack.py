# SPDX-License-Identifier: Apache-2.0
"""record_unpack: seeded random records (every field random at full width, kinds 0 .. 7) as
a byte stream with random gaps, against random cmd_full back-pressure: each record of kind
0 .. 5 is pushed once with exactly its fields, only while cmd_full is low, none dropped; kinds
6, 7 strobe record_error and are not pushed; a flush mid-record drops the partial record.
The records come from the host's encoder (interp.link.records), checked against the local one.
Compact records (differences from their base, the last record of their class: arcs or the
others) mixed with plain ones, a flush that zeroes both bases, a difference longer than its
field (record_error); records with i .. l zero (head bit 6, a table of 5 bytes) after records without; the cost, limit, rate,
length and budget codes (fields the unpacker forms: the cost of the geometry or zero, the
limit of the feed, cost x scale / 2^shift, |x|, |y| or |z| x cost, rate x length /
2^(block_shift - 1)) at random block shifts, scales (0 and 2^32 - 1 among them) and shifts,
against the host's reader; and the pace
from a stream without gaps: RECORD_BYTES + 1 clocks a plain record, RECORD_BYTES + 8 +
DERIVE_CLOCKS a compact one, codes or not."""
from dataclasses import replace

import cocotb
from cocotb.triggers import FallingEdge, ReadOnly

from interp.link import records
from interp.models.motion import Command
from interp.simulation import motion_build
from interp.simulation.runner import run_cocotb
from interp.testing.controllerkit import (BUILD_PARAMETERS, encode, icarus_in_make_test, local_encode,
                                          mixed_records, pushed_fields)
from interp.testing.tbkit import TB, seeded_rng

NAMES = ("feed", "x", "y", "z", "i", "j", "k", "l", "limit", "exit", "rate", "cost", "length", "budget")
IDLE_INPUTS = {"flush": 0, "in_valid": 0, "in_data": 0, "cmd_full": 0, "block_shift": 2,
               "limit_scale": 0, "limit_shift": 0, "rate_scale": 0, "rate_shift": 0}


def code_inputs(codes):
    """The unpacker's inputs of a records.Codes."""
    return {name: getattr(codes, name) for name in ("block_shift", "limit_scale", "limit_shift",
                                                    "rate_scale", "rate_shift")}


def random_command(rng, b):
    def signed(bits):
        return rng.randint(-(1 << (bits - 1)), (1 << (bits - 1)) - 1)
    return Command(rng.randint(0, 7), rng.getrandbits(b["FEED_W"]), *(signed(b["W"]) for _ in range(7)),
                   plane=rng.randint(0, 3), limit=rng.getrandbits(b["FEED_W"]), exit=rng.getrandbits(b["NW"]),
                   rate=rng.getrandbits(b["PF"] + 1), cost=rng.getrandbits(b["FEED_W"]),
                   length=rng.getrandbits(b["LEN_W"]), budget=rng.getrandbits(b["ZW"]))


def assert_pushed(pushed, want):
    assert pushed == want, f"{len(pushed)} pushed, want {len(want)}; first difference at " \
        f"{next((n for n, (g, w) in enumerate(zip(pushed, want)) if g != w), min(len(pushed), len(want)))}"


@cocotb.test()
async def random_records(dut):
    rng = seeded_rng(dut, "random_records")
    b = {k: int(getattr(dut, k).value) for k in BUILD_PARAMETERS if hasattr(dut, k)}
    b.setdefault("MW", 0), b.setdefault("TW", 0), b.setdefault("POS_W", 0)
    tb = TB(dut)
    await tb.reset(IDLE_INPUTS)
    cmds = [random_command(rng, b) for _ in range(40)]
    assert all(encode(c, b) == local_encode(c, b) for c in cmds), "the host's encoder and the local one differ"
    cut = rng.randrange(1, 20)                       # a partial record, flushed, before record 10
    stream = [(byte, n) for n, c in enumerate(cmds) for byte in encode(c, b)]
    stream = stream[:10 * len(encode(cmds[0], b))] + [(0xEE, -1)] * cut + stream[10 * len(encode(cmds[0], b)):]
    pushed, errors = await run_stream(tb, rng, stream, 10, 0.7, rng.choice([0.0, 0.3, 0.8]))
    want = [pushed_fields(c, b) for c in cmds if c.kind < 6]
    assert errors == sum(c.kind >= 6 for c in cmds)
    assert_pushed(pushed, want)


def changed_command(rng, b, previous):
    """A record like a CAM program's: each field kept, moved by a random amount of random size,
    or new at random."""
    new = random_command(rng, b)

    def field(name, bits, signed):
        old = getattr(previous, name)
        how = rng.random()
        if how < 0.4:
            return old
        if how < 0.8:
            size = rng.randint(1, (bits + 7) // 8)
            value = old + rng.randint(-(1 << (8 * size - 1)), (1 << (8 * size - 1)) - 1)
            low, high = (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if signed else (0, (1 << bits) - 1)
            return min(max(value, low), high)
        return getattr(new, name)
    widths = {"feed": b["FEED_W"], "limit": b["FEED_W"], "cost": b["FEED_W"], "exit": b["NW"],
              "rate": b["PF"] + 1, "length": b["LEN_W"], "budget": b["ZW"], **{n: b["W"] for n in "xyzijkl"}}
    return Command(new.kind, *(field(n, widths[n], n in "xyzijkl") for n in ("feed", *"xyzijkl")),
                   plane=new.plane, **{n: field(n, widths[n], False)
                                       for n in ("limit", "exit", "rate", "cost", "length", "budget")})


def compact_stream(rng, b, cmds, plain_share, codes=None):
    """(number, command) pairs -> their records after a reset or flush, as (byte, number)
    (with records.Codes: the codes wherever they are exact)."""
    numbered = list(cmds)
    encoded = mixed_records(rng, [c for _, c in numbered], b, plain_share, codes)
    return [(byte, n) for (n, _), record in zip(numbered, encoded) for byte in record]


async def run_stream(tb, rng, stream, flush_before, valid_share, full_rate):
    """Drive (byte, record) pairs; flush once when the stream reaches the first byte of record
    `flush_before` (None: never); the pushed fields and the record_error count."""
    dut = tb.dut
    pushed, errors, at, flushed, idle = [], 0, 0, flush_before is None, 0
    for cycle in range(200_000):
        if at >= len(stream) and (not int(dut.assembling.value) or idle > 1000):
            break
        idle = idle + 1 if at >= len(stream) else 0
        await FallingEdge(dut.clk)
        flush = at < len(stream) and not flushed and stream[at][1] == flush_before
        flushed |= flush
        valid = at < len(stream) and not flush and rng.random() < valid_share
        tb.drive({"in_valid": int(valid), "in_data": stream[at][0] if valid else 0, "flush": int(flush),
                  "cmd_full": int(rng.random() < full_rate)})
        await ReadOnly()
        if int(dut.cmd_valid.value):
            assert not int(dut.cmd_full.value), "pushed while motion_top is full"
            pushed.append({"kind": int(dut.cmd_kind.value), "plane": int(dut.cmd_plane.value),
                           **{n: int(getattr(dut, f"cmd_{n}").value) for n in NAMES}})
        errors += int(dut.record_error.value)
        assert int(dut.taken.value) == int(dut.cmd_valid.value) | int(dut.record_error.value)
        if valid and int(dut.in_ready.value):
            at += 1
    assert at == len(stream), "the stream was not all taken"
    assert not int(dut.assembling.value), "a record is left half assembled"
    return pushed, errors


@cocotb.test()
async def compact_records(dut):
    rng = seeded_rng(dut, "compact_records")
    b = {k: int(getattr(dut, k).value) for k in BUILD_PARAMETERS if hasattr(dut, k)}
    tb = TB(dut)
    await tb.reset(IDLE_INPUTS)
    cmds = [random_command(rng, b)]
    for _ in range(59):
        cmds.append(changed_command(rng, b, cmds[-1]))
    # 20 records, a partial one flushed (the bases are zero again), 40 more
    partial = [(byte, 20) for byte, _ in compact_stream(rng, b, [(20, cmds[20])], 0.0)[:rng.randrange(1, 12)]]
    stream = compact_stream(rng, b, enumerate(cmds[:20]), 0.2) + partial \
        + compact_stream(rng, b, [(n + 21, c) for n, c in enumerate(cmds[20:])], 0.2)
    # last, a difference longer than its field: the exit's nibble above B(NW)
    size = records.nbytes(b["NW"])
    table = bytearray(7)
    table[4] = min(15, size + 1) << 4                       # field 9 (exit): the high nibble of byte 4
    stream += [(byte, 99) for byte in bytes([records.COMPACT]) + table + bytes(size)]
    pushed, errors = await run_stream(tb, rng, stream, 21, 0.7, rng.choice([0.0, 0.3]))
    want = [pushed_fields(c, b) for c in cmds if c.kind < 6]
    assert errors == sum(c.kind >= 6 for c in cmds) + (1 if size < 15 else 0)
    assert_pushed(pushed, want)


def coded_command(rng, b, command, codes, every=None):
    """The command with the cost of its geometry (round(2^FRAC sqrt(x^2 + y^2 + z^2) / |axis|),
    of a random axis) or zero, the limit of its cost (records.Codes' scales) or its feed,
    the rate of its cost, the length of one of its axes (|axis| x cost) and the budget of
    its rate and length, each at random (else its own); with `every` "line" all of them,
    the cost of its geometry and the limit of its cost, with "arc" a cost of zero and the
    limit of its feed."""
    how = rng.random()
    if every == "line" or (not every and how < 0.5):
        command = replace(command, cost=records.derived_cost(command.x, command.y, command.z, rng.choice("xyz"), b))
    elif every == "arc" or how < 0.65:
        command = replace(command, cost=0)
    how = rng.random()
    if every == "line" or (not every and how < 0.5):
        command = replace(command, limit=codes.limit(command.cost, b))
    elif every == "arc" or how < 0.7:
        command = replace(command, limit=command.feed)
    if every or rng.random() < 0.6:
        command = replace(command, rate=codes.rate(command.cost, b))
    if every or rng.random() < 0.8:
        command = replace(command, length=records.derived_length(getattr(command, rng.choice("xyz")),
                                                                  command.cost, b))
    if every or rng.random() < 0.8:
        command = replace(command, budget=records.derived_budget(command.rate, command.length, codes.block_shift, b))
    return command


@cocotb.test()
async def coded_records(dut):
    """Limit, rate, length and budget codes: at block shifts 1 .. 15 (and 0, taken as 1) and
    random scales at shifts 0 .. 63, records whose limit and rate are cost x scale /
    2^shift, whose length is an axis x cost and whose budget is rate x length /
    2^(block_shift - 1) come out with exactly those fields, as the host's reader forms
    them; the codes after other records, plain ones among them, and the reader's record
    equals the pushed one."""
    rng = seeded_rng(dut, "coded_records")
    b = {k: int(getattr(dut, k).value) for k in BUILD_PARAMETERS if hasattr(dut, k)}
    tb = TB(dut)
    shifts = [(0, 63), (63, 0)] + [(rng.randrange(64), rng.randrange(64)) for _ in range(4)]
    scales = [(0, 0xFFFFFFFF), (0xFFFFFFFF, 0)] + [(rng.getrandbits(32), rng.getrandbits(32)) for _ in range(4)]
    for block_shift, (limit_shift, rate_shift), (limit_scale, rate_scale) in zip(
            [0, 1, 15] + rng.sample(range(2, 15), 3), shifts, scales):
        codes = records.Codes(block_shift, limit_scale, limit_shift, rate_scale, rate_shift)
        await tb.reset({**IDLE_INPUTS, **code_inputs(codes)})
        cmds = [random_command(rng, b)]
        for _ in range(23):
            cmds.append(changed_command(rng, b, cmds[-1]))
        extremes = (0, (1 << b["FEED_W"]) - 1)                  # the cost's
        cmds = [replace(c, cost=rng.choice(extremes)) if rng.random() < 0.15 else c for c in cmds]
        every = {n: "line" if n % 8 == 1 else "arc" for n in range(len(cmds)) if n % 4 == 1}   # all codes
        cmds = [coded_command(rng, b, c, codes, every.get(n)) if n in every or rng.random() < 0.7 else c
                for n, c in enumerate(cmds)]
        cmds = [replace(c, kind=c.kind % 6) for c in cmds]
        zeroed = {n for n in range(len(cmds)) if n % 3 == 0 or rng.random() < 0.2}   # a line's i .. l
        cmds = [replace(c, i=0, j=0, k=0, l=0) if n in zeroed else c for n, c in enumerate(cmds)]
        stream = compact_stream(rng, b, enumerate(cmds), 0.1, codes)
        reader, coded, short = records.RecordReader(b, codes), 0, 0
        fields = (records.LIMIT_FIELD, records.RATE_FIELD, records.COST_FIELD, records.LENGTH_FIELD,
                  records.BUDGET_FIELD)
        for n in range(len(cmds)):
            raw = bytes(byte for byte, k in stream if k == n)
            if raw[0] & records.COMPACT:                # (10 % go plain)
                nibbles = records.table_nibbles(raw)
                if n in every:
                    assert all(records.is_code(f, nibbles[f]) for f in fields), f"record {n}: {nibbles}"
                    coded += 1
                if n in zeroed:
                    assert raw[0] & records.ZERO_IJKL, f"record {n}: i .. l zero, head {raw[0]:#x}"
                    short += 1
            assert records.decode(reader.take(raw), b) == records.decode(encode(cmds[n], b), b)
        assert coded and short, f"{coded} compact records with every code, {short} with i .. l zero"
        pushed, errors = await run_stream(tb, rng, stream, None, 0.8, rng.choice([0.0, 0.3]))
        assert errors == 0
        assert_pushed(pushed, [pushed_fields(c, b) for c in cmds])


@cocotb.test()
async def pace(dut):
    """From a stream without gaps, motion_top never full: pushes RECORD_BYTES + 1 clocks apart
    for plain records, RECORD_BYTES + 8 + DERIVE_CLOCKS for compact ones (with codes, with a
    table of 5 bytes, or neither)."""
    rng = seeded_rng(dut, "pace")
    b = {k: int(getattr(dut, k).value) for k in BUILD_PARAMETERS if hasattr(dut, k)}
    tb = TB(dut)
    size = records.record_bytes(b)
    codes = records.Codes(2, rng.getrandbits(32), rng.randrange(64), rng.getrandbits(32), rng.randrange(64))
    for share, interval in ((1.0, size + 1), (0.0, size + 8 + records.derive_clocks(b))):
        await tb.reset({**IDLE_INPUTS, **code_inputs(codes)})
        cmds = [random_command(rng, b)]
        for _ in range(7):
            cmds.append(changed_command(rng, b, cmds[-1]))
        if not share:                                # codes, i .. l zero, both, neither
            cmds = [coded_command(rng, b, c, codes) if n % 2 else c for n, c in enumerate(cmds)]
            cmds = [replace(c, i=0, j=0, k=0, l=0) if n % 4 >= 2 else c for n, c in enumerate(cmds)]
        stream = compact_stream(rng, b, enumerate(cmds), share, codes)
        at, cycle, pushes = 0, 0, []
        while len(pushes) < len(cmds) and cycle < 8000:
            await FallingEdge(dut.clk)
            tb.drive({"in_valid": int(at < len(stream)), "in_data": stream[at][0] if at < len(stream) else 0})
            await ReadOnly()
            if int(dut.cmd_valid.value) or int(dut.record_error.value):
                pushes.append(cycle)
            if at < len(stream) and int(dut.in_ready.value):
                at += 1
            cycle += 1
        gaps = {later - earlier for earlier, later in zip(pushes, pushes[1:])}
        assert gaps == {interval}, f"{'plain' if share else 'compact'} records: pushes {gaps} clocks apart"


def test_record_unpack(sim):
    icarus_in_make_test(sim)
    p = motion_build.PARAMETERS
    for params in ({}, {k: p[k] for k in ("W", "FEED_W", "FRAC", "NW", "PF", "LEN_W", "ZW")}):
        run_cocotb(toplevel="record_unpack", test_module="test_record_unpack", sim=sim, parameters=params,
                   name="record_unpack")
