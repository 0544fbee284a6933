# SPDX-License-Identifier: Apache-2.0
"""uart_link through its UART pins (cocotbext-uart UartSource/UartSink) with a Wishbone slave
model: HELLO, DATA frames to the record stream byte for byte, bad CRC, over-long LEN, truncated
frames, garbage between frames, duplicates, gaps, credit, READ/REPLY, WRITE executed once,
counters, reset in a frame, and a go-back-N host over a noisy line (SEED=; NOISY_FRAMES=,
NOISE= the probability of a bit flip per byte, also sets drops and insertions)."""

import os

import cocotb
import pytest
from cocotb.triggers import FallingEdge, RisingEdge, Timer
from cocotbext.uart import UartSink, UartSource

from interp.simulation.runner import run_cocotb
from interp.testing.linkkit import (ACK, DATA, HELLO, NAK, NAK_CREDIT, NAK_FRAME, NAK_GAP, NAK_TYPE, REPLY, SYNC,
                                    AnswerParser, ack_fields, frame, nak_fields, read_frame, reply_fields,
                                    write_frame)
from interp.testing.linkkit import FAST_CLOCK
from interp.testing.tbkit import TB, seeded_rng

PERIOD_NS = 10
REGISTERS = {0x00: 0x494E5450, 0x18: 0x00000101, 0x40: 0}


class LinkBench:
    """The UART pins, a record-stream sink and a Wishbone slave (acks after 1 or 2 clocks)."""

    def __init__(self, dut):
        self.dut = dut
        self.tb = TB(dut, PERIOD_NS)
        clocks = round(int(dut.CLK_HZ.value) / int(dut.BAUD.value))
        self.bit_ns = clocks * PERIOD_NS
        self.byte_ns = 10 * self.bit_ns
        self.timeout_ns = int(dut.FRAME_TIMEOUT.value) * self.byte_ns
        self.lmax = int(dut.LMAX.value)
        baud = round(1e9 / self.bit_ns)
        self.source = UartSource(dut.rx, baud=baud, bits=8)
        self.sink = UartSink(dut.tx, baud=baud, bits=8)
        self.parser = AnswerParser()
        self.records = bytearray()
        self.registers = dict(REGISTERS)
        self.writes = []
        self.bus_cycles = 0
        self.ready_p = 1.0
        self.rng = None

    async def start(self):
        dut = self.dut
        dut.cmd_ready.value = 1
        dut.queue_free.value = 4096
        dut.wbm_ack.value = 0
        dut.wbm_dat_r.value = 0
        dut.status_state.value = 1
        dut.status_error.value = 0
        await self.tb.reset({})
        cocotb.start_soon(self.record_sink())
        cocotb.start_soon(self.wishbone_slave())

    async def record_sink(self):
        dut = self.dut
        while True:
            if not int(dut.cmd_valid.value):
                await RisingEdge(dut.cmd_valid)
            await FallingEdge(dut.clk)
            while int(dut.cmd_valid.value):
                ready = int(self.rng.random() < self.ready_p) if self.rng else 1
                dut.cmd_ready.value = ready
                if ready:
                    self.records.append(int(dut.cmd_data.value))
                await FallingEdge(dut.clk)
            dut.cmd_ready.value = 1

    async def wishbone_slave(self):
        dut = self.dut
        while True:
            if not int(dut.wbm_cyc.value):
                await RisingEdge(dut.wbm_cyc)
            await FallingEdge(dut.clk)
            assert int(dut.wbm_stb.value) and int(dut.wbm_sel.value) == 0xF
            self.bus_cycles += 1
            if self.bus_cycles % 2:
                await FallingEdge(dut.clk)             # every other access waits a clock
            address = int(dut.wbm_adr.value)
            if int(dut.wbm_we.value):
                self.writes.append((address, int(dut.wbm_dat_w.value)))
                self.registers[address] = int(dut.wbm_dat_w.value)
            else:
                dut.wbm_dat_r.value = self.registers.get(address, 0)
            dut.wbm_ack.value = 1
            await FallingEdge(dut.clk)
            dut.wbm_ack.value = 0
            assert not int(dut.wbm_cyc.value), "cyc held after ack"

    async def send(self, data: bytes):
        await self.source.write(data)
        await self.source.wait()

    def poll(self):
        return self.parser.feed(bytes(self.sink.read_nowait()))

    async def answers(self, count: int = 1, wait_bytes: int = 40) -> list:
        """The next `count` answer frames (waits up to `wait_bytes` byte times for them)."""
        got = []
        for _ in range(wait_bytes):
            got += self.poll()
            if len(got) >= count:
                break
            await Timer(self.byte_ns, "ns")
        assert len(got) == count, f"answers {got}, wanted {count}"
        return got

    async def exchange(self, data: bytes, count: int = 1) -> list:
        await self.send(data)
        return await self.answers(count)

    def counters(self) -> dict:
        return {name: int(getattr(self.dut, "link_" + name).value)
                for name in ("frames", "duplicates", "errors", "gaps")}


async def setup(dut) -> LinkBench:
    bench = LinkBench(dut)
    await bench.start()
    return bench


def is_ack(answer, seq, free=None):
    kind, got_seq, payload = answer
    return kind == ACK and got_seq == seq and (free is None or ack_fields(payload)["free"] == free)


def is_nak(answer, seq, reason):
    kind, got_seq, payload = answer
    return kind == NAK and got_seq == seq and nak_fields(payload)["reason"] == reason


@cocotb.test()
async def hello(dut):
    """HELLO is answered with ACK: E = 0, the free bytes, state and error as given; twice, no change."""
    bench = await setup(dut)
    dut.status_state.value = 3
    dut.status_error.value = 17
    for _ in range(2):
        (answer,) = await bench.exchange(frame(HELLO, 0x55))
        assert answer[:2] == (ACK, 0) and ack_fields(answer[2]) == {"free": 4096, "state": 3, "error": 17}
    assert bench.counters() == {"frames": 2, "duplicates": 0, "errors": 0, "gaps": 0}


@cocotb.test()
async def data_frames(dut):
    """DATA frames of 1 .. LMAX bytes (records spanning frames): the record stream is their
    payloads in order, each frame ACKed with E advanced."""
    rng = seeded_rng(dut, "data_frames")
    bench = await setup(dut)
    payloads = [bytes(rng.randrange(256) for _ in range(n)) for n in (1, bench.lmax, 84, 0, 13)]
    for seq, payload in enumerate(payloads):
        (answer,) = await bench.exchange(frame(DATA, seq, payload))
        assert is_ack(answer, seq + 1, 4096), answer
    assert bytes(bench.records) == b"".join(payloads)
    assert bench.counters()["frames"] == len(payloads)


@cocotb.test()
async def bad_frames(dut):
    """Bad CRC, LEN > LMAX, truncated (NAK 1 after FRAME_TIMEOUT), unknown TYPE (NAK 4), garbage
    between frames: nothing executed, the next good frame accepted."""
    bench = await setup(dut)
    good = frame(DATA, 0, b"record")
    bad = bytearray(good)
    bad[5] ^= 0x10
    (answer,) = await bench.exchange(bytes(bad))
    assert is_nak(answer, 0, NAK_FRAME), answer
    (answer,) = await bench.exchange(bytes([SYNC, bench.lmax + 1, DATA, 0]))
    assert is_nak(answer, 0, NAK_FRAME), answer
    await bench.send(good[:6])
    await Timer(bench.timeout_ns - 3 * bench.byte_ns, "ns")
    assert not bench.poll(), "dropped before the timeout"
    (answer,) = await bench.answers(1, wait_bytes=15)      # 3 byte times + the NAK's 9
    assert is_nak(answer, 0, NAK_FRAME), answer
    (answer,) = await bench.exchange(frame(0x09, 0, b""))
    assert is_nak(answer, 0, NAK_TYPE), answer
    (answer,) = await bench.exchange(bytes([0x00, 0xFF, 0x5A, 0x13, 0x02]) + good + b"\x11\x22")
    assert is_ack(answer, 1), answer
    assert bytes(bench.records) == b"record"
    assert bench.counters() == {"frames": 1, "duplicates": 0, "errors": 4, "gaps": 0}


@cocotb.test()
async def duplicate_gap_credit(dut):
    """A resent frame is ACKed and not executed; a gap is NAK 2 with SEQ = E; LEN above the
    free bytes is NAK 3 with nothing written, accepted once room is reported."""
    bench = await setup(dut)
    (answer,) = await bench.exchange(frame(DATA, 0, b"one"))
    assert is_ack(answer, 1)
    (answer,) = await bench.exchange(frame(DATA, 0, b"one"))
    assert is_ack(answer, 1), answer
    (answer,) = await bench.exchange(frame(DATA, 3, b"three"))
    assert is_nak(answer, 1, NAK_GAP), answer
    dut.queue_free.value = 4
    (answer,) = await bench.exchange(frame(DATA, 1, b"two!!"))
    assert is_nak(answer, 1, NAK_CREDIT) and nak_fields(answer[2])["free"] == 4, answer
    dut.queue_free.value = 5
    (answer,) = await bench.exchange(frame(DATA, 1, b"two!!"))
    assert is_ack(answer, 2, 5), answer
    assert bytes(bench.records) == b"onetwo!!"
    assert bench.counters() == {"frames": 2, "duplicates": 1, "errors": 0, "gaps": 2}


@cocotb.test()
async def read_write(dut):
    """READ answered with REPLY (the slave's value, SEQ echoed); WRITE executed once even when
    resent; addresses above 0xFF read 0 without a bus access."""
    bench = await setup(dut)
    (answer,) = await bench.exchange(read_frame(0x99, 0x00))
    assert answer[:2] == (REPLY, 0x99) and reply_fields(answer[2]) == {"address": 0, "value": 0x494E5450}
    (answer,) = await bench.exchange(write_frame(0, 0x40, 0x10))
    assert is_ack(answer, 1), answer
    (answer,) = await bench.exchange(write_frame(0, 0x40, 0x10))
    assert is_ack(answer, 1), answer
    assert bench.writes == [(0x40, 0x10)]
    (answer,) = await bench.exchange(read_frame(3, 0x40))
    assert answer[:2] == (REPLY, 3) and reply_fields(answer[2])["value"] == 0x10
    cycles = bench.bus_cycles
    (answer,) = await bench.exchange(read_frame(4, 0x1218))
    assert reply_fields(answer[2]) == {"address": 0x1218, "value": 0}
    (answer,) = await bench.exchange(write_frame(1, 0x0140, 7))
    assert is_ack(answer, 2), answer
    assert bench.bus_cycles == cycles and bench.writes == [(0x40, 0x10)]
    assert bench.counters() == {"frames": 5, "duplicates": 1, "errors": 0, "gaps": 0}


@cocotb.test()
async def reset_in_frame(dut):
    """Reset in the middle of a frame: the rest of it is skipped, E = 0 again."""
    bench = await setup(dut)
    (answer,) = await bench.exchange(frame(DATA, 0, b"abc"))
    data = frame(DATA, 1, b"defgh")
    await bench.send(data[:6])
    await bench.tb.reset({})
    (answer,) = await bench.exchange(data[6:] + frame(DATA, 0, b"ij"))
    assert is_ack(answer, 1), answer
    assert bytes(bench.records) == b"abcij"
    assert bench.counters()["frames"] == 1


async def go_back_n(bench, rng, payloads, noise: float, window: int = 16):
    """A host sending `payloads` as DATA frames: window, go back N on NAK 1/2 or no progress."""
    base = sent = 0
    stalled = 0
    retransmissions = 0
    while base < len(payloads):
        if sent < min(base + window, len(payloads)):
            data = bytearray(frame(DATA, sent % 256, payloads[sent]))
            for i in range(len(data)):
                if rng.random() < noise:
                    data[i] ^= 1 << rng.randrange(8)
            if rng.random() < noise * 4:
                del data[rng.randrange(len(data))]
            if rng.random() < noise * 4:
                data[rng.randrange(len(data)):0] = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 4)))
            await bench.send(bytes(data))
            sent += 1
        else:
            await Timer(bench.byte_ns, "ns")
            stalled += 1
        for kind, seq, payload in bench.poll():
            if kind not in (ACK, NAK):
                continue
            acked = base + (seq - base) % 256
            if acked <= sent:
                if acked > base:
                    base, stalled = acked, 0
                if kind == NAK and nak_fields(payload)["reason"] in (NAK_FRAME, NAK_GAP, NAK_CREDIT):
                    sent = base
                    retransmissions += 1
        if stalled > 2 * int(bench.dut.FRAME_TIMEOUT.value) + 20:       # retransmission timeout
            sent, stalled = base, 0
            retransmissions += 1
    return retransmissions


@cocotb.test()
async def noisy_line(dut):
    """A go-back-N host over a line that flips bits, drops and inserts bytes, with the record
    consumer stalling at random: the record stream is exactly the payloads, in order."""
    rng = seeded_rng(dut, "noisy_line")
    bench = await setup(dut)
    bench.rng, bench.ready_p = rng, 0.7
    frames = int(os.environ.get("NOISY_FRAMES", 24))
    noise = float(os.environ.get("NOISE", 0.004))
    payloads = [bytes(rng.randrange(256) for _ in range(rng.randrange(1, bench.lmax + 1))) for _ in range(frames)]
    retransmissions = await go_back_n(bench, rng, payloads, noise)
    await Timer(4 * bench.byte_ns, "ns")
    counters = bench.counters()
    dut._log.info("noisy line: %d frames, %d bytes, %d go-backs, counters %s", len(payloads),
                  len(bench.records), retransmissions, counters)
    assert bytes(bench.records) == b"".join(payloads)
    assert counters["frames"] == len(payloads)
    assert counters["errors"] > 0 and retransmissions > 0, "the noise never hit"


@pytest.mark.parametrize("simulator", ["icarus", pytest.param("verilator", marks=pytest.mark.slow)])
def test_uart_link(simulator):
    run_cocotb(toplevel="uart_link", test_module="test_uart_link", sim=simulator,
               parameters={"CLK_HZ": 15_000_000, "BAUD": 3_000_000}, name="uart_link_5",
               env=FAST_CLOCK)


@pytest.mark.slow
@pytest.mark.parametrize("noise", [0.002, 0.01])
def test_uart_link_noisy_long(noise):
    """300 frames over the noisy line (make test-all)."""
    run_cocotb(toplevel="uart_link", test_module="test_uart_link", sim="verilator", testcase="noisy_line",
               parameters={"CLK_HZ": 15_000_000, "BAUD": 3_000_000}, name="uart_link_5",
               env={**FAST_CLOCK, "NOISY_FRAMES": 300, "NOISE": noise})
