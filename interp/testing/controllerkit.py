# SPDX-License-Identifier: Apache-2.0
"""cocotb side of the controller benches (tb/controller, tb/uart_controller): the command
record encoder, the register addresses, a Wishbone master on the controller's `wb_*` port
(cocotbext-wishbone), the record byte stream and monitors of the step pins and of the
commands pushed into motion_top.

Records are made by the host's encoder (interp.link.records); the local one (the record
format of docs/controller.md, "Records") is checked against it and stands in without it.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import cocotb
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge
from cocotb.utils import get_sim_time

from ..link.registers import REGISTERS
from ..models.motion import Command

BUILD_PARAMETERS = ("W", "FEED_W", "FRAC", "NW", "PF", "LEN_W", "ZW", "MW", "TW", "POS_W")
SIGNED = ("x", "y", "z", "i", "j", "k", "l")

# register byte addresses (generated from regs/controller.rdl)
REG = dict(REGISTERS)
HOLD, ABORT, CLEAR, PROBE_ARM, ENABLE, FILL, PROBE_STOP = 1, 2, 4, 8, 16, 32, 64
IDLE, RUN, HOLDING, HELD, ALARM = range(5)


def nbytes(bits: int) -> int:
    return (bits + 7) // 8


def layout(build: dict) -> list[tuple[str, int]]:
    """[(field, bits)] after the head byte, in record order."""
    w, f = build["W"], build["FEED_W"]
    return ([("feed", f)] + [(n, w) for n in SIGNED]
            + [("limit", f), ("exit", build["NW"]), ("rate", build["PF"] + 1), ("cost", f),
               ("length", build["LEN_W"]), ("budget", build["ZW"])])


def record_bytes(build: dict) -> int:
    return 1 + sum(nbytes(bits) for _, bits in layout(build))


def encode(cmd: Command, build: dict) -> bytes:
    """One command -> its record: the host's encoder (interp.link.records) when it is there,
    else local_encode."""
    try:
        from ..link import records
    except ImportError:
        return local_encode(cmd, build)
    return records.encode(cmd, build)


def mixed_records(rng, commands, build, plain_share: float, codes=None) -> list[bytes]:
    """The commands' records as a stream after a reset or flush sends them: compact ones
    (interp.link.records.Encoder: against the last record of their class; with the
    controller's codes (records.Codes.of), the codes where they are exact), each plain
    instead with probability plain_share."""
    from ..link import records
    encoder = records.Encoder(build, codes)
    return [encoder.record(c, rng.random() >= plain_share) for c in commands]


def local_encode(cmd: Command, build: dict) -> bytes:
    """One command -> its record (fields little-endian, signed ones sign-extended)."""
    out = bytearray([cmd.kind | cmd.plane << 4])
    for name, bits in layout(build):
        value = getattr(cmd, name)
        size = nbytes(bits)
        if name in SIGNED:
            value &= (1 << bits) - 1
            if value >> (bits - 1):
                value -= 1 << bits
            out += value.to_bytes(size, "little", signed=True)
        else:
            assert 0 <= value < 1 << bits, f"{name} {value} does not fit {bits} bits"
            out += value.to_bytes(size, "little")
    return bytes(out)


def pushed_fields(cmd: Command, build: dict) -> dict:
    """The command as motion_top's ports see it (signed fields as W-bit patterns)."""
    mask = (1 << build["W"]) - 1
    return {"kind": cmd.kind, "plane": cmd.plane, "feed": cmd.feed,
            **{n: getattr(cmd, n) & mask for n in SIGNED},
            **{n: getattr(cmd, n) for n in ("limit", "exit", "rate", "cost", "length", "budget")}}


@dataclass
class StepLog:
    """Rising edges of the step pins: (time in cycles, axis, direction bit)."""
    edges: list = field(default_factory=list)

    def position(self, since: int = 0) -> list[int]:
        pos = [0, 0, 0]
        for _, axis, negative in self.edges[since:]:
            pos[axis] += -1 if negative else 1
        return pos


async def watch_steps(dut, log: StepLog, cycle) -> None:
    """Log the rising edges of dut.step (x, y, z) with dut.dir, at cycle()."""
    last = 0
    while True:
        await dut.step.value_change
        await ReadOnly()
        now = int(dut.step.value)
        direction = int(dut.dir.value)
        for axis in range(3):
            if now >> axis & 1 and not last >> axis & 1:
                log.edges.append((cycle(), axis, direction >> axis & 1))
        last = now


def data_words(data: bytes, fill: int = 0):
    """(value, byte selects) of the CMD_DATA writes that queue `data`: 4 bytes a write, the
    last 1 .. 3 with only their lanes selected (the others `fill`, ignored)."""
    for at in range(0, len(data), 4):
        chunk = data[at:at + 4]
        yield int.from_bytes(chunk.ljust(4, bytes([fill])), "little"), (1 << len(chunk)) - 1


class ControllerBench:
    """Clock, reset, Wishbone master, record stream and monitors of a controller DUT."""

    def __init__(self, dut, period_ns: int = 10):
        from cocotb.clock import Clock

        self.dut = dut
        self.period = period_ns
        cocotb.start_soon(Clock(dut.clk, period_ns, unit="ns").start())
        self.build = {k: int(getattr(dut, k).value) for k in BUILD_PARAMETERS}
        self.rb = record_bytes(self.build)
        self.steps = StepLog()
        self.pushes: list[dict] = []
        self.push_cycles: list[int] = []        # the cycle of each push

    async def start(self):
        from cocotbext.wishbone.driver import WishboneMaster

        dut = self.dut
        for name in ("cmd_valid", "cmd_data", "estop", "limit", "probe", "wb_cyc", "wb_stb", "wb_we",
                     "wb_adr", "wb_dat_w", "link_frames", "link_duplicates", "link_errors", "link_gaps"):
            getattr(dut, name).value = 0
        dut.wb_sel.value = 0xF
        await self.reset()
        self.wb = WishboneMaster(dut, "wb", dut.clk, width=32, timeout=100_000, signals_dict={
            "cyc": "cyc", "stb": "stb", "we": "we", "adr": "adr", "datwr": "dat_w", "datrd": "dat_r",
            "ack": "ack", "sel": "sel"})
        cocotb.start_soon(self._watch_steps())
        cocotb.start_soon(self._watch_pushes())
        return self

    async def reset(self, cycles: int = 2):
        await FallingEdge(self.dut.clk)
        self.dut.rst.value = 1
        for _ in range(cycles):
            await FallingEdge(self.dut.clk)
        self.dut.rst.value = 0

    def cycle(self) -> int:
        return int(get_sim_time(unit="ns")) // self.period

    async def _watch_steps(self):
        await watch_steps(self.dut, self.steps, self.cycle)

    async def _watch_pushes(self):
        motion = self.dut.u_motion
        while True:
            await RisingEdge(motion.cmd_valid)
            await ReadOnly()
            if int(motion.cmd_valid.value):
                self.push_cycles.append(self.cycle())
                self.pushes.append({"kind": int(motion.cmd_kind.value), "plane": int(motion.cmd_plane.value),
                                    **{n: int(getattr(motion, f"cmd_{n}").value) for n in (
                                        "feed", *SIGNED, "limit", "exit", "rate", "cost", "length", "budget")}})

    # ---------------- Wishbone ----------------
    async def read(self, name_or_address) -> int:
        from cocotbext.wishbone.driver import WBOp

        address = REG[name_or_address] if isinstance(name_or_address, str) else name_or_address
        result = await self.wb.send_cycle([WBOp(address)])
        self.last_ack = result[0].waitAck
        return int(result[0].datrd)

    async def write(self, name_or_address, value: int, sel: int = 0xF) -> None:
        from cocotbext.wishbone.driver import WBOp

        address = REG[name_or_address] if isinstance(name_or_address, str) else name_or_address
        result = await self.wb.send_cycle([WBOp(address, value & 0xFFFFFFFF, sel=sel)])
        self.last_ack = result[0].waitAck

    async def signed(self, name: str) -> int:
        value = await self.read(name)
        return value - (1 << 32) if value >> 31 else value

    async def position(self) -> list[int]:
        return [await self.signed(f"POS_{a}") for a in "XYZ"]

    async def state(self) -> int:
        return await self.read("STATUS") & 7

    # ---------------- records ----------------
    async def send(self, data: bytes) -> None:
        """The bytes on the record stream port (cmd_valid / cmd_ready)."""
        dut, i = self.dut, 0
        await FallingEdge(dut.clk)
        while i < len(data):
            dut.cmd_valid.value = 1
            dut.cmd_data.value = data[i]
            ready = int(dut.cmd_ready.value)      # stable from a rising edge to the next
            await FallingEdge(dut.clk)
            i += ready
        dut.cmd_valid.value = 0

    async def send_words(self, data: bytes) -> None:
        """The bytes through CMD_DATA, 4 a write; the last 1 .. 3 with only their byte
        selects set (no padding: a padding byte would start a record)."""
        for value, sel in data_words(data):
            await self.write("CMD_DATA", value, sel=sel)

    def records(self, commands) -> bytes:
        return b"".join(encode(c, self.build) for c in commands)

    async def wait_idle(self, max_cycles: int = 200_000, poll: int = 50) -> int:
        """Until STATUS says IDLE (not busy); the cycles waited."""
        start = self.cycle()
        while True:
            status = await self.read("STATUS")
            if status & 7 in (IDLE, ALARM) and not status & 8:
                return self.cycle() - start
            assert self.cycle() - start < max_cycles, f"not idle after {max_cycles} cycles: STATUS {status:#x}"
            for _ in range(poll):
                await FallingEdge(self.dut.clk)

    async def clocks(self, n: int) -> None:
        for _ in range(n):
            await FallingEdge(self.dut.clk)


def icarus_in_make_test(sim: str) -> None:
    """The controller's benches run on Icarus in `make test`, on Verilator too in `make
    test-all` (INTERP_TEST_ALL=1): a Verilator build of the controller costs about 40 s of CPU."""
    import os

    import pytest

    if sim != "icarus" and not os.environ.get("INTERP_TEST_ALL"):
        pytest.skip("Verilator build of the controller benches: run with `make test-all`")
