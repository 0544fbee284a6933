# SPDX-License-Identifier: Apache-2.0
"""frame_rx at the byte level against interp.testing.linkkit.FrameRxModel: every answer,
READ/WRITE request and released payload byte; good, corrupted, truncated, over-long,
duplicate and out-of-order frames, garbage, framing errors; credit and busy refusals;
the timeout's exact boundary; reset in the middle of a frame."""

import cocotb
import pytest

from interp.simulation.runner import run_cocotb
from interp.testing.linkkit import (DATA, HELLO, NAK_CREDIT, NAK_FRAME, NAK_GAP, NAK_TYPE, READ, SYNC, WRITE,
                                    FrameRxModel, frame, read_frame, write_frame)
from interp.testing.linkkit import FAST_CLOCK
from interp.testing.tbkit import TB, seeded_rng

IDLE = {"in_valid": 0, "in_data": 0, "in_error": 0, "queue_free": 1000, "wb_busy": 0, "cmd_ready": 1}


class Bench:
    def __init__(self, dut):
        self.dut = dut
        self.tb = TB(dut)
        self.lmax = int(dut.LMAX.value)
        self.timeout = int(dut.TIMEOUT_CLOCKS.value)
        self.inputs = dict(IDLE)
        self.events, self.released = [], bytearray()
        self.counts = {"ev_executed": 0, "ev_duplicate": 0, "ev_error": 0, "ev_gap": 0}

    async def reset(self):
        await self.tb.reset(IDLE)
        self.inputs = dict(IDLE)

    async def tick(self, **inputs):
        """One clock with `inputs` on top of the standing ones; record what came out
        (a byte on cmd_data is taken if cmd_ready is high in that clock)."""
        dut = self.dut
        applied = {**self.inputs, **inputs}
        if int(dut.cmd_valid.value) and applied["cmd_ready"]:
            self.released.append(int(dut.cmd_data.value))
        await self.tb.tick(applied)
        if int(dut.rsp_valid.value):
            self.events.append(("answer", int(dut.rsp_reason.value)))
        if int(dut.read_req.value):
            self.events.append(("read", int(dut.req_addr.value), int(dut.req_seq.value)))
        if int(dut.write_req.value):
            self.events.append(("write", int(dut.req_addr.value), int(dut.req_value.value)))
        for name in self.counts:
            self.counts[name] += int(getattr(dut, name).value)

    async def clocks(self, n: int, **inputs):
        for _ in range(n):
            await self.tick(**inputs)

    async def send(self, data: bytes, spacing: int = 8, model: FrameRxModel | None = None):
        for byte in data:
            await self.tick(in_valid=1, in_data=byte)
            if model:
                self.want(model.feed(byte, spacing - 1))
            await self.clocks(spacing - 1)

    def want(self, events):
        self.expected_events += events

    expected_events: list = []


async def setup(dut) -> Bench:
    bench = Bench(dut)
    bench.expected_events = []
    await bench.reset()
    return bench


async def settle(bench, n=30):
    await bench.clocks(n)


@cocotb.test()
async def good_data_frames(dut):
    """DATA frames with SEQ 0, 1, 2 ... release exactly their payloads, each ACKed; E counts."""
    bench = await setup(dut)
    payloads = [bytes(range(n, n + k)) for n, k in ((0, 1), (10, bench.lmax), (50, 0), (60, 7))]
    for seq, payload in enumerate(payloads):
        await bench.send(frame(DATA, seq, payload))
    await settle(bench)
    assert bytes(bench.released) == b"".join(payloads)
    assert bench.events == [("answer", 0)] * 4
    assert int(dut.expected.value) == 4
    assert bench.counts == {"ev_executed": 4, "ev_duplicate": 0, "ev_error": 0, "ev_gap": 0}


@cocotb.test()
async def latency(dut):
    """CRC_LO in cycle m: the answer in cycle m + 2 (E advanced), the first payload byte in m + 3,
    one byte per clock after it (as the datasheet's timing table says)."""
    bench = await setup(dut)
    await bench.send(frame(DATA, 0, b"xyz"), spacing=1)
    seen = {}
    for cycle in range(1, 8):
        if int(dut.rsp_valid.value):
            seen.setdefault("answer", cycle)
            assert int(dut.expected.value) == 1
        if int(dut.cmd_valid.value):
            seen.setdefault("first", cycle)
        await bench.tick()
    assert seen == {"answer": 2, "first": 3}, seen
    assert bytes(bench.released) == b"xyz"


@cocotb.test()
async def refusals(dut):
    """Bad CRC, LEN > LMAX, unknown TYPE, bad LEN for the TYPE, duplicate, gap: nothing released."""
    bench = await setup(dut)
    await bench.send(frame(DATA, 0, b"abc"))
    bad_crc = bytearray(frame(DATA, 1, b"xyz"))
    bad_crc[-1] ^= 0x01
    cases = [
        (bytes(bad_crc), NAK_FRAME),
        (bytes([SYNC, bench.lmax + 1, DATA, 1]), NAK_FRAME),
        (frame(0x07, 1, b""), NAK_TYPE),
        (frame(READ, 0, b"\x00"), NAK_TYPE),
        (frame(WRITE, 1, b"\x00\x00\x00"), NAK_TYPE),
        (frame(HELLO, 9, b"\x00"), NAK_TYPE),
        (frame(DATA, 0, b"old"), 0),                 # duplicate: ACK, not executed
        (frame(DATA, 200, b"old"), 0),
        (frame(DATA, 2, b"gap"), NAK_GAP),
        (frame(DATA, 128, b"gap"), NAK_GAP),
    ]
    for data, _ in cases:
        await bench.send(data)
        await settle(bench)
    assert bytes(bench.released) == b"abc"
    assert bench.events == [("answer", 0)] + [("answer", r) for _, r in cases]
    assert int(dut.expected.value) == 1
    assert bench.counts == {"ev_executed": 1, "ev_duplicate": 2, "ev_error": 6, "ev_gap": 2}


@cocotb.test()
async def credit_and_busy(dut):
    """LEN above queue_free: NAK 3, nothing written, E kept; a payload arriving while the
    previous one still drains (cmd_ready low) and any frame while the Wishbone access is
    pending are refused with NAK 3 and accepted when resent."""
    bench = await setup(dut)
    bench.inputs["queue_free"] = 4
    await bench.send(frame(DATA, 0, b"12345"))
    await settle(bench)
    assert bench.events == [("answer", NAK_CREDIT)] and not bench.released
    await bench.send(frame(DATA, 0, b"1234"))
    await settle(bench)
    assert bench.events[-1] == ("answer", 0) and bytes(bench.released) == b"1234"
    bench.inputs["queue_free"] = 1000
    bench.inputs["cmd_ready"] = 0                     # the consumer stalls
    await bench.send(frame(DATA, 1, b"first"))
    await bench.send(frame(DATA, 2, b"second"))        # arrives while "first" waits
    await settle(bench)
    assert bench.events[-2:] == [("answer", 0), ("answer", NAK_CREDIT)]
    bench.inputs["cmd_ready"] = 1
    await settle(bench)
    await bench.send(frame(DATA, 2, b"second"))
    await settle(bench)
    assert bytes(bench.released) == b"1234firstsecond"
    bench.inputs["wb_busy"] = 1
    for data in (read_frame(0, 4), write_frame(3, 4, 5), frame(DATA, 3, b"x")):
        await bench.send(data)
        await settle(bench)
    assert bench.events[-3:] == [("answer", NAK_CREDIT)] * 3
    bench.inputs["wb_busy"] = 0
    await bench.send(write_frame(3, 0x40, 0x12345678))
    await bench.send(read_frame(77, 0x1C))
    await settle(bench)
    assert bench.events[-3:] == [("answer", 0), ("write", 0x40, 0x12345678), ("read", 0x1C, 77)]
    assert int(dut.expected.value) == 4


@cocotb.test()
async def timeout_boundary(dut):
    """A frame whose next byte comes TIMEOUT_CLOCKS clocks later is kept; one clock later it is
    dropped (NAK 1) and the late bytes are skipped by the hunt."""
    bench = await setup(dut)
    t = bench.timeout
    data = frame(DATA, 0, b"ab")
    await bench.send(data[:3])
    await bench.send(data[3:], spacing=t)
    await settle(bench)
    assert bench.events == [("answer", 0)] and bytes(bench.released) == b"ab"
    data = frame(DATA, 1, b"cd")
    await bench.send(data[:3])
    await bench.clocks(t - 7)
    await bench.send(data[3:])
    await settle(bench)
    assert bench.events[-1] == ("answer", NAK_FRAME) and bytes(bench.released) == b"ab"
    assert int(dut.expected.value) == 1


@cocotb.test()
async def framing_error_and_reset(dut):
    """A framing error inside a frame drops it (NAK 1); reset in a frame returns to the hunt, E = 0."""
    bench = await setup(dut)
    data = frame(DATA, 0, b"abcd")
    await bench.send(data[:5])
    await bench.tick(in_error=1)
    await bench.send(data[5:])
    await settle(bench)
    assert bench.events == [("answer", NAK_FRAME)] and not bench.released
    await bench.send(data)
    await bench.send(frame(DATA, 1, b"efgh")[:6])
    await bench.reset()
    await bench.send(frame(DATA, 1, b"efgh")[6:])
    await bench.send(frame(DATA, 0, b"ijk"))
    await settle(bench)
    assert bytes(bench.released) == b"abcdijk"
    assert int(dut.expected.value) == 1


@cocotb.test()
async def random_stream(dut):
    """Random mix of good, corrupted, truncated, duplicate and out-of-order frames, garbage and
    framing errors, answered and released exactly as the model says."""
    rng = seeded_rng(dut, "random_stream")
    bench = await setup(dut)
    model = FrameRxModel(lmax=bench.lmax, timeout=bench.timeout, free=1000)
    for _ in range(250):
        e = model.expected
        pick = rng.random()
        seq = (e + rng.choice([0, 0, 0, 0, 1, 2, 255, 254, 128, 127])) % 256
        payload = bytes(rng.randrange(256) for _ in range(rng.randrange(bench.lmax + 1)))
        if pick < 0.45:
            data = frame(DATA, seq, payload)
        elif pick < 0.5:
            data = write_frame(seq, rng.randrange(1 << 16), rng.randrange(1 << 32))
        elif pick < 0.55:
            data = read_frame(seq, rng.randrange(1 << 16))
        elif pick < 0.6:
            data = frame(rng.choice([HELLO, 0, 5, 0x81]), seq, payload[:rng.randrange(2)])
        elif pick < 0.75:
            data = bytearray(frame(DATA, seq, payload))
            data[rng.randrange(len(data))] ^= 1 << rng.randrange(8)
        elif pick < 0.85:
            data = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 12)))
        elif pick < 0.9:
            data = bytes([SYNC, rng.randrange(bench.lmax + 1, 256)])
        else:
            data = frame(DATA, seq, payload)[:rng.randrange(1, len(payload) + 6)]
        await bench.send(data, spacing=rng.randrange(6, 11), model=model)
        if pick >= 0.9:
            await bench.clocks(bench.timeout + 5)
            bench.want(model.feed(0x00, bench.timeout + 5) if model.state != "hunt" else [])
            await bench.send(b"\x00")
        if rng.random() < 0.1:
            await bench.tick(in_error=1)
            bench.want(model.error())
            await bench.clocks(5)
    await settle(bench, 60)
    assert bench.events == bench.expected_events
    assert bytes(bench.released) == bytes(model.released)
    assert int(dut.expected.value) == model.expected
    dut._log.info("%d answers, %d bytes released, E = %d", len(bench.events), len(bench.released),
                  model.expected)


@pytest.mark.parametrize("simulator", ["icarus", pytest.param("verilator", marks=pytest.mark.slow)])
def test_frame_rx(simulator):
    run_cocotb(toplevel="frame_rx", test_module="test_frame_rx", sim=simulator,
               parameters={"LMAX": 16, "TIMEOUT_CLOCKS": 120}, name="frame_rx_16",
               env=FAST_CLOCK)
