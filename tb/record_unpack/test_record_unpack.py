# SPDX-License-Identifier: Apache-2.0
"""record_unpack: seeded random records (every field random at full width, kinds 0 .. 7) as
a byte stream with random gaps, against random cmd_full back-pressure: each record of kind
0 .. 5 is pushed once with exactly its fields, only while cmd_full is low, none dropped; kinds
6, 7 strobe record_error and are not pushed; a flush mid-record drops the partial record.
The records come from the host's encoder (interp.link.records), checked against the local one."""
import cocotb
from cocotb.triggers import FallingEdge, ReadOnly

from interp.models.motion import Command
from interp.simulation import motion_build
from interp.simulation.runner import run_cocotb
from interp.testing.controllerkit import BUILD_PARAMETERS, encode, icarus_in_make_test, local_encode, pushed_fields
from interp.testing.tbkit import TB, seeded_rng

NAMES = ("feed", "x", "y", "z", "i", "j", "k", "l", "limit", "exit", "rate", "cost", "length", "budget")


def random_command(rng, b):
    def signed(bits):
        return rng.randint(-(1 << (bits - 1)), (1 << (bits - 1)) - 1)
    return Command(rng.randint(0, 7), rng.getrandbits(b["FEED_W"]), *(signed(b["W"]) for _ in range(7)),
                   plane=rng.randint(0, 3), limit=rng.getrandbits(b["FEED_W"]), exit=rng.getrandbits(b["NW"]),
                   rate=rng.getrandbits(b["PF"] + 1), cost=rng.getrandbits(b["FEED_W"]),
                   length=rng.getrandbits(b["LEN_W"]), budget=rng.getrandbits(b["ZW"]))


@cocotb.test()
async def random_records(dut):
    rng = seeded_rng(dut, "random_records")
    b = {k: int(getattr(dut, k).value) for k in BUILD_PARAMETERS if hasattr(dut, k)}
    b.setdefault("MW", 0), b.setdefault("TW", 0), b.setdefault("POS_W", 0)
    tb = TB(dut)
    await tb.reset({"flush": 0, "in_valid": 0, "in_data": 0, "cmd_full": 0})
    cmds = [random_command(rng, b) for _ in range(40)]
    assert all(encode(c, b) == local_encode(c, b) for c in cmds), "the host's encoder and the local one differ"
    cut = rng.randrange(1, 20)                       # a partial record, flushed, before record 10
    stream = [(byte, n) for n, c in enumerate(cmds) for byte in encode(c, b)]
    stream = stream[:10 * len(encode(cmds[0], b))] + [(0xEE, -1)] * cut + stream[10 * len(encode(cmds[0], b)):]
    pushed, errors, at, flushed = [], 0, 0, False
    full_rate = rng.choice([0.0, 0.3, 0.8])
    for cycle in range(60_000):
        if at >= len(stream) and not int(dut.assembling.value):
            break
        await FallingEdge(dut.clk)
        flush = at < len(stream) and stream[at][1] >= 10 and not flushed
        if flush:                                   # the partial record's bytes are in: flush it
            flushed = True
        valid = at < len(stream) and not flush and rng.random() < 0.7
        tb.drive({"in_valid": int(valid), "in_data": stream[at][0] if valid else 0, "flush": int(flush),
                  "cmd_full": int(rng.random() < full_rate)})
        await ReadOnly()                            # what the next rising edge takes
        if int(dut.cmd_valid.value):
            assert not int(dut.cmd_full.value), "pushed while motion_top is full"
            pushed.append({"kind": int(dut.cmd_kind.value), "plane": int(dut.cmd_plane.value),
                           **{n: int(getattr(dut, f"cmd_{n}").value) for n in NAMES}})
        errors += int(dut.record_error.value)
        assert int(dut.taken.value) == int(dut.cmd_valid.value) | int(dut.record_error.value)
        if valid and int(dut.in_ready.value):
            at += 1
    want = [pushed_fields(c, b) for c in cmds if c.kind < 6]
    assert errors == sum(c.kind >= 6 for c in cmds)
    assert pushed == want, f"{len(pushed)} pushed, want {len(want)}; first difference at " \
        f"{next((n for n, (g, w) in enumerate(zip(pushed, want)) if g != w), min(len(pushed), len(want)))}"


def test_record_unpack(sim):
    icarus_in_make_test(sim)
    p = motion_build.PARAMETERS
    for params in ({}, {k: p[k] for k in ("W", "FEED_W", "NW", "PF", "LEN_W", "ZW")}):
        run_cocotb(toplevel="record_unpack", test_module="test_record_unpack", sim=sim, parameters=params,
                   name="record_unpack")
