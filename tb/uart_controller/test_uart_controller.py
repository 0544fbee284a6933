# SPDX-License-Identifier: Apache-2.0
"""uart_controller: the controller behind the UART link, through the UART pins only
(cocotbext-uart): HELLO -> ACK (free bytes, state, error); READ of ID, VERSION -> REPLY;
WRITE frames set the machine registers; DATA frames carry records (one record split over
two frames too) and the machine moves to the programmed end (POS_* read back over the
link); LINK_FRAMES counts the frames; an e-stop shows in the next ACK (ALARM, error 16);
the LEDs show the state.  The benches' small motion build, 5 clocks per UART bit."""
import cocotb
from cocotb.triggers import FallingEdge, Timer
from cocotbext.uart import UartSink, UartSource

from interp.models.motion import ARC_CW, LINE, Command, queue_steps
from interp.models.profile import profile_for
from interp.simulation import motion_build
from interp.simulation.runner import run_cocotb
from interp.testing.controllerkit import BUILD_PARAMETERS, REG, encode, icarus_in_make_test
from interp.testing.linkkit import ACK, DATA, HELLO, REPLY, AnswerParser, ack_fields, frame, read_frame, \
    reply_fields, write_frame
from interp.testing.tbkit import TB

PERIOD_NS = 10
PARAMETERS = {**motion_build.PARAMETERS, "QUEUE_AW": 8, "CLK_HZ": 15_000_000, "BAUD": 3_000_000, "CURVES": 0}


class UartBench:
    def __init__(self, dut):
        self.dut = dut
        self.tb = TB(dut, PERIOD_NS)
        baud = round(1e9 / (round(int(dut.CLK_HZ.value) / int(dut.BAUD.value)) * PERIOD_NS))
        self.source = UartSource(dut.uart_rx, baud=baud, bits=8)
        self.sink = UartSink(dut.uart_tx, baud=baud, bits=8)
        self.parser = AnswerParser()
        self.build = {k: int(getattr(dut.u_controller, k).value) for k in BUILD_PARAMETERS}
        self.seq = 0

    async def start(self):
        for name in ("estop", "limit", "probe"):
            getattr(self.dut, name).value = 0
        self.dut.uart_rx.value = 1
        await self.tb.reset({})
        return self

    async def answer(self, data: bytes, timeout_cycles: int = 20_000):
        await self.source.write(data)
        await self.source.wait()
        for _ in range(timeout_cycles // 100):
            await Timer(100 * PERIOD_NS, unit="ns")
            got = self.parser.feed(bytes(self.sink.read_nowait(self.sink.count())))
            if got:
                return got[0]
        raise AssertionError(f"no answer to {data.hex()}")

    async def read(self, name: str) -> int:
        kind, _, payload = await self.answer(read_frame(0, REG[name]))
        assert kind == REPLY and reply_fields(payload)["address"] == REG[name]
        return reply_fields(payload)["value"]

    async def sequenced(self, data: bytes) -> dict:
        kind, seq, payload = await self.answer(data)
        assert kind == ACK, f"answer {kind:#x} {payload.hex()}"
        self.seq += 1
        assert seq == self.seq % 256, f"ACK seq {seq}, want {self.seq}"
        return ack_fields(payload)

    async def write(self, name: str, value: int) -> dict:
        return await self.sequenced(write_frame(self.seq, REG[name], value))

    async def data(self, payload: bytes) -> dict:
        return await self.sequenced(frame(DATA, self.seq, payload))


@cocotb.test()
async def link_to_motion(dut):
    ub = await UartBench(dut).start()
    kind, seq, payload = await ub.answer(frame(HELLO, 0))
    assert (kind, seq, ack_fields(payload)) == (ACK, 0, {"free": 256, "state": 0, "error": 0})
    assert await ub.read("ID") == 0x494E5450
    assert await ub.read("VERSION") >> 8 & 0xFF == 36
    for name, value in (("QUANTUM_LO", 64), ("PULSE_WIDTH", 1), ("DIR_SETUP", 0), ("DIR_HOLD", 0)):
        await ub.write(name, value)
        assert await ub.read(name) == value
    cmds = profile_for([Command(LINE, 1 << 15, 9, -4, 2), Command(ARC_CW, 1 << 15, 0, 0, 0, 5, 0),
                        Command(LINE, 1 << 14, -3, 6, 0)], quantum=64, accel=32.0, frac=16, pf=12, width=16)
    records = b"".join(encode(c, ub.build) for c in cmds)
    await ub.data(records[:72])                                            # two records
    await ub.data(records[72:90])                                          # the third record over two frames
    await ub.data(records[90:])
    for _ in range(200):
        ack = await ub.sequenced(frame(DATA, ub.seq, b""))                 # an empty DATA frame: a status poll
        if ack["state"] == 0 and ack["free"] == 256:
            break
    steps, _ = queue_steps(cmds)
    end = [sum(s[a] for s in steps) for a in range(3)]
    assert [(v - (1 << 32)) if v >> 31 else v for v in [await ub.read(f"POS_{a}") for a in "XYZ"]] == end
    assert await ub.read("LINK_FRAMES") & 0xFFFF >= ub.seq                # every sequenced frame (and more)
    assert int(dut.led.value) & 0x1F == 0
    dut.estop.value = 1
    kind, _, payload = await ub.answer(frame(HELLO, 0))
    assert ack_fields(payload)["state"] == 4 and ack_fields(payload)["error"] == 16
    assert int(dut.led.value) & 0x1F == 0x14                               # ALARM, alarm LED
    await FallingEdge(dut.clk)


def test_uart_controller(sim):
    icarus_in_make_test(sim)
    run_cocotb(toplevel="uart_controller", test_module="test_uart_controller", sim=sim, parameters=PARAMETERS,
               name="uart_controller")
