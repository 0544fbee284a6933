# SPDX-License-Identifier: Apache-2.0
"""record_bounds: a seeded stream of plain and compact records (the host's encoder,
interp.link.records) written with random gaps: `last` is high exactly with the last byte of
every record (the host's RecordReader gives the lengths; the limit, rate, length and budget
codes send no bytes; a compact head with bit 6 set has a table of 5 bytes); a flush mid-record makes the next byte a head again."""
import cocotb
from cocotb.triggers import FallingEdge, ReadOnly

from interp.link import records
from interp.simulation import motion_build
from interp.simulation.runner import run_cocotb
from interp.testing.controllerkit import icarus_in_make_test, mixed_records
from interp.testing.tbkit import TB, seeded_rng

WIDTHS = ("W", "FEED_W", "NW", "PF", "LEN_W", "ZW")
BUILDS = (records.Build(), records.Build(**{k: motion_build.PARAMETERS[k] for k in WIDTHS}))   # default, small


def random_stream(rng, build, count):
    """`count` records of random fields, each compact or plain at random, after a reset;
    many with a cost of their geometry or zero, a limit and a rate of cost x scale or a
    limit of the feed, a length of an axis x cost and a budget of rate x length (their
    codes, no bytes)."""
    size = records.record_bytes(build)
    codes = records.Codes(rng.randint(0, 15), rng.getrandbits(32), rng.randrange(64), rng.getrandbits(32),
                          rng.randrange(64))
    previous, commands = bytes(size), []
    for n in range(count):
        fields = {name: rng.getrandbits(bits) for name, bits in records.layout(build)}
        for name in records.SIGNED:                         # small moves: short differences
            fields[name] = rng.randint(-300, 300)
        fields.update(kind=rng.randint(0, 5), plane=rng.randint(0, 3))
        if n % 4 == 1 or rng.random() < 0.3:
            fields["cost"] = records.derived_cost(fields["x"], fields["y"], fields["z"], rng.choice("xyz"), build)
        elif n % 4 == 3 or rng.random() < 0.2:
            fields["cost"] = 0
        if n % 5 == 2:
            fields["limit"] = fields["feed"]
        elif n % 3 and rng.random() < 0.5:
            fields.update({name: records.decode(previous, build)[name] for name in ("limit", "rate")})
        elif n % 3 == 0 or rng.random() < 0.6:
            fields["limit"], fields["rate"] = codes.limit(fields["cost"], build), codes.rate(fields["cost"], build)
        if rng.random() < 0.4:
            fields.update(i=0, j=0, k=0, l=0)               # a line's: a table of 5 bytes
        if rng.random() < 0.5:
            fields["length"] = records.derived_length(fields[rng.choice("xyz")], fields["cost"], build)
        if rng.random() < 0.5:
            fields["budget"] = records.derived_budget(fields["rate"], fields["length"], codes.block_shift, build)
        commands.append(fields)
        previous = records.encode(fields, build)
    return mixed_records(rng, commands, build, 0.3, codes)


@cocotb.test()
async def bounds(dut):
    rng = seeded_rng(dut, "bounds")
    size = int(dut.RECORD_BYTES.value)
    build = next(b for b in BUILDS if records.record_bytes(b) == size)
    tb = TB(dut)
    await tb.reset({"flush": 0, "write": 0, "data": 0})
    recs = random_stream(rng, build, 60)
    partial = rng.choice(recs)[:rng.randrange(1, 12)]       # flushed before record 10
    stream = [(byte, n == len(rec) - 1) for rec in recs[:10] for n, byte in enumerate(rec)]
    stream += [(byte, None) for byte in partial]
    stream += [(byte, n == len(rec) - 1) for rec in recs[10:] for n, byte in enumerate(rec)]
    flush_at = sum(len(r) for r in recs[:10]) + len(partial)
    reader = records.RecordReader(build)
    assert all(reader.length(r) == len(r) for r in recs), "the host's lengths"
    assert any(r[0] & records.COMPACT and records.table_nibbles(r)[records.BUDGET_FIELD] == records.BUDGET_CODE
               for r in recs), "no budget code"
    assert any(r[0] & records.ZERO_IJKL for r in recs), "no table of 5 bytes"
    for field, code in ((records.LIMIT_FIELD, records.SCALED_CODE), (records.RATE_FIELD, records.SCALED_CODE),
                        (records.LIMIT_FIELD, records.FEED_CODE), (records.COST_FIELD, records.ZERO_COST_CODE),
                        (records.COST_FIELD, (13, 14, 15))):
        codes = code if isinstance(code, tuple) else (code,)
        assert any(r[0] & records.COMPACT and records.table_nibbles(r)[field] in codes
                   for r in recs), f"no code {code} in field {field}"
    at, lasts = 0, 0
    while at < len(stream) or at == flush_at:
        await FallingEdge(dut.clk)
        flush = at == flush_at
        write = not flush and at < len(stream) and rng.random() < 0.7
        tb.drive({"flush": int(flush), "write": int(write), "data": stream[at][0] if write else 0})
        await ReadOnly()
        if write:
            want = bool(stream[at][1])
            assert int(dut.last.value) == want, f"byte {at}: last {int(dut.last.value)}, want {int(want)}"
            lasts += want
            at += 1
        else:
            assert not int(dut.last.value), "last without a write"
        if flush:
            flush_at = -1
    assert lasts == len(recs)


def test_record_bounds(sim):
    icarus_in_make_test(sim)
    for build in BUILDS:
        run_cocotb(toplevel="record_bounds", test_module="test_record_bounds", sim=sim,
                   parameters={"RECORD_BYTES": records.record_bytes(build)}, name="record_bounds")
