# SPDX-License-Identifier: Apache-2.0
"""frame_tx: ACK, NAK and REPLY frames byte for byte (CRC from crcmod); answers coalesced
(newest ACK/NAK and newest REPLY kept), REPLY first; state taken when the frame starts."""

import cocotb
import pytest

from interp.simulation.runner import run_cocotb
from interp.testing.linkkit import ACK, NAK, REPLY, AnswerParser, frame
from interp.testing.linkkit import FAST_CLOCK
from interp.testing.tbkit import TB, seeded_rng

IDLE = {"ans_valid": 0, "ans_reason": 0, "reply_valid": 0, "reply_addr": 0, "reply_value": 0, "reply_seq": 0,
        "expected": 0, "queue_free": 0, "status_state": 0, "status_error": 0, "out_ready": 1}


class Bench:
    def __init__(self, dut):
        self.dut, self.tb = dut, TB(dut)
        self.inputs = dict(IDLE)
        self.out = bytearray()

    async def tick(self, **pulses):
        applied = {**self.inputs, **pulses}
        if int(self.dut.out_valid.value) and applied["out_ready"]:
            self.out.append(int(self.dut.out_data.value))
        await self.tb.tick(applied)

    async def clocks(self, n, **inputs):
        for _ in range(n):
            await self.tick(**inputs)


async def setup(dut):
    bench = Bench(dut)
    await bench.tb.reset(IDLE)
    return bench


@cocotb.test()
async def each_answer(dut):
    """An ACK, a NAK and a REPLY, with the line always ready: exact bytes."""
    bench = await setup(dut)
    bench.inputs.update(expected=7, queue_free=0x1234, status_state=2, status_error=17)
    await bench.tick(ans_valid=1, ans_reason=0)
    await bench.clocks(20)
    await bench.tick(ans_valid=1, ans_reason=3)
    await bench.clocks(20)
    await bench.tick(reply_valid=1, reply_addr=0x0018, reply_value=0xDEADBEEF, reply_seq=0x42)
    await bench.clocks(20)
    want = (frame(ACK, 7, bytes([0x34, 0x12, 2, 17])) + frame(NAK, 7, bytes([3, 0x34, 0x12]))
            + frame(REPLY, 0x42, bytes([0x18, 0x00, 0xEF, 0xBE, 0xAD, 0xDE])))
    assert bytes(bench.out) == want, bench.out.hex(" ")
    assert not int(dut.out_valid.value)


@cocotb.test()
async def coalesced(dut):
    """While a frame waits for the line, an ACK then a NAK 2 and two REPLYs are requested:
    after it come the newest REPLY, then the NAK with the state at its start, nothing else."""
    bench = await setup(dut)
    bench.inputs.update(expected=1, queue_free=100, out_ready=0)
    await bench.tick(ans_valid=1, ans_reason=0)            # starts at once, waits for the line
    await bench.tick(ans_valid=1, ans_reason=0)
    await bench.tick(ans_valid=1, ans_reason=2)
    await bench.tick(reply_valid=1, reply_addr=1, reply_value=11, reply_seq=5)
    await bench.tick(reply_valid=1, reply_addr=2, reply_value=22, reply_seq=6)
    bench.inputs.update(expected=9, queue_free=50, out_ready=1)
    await bench.clocks(60)
    parser = AnswerParser()
    got = parser.feed(bytes(bench.out))
    assert got == [(ACK, 1, bytes([100, 0, 0, 0])), (REPLY, 6, bytes([2, 0, 22, 0, 0, 0])),
                   (NAK, 9, bytes([2, 50, 0]))], got
    assert parser.bad == 0 and not parser.buffer


@cocotb.test()
async def random_flow(dut):
    """Random requests and a random line: every frame well formed, the last answer of each
    kind always sent, no answer invented."""
    rng = seeded_rng(dut, "random_flow")
    bench = await setup(dut)
    sent_replies, sent_answers = [], []
    for _ in range(3000):
        pulses = {"out_ready": int(rng.random() < 0.3)}
        if rng.random() < 0.05:
            pulses.update(ans_valid=1, ans_reason=rng.randrange(5))
            sent_answers.append(pulses["ans_reason"])
        if rng.random() < 0.03:
            pulses.update(reply_valid=1, reply_addr=rng.randrange(1 << 16), reply_value=rng.randrange(1 << 32),
                          reply_seq=rng.randrange(256))
            sent_replies.append((pulses["reply_seq"], pulses["reply_addr"], pulses["reply_value"]))
        bench.inputs["expected"] = rng.randrange(256)
        await bench.tick(**pulses)
    await bench.clocks(200)
    parser = AnswerParser()
    frames = parser.feed(bytes(bench.out))
    assert parser.bad == 0 and not parser.buffer
    replies = [(s, int.from_bytes(p[0:2], "little"), int.from_bytes(p[2:6], "little"))
               for k, s, p in frames if k == REPLY]
    reasons = [0 if k == ACK else p[0] for k, s, p in frames if k != REPLY]
    assert replies and reasons
    assert replies[-1] == sent_replies[-1] and reasons[-1] == sent_answers[-1]
    assert all(r in sent_replies for r in replies)
    it = iter(sent_replies)
    assert all(r in it for r in replies), "REPLYs out of order"
    it = iter(sent_answers)
    assert all(r in it for r in reasons), "answers out of order"


@pytest.mark.parametrize("simulator", ["icarus", pytest.param("verilator", marks=pytest.mark.slow)])
def test_frame_tx(simulator):
    run_cocotb(toplevel="frame_tx", test_module="test_frame_tx", sim=simulator,
               env=FAST_CLOCK)
