# SPDX-License-Identifier: Apache-2.0
"""interp.litex.CNCController: the controller as a LiteX peripheral, converted to Verilog by
Migen (the wrapper's Instance, its word-addressed LiteX Wishbone bus and its pads) and run
as the CPU of a SoC would drive it (cocotbext-wishbone on the LiteX bus, word addresses):
the constants and the build, the input pads in INPUTS, CONTROL.enable on its pad, and a
compiled G-code program written to CMD_DATA as the host's compact records (with their
codes; a stream whose length is not a multiple of 4: its last write selects only
its bytes) ending at its
programmed position, counted on the step pads and in POS_X/Y/Z."""
import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, FallingEdge

from interp.link import records
from interp.link.driver import settings_writes
from interp.link.registers import REG_ID, RESETS
from interp.simulation.runner import ROOT, run_cocotb
from interp.testing.controllerkit import CLEAR, ENABLE, REG, StepLog, data_words, icarus_in_make_test, watch_steps

CLOCK_HZ = 50_000                      # the machine's clock (the sim's period is arbitrary)
NAME = "litex_cnc"


class LiteXBench:
    def __init__(self, dut):
        self.dut = dut
        self.steps = StepLog()
        cocotb.start_soon(Clock(dut.sys_clk, 10, unit="ns").start())

    async def start(self):
        from cocotbext.wishbone.driver import WishboneMaster

        dut = self.dut
        for name in ("bus_cyc", "bus_stb", "bus_we", "bus_adr", "bus_dat_w", "estop", "limit", "probe"):
            getattr(dut, name).value = 0
        dut.bus_sel.value = 0xF
        dut.sys_rst.value = 1
        await ClockCycles(dut.sys_clk, 3)
        dut.sys_rst.value = 0
        self.wb = WishboneMaster(dut, "bus", dut.sys_clk, width=32, timeout=100_000, signals_dict={
            "cyc": "cyc", "stb": "stb", "we": "we", "adr": "adr", "datwr": "dat_w", "datrd": "dat_r",
            "ack": "ack", "sel": "sel"})
        cocotb.start_soon(watch_steps(dut, self.steps, lambda: 0))
        return self

    async def read(self, name: str) -> int:
        from cocotbext.wishbone.driver import WBOp

        return int((await self.wb.send_cycle([WBOp(REG[name] >> 2)]))[0].datrd)      # word address

    async def write(self, name: str, value: int, sel: int = 0xF) -> None:
        from cocotbext.wishbone.driver import WBOp

        await self.wb.send_cycle([WBOp(REG[name] >> 2, value & 0xFFFFFFFF, sel=sel)])


@cocotb.test()
async def soc_drives_the_controller(dut):
    from interp.commands.gcode import compile_text
    from interp.gcode.machine import load_machine

    tb = await LiteXBench(dut).start()
    assert await tb.read("ID") == RESETS["ID"] and REG["ID"] == REG_ID
    assert await tb.read("CLOCK_HZ") == CLOCK_HZ
    build = records.Build()
    assert await tb.read("BUILD0") == build.FEED_W | build.FRAC << 8 | build.NW << 16 | build.PF << 24
    # the input pads, through the synchronizer: estop bit 0, limit x/y/z bits 1..3, probe bit 4
    for estop, limit, probe in ((1, 0, 0), (0, 0b101, 0), (0, 0b010, 1), (0, 0, 0)):
        dut.estop.value, dut.limit.value, dut.probe.value = estop, limit, probe
        await ClockCycles(dut.sys_clk, 4)
        want = estop | limit << 1 | probe << 4
        assert await tb.read("INPUTS") == want, f"INPUTS {await tb.read('INPUTS'):#x}, pads {want:#x}"
    await tb.write("CONTROL", CLEAR)                          # the e-stop latched ERROR
    assert await tb.read("ERROR") == 0
    await FallingEdge(dut.sys_clk)
    assert int(dut.enable.value) == 0
    await tb.write("CONTROL", ENABLE)
    await FallingEdge(dut.sys_clk)
    assert int(dut.enable.value) == 1, "CONTROL.enable on the enable pad"

    # a program, as the firmware would: the settings, then the records through CMD_DATA
    machine = load_machine(clock_hz=CLOCK_HZ)
    _, compiled = compile_text("G21 G90 G17\nG01 X0.4 Y-0.2 F1200\nG02 X0.6 Y0 I0 J0.2\nG01 Z-0.1 F600\n", machine)
    for name, value in settings_writes(machine.timing(), compiled.settings, compiled):
        await tb.write(name, value)
    stream = records.encode_program(compiled.commands, build, codes=compiled)
    assert len(stream) < len(records.encode_program(compiled.commands, build)), "no code"
    assert len(stream) % 4, "the stream's last write is a partial one"
    for value, sel in data_words(stream, fill=0xFF):           # lanes not selected: 0xFF, ignored
        await tb.write("CMD_DATA", value, sel=sel)
    for _ in range(400):
        if await tb.read("EXECUTED") == len(compiled.commands) and not await tb.read("STATUS") & 8:
            break               # all executed, nothing left in the queue (no stray byte)
        await ClockCycles(dut.sys_clk, 500)
    else:
        raise AssertionError(f"STATUS {await tb.read('STATUS'):#x}: still busy")
    assert await tb.read("ERROR") == 0
    assert await tb.read("EXECUTED") == len(compiled.commands)
    position = [await tb.read(f"POS_{a}") for a in "XYZ"]
    position = [p - (1 << 32) if p >> 31 else p for p in position]
    assert position == list(compiled.end_steps) == tb.steps.position(), \
        f"POS {position}, pads {tb.steps.position()}, programmed {list(compiled.end_steps)}"


def generate(path):
    """The wrapper (default build, CURVES 0, a 4 KiB queue) as Verilog, module litex_cnc."""
    from migen import Module
    from migen.fhdl.verilog import convert

    from interp.litex import PADS, CNCController

    class Top(Module):
        def __init__(self):
            self.submodules.cnc = CNCController(None, None, clk_freq=CLOCK_HZ)

    top = Top()
    cnc = top.cnc
    bus = cnc.bus
    ios = {bus.adr, bus.dat_w, bus.dat_r, bus.sel, bus.cyc, bus.stb, bus.ack, bus.we, bus.err}
    ios |= {getattr(cnc, name) for name, _, _ in PADS}
    path.parent.mkdir(parents=True, exist_ok=True)
    convert(top, ios=ios, name=NAME).write(str(path))


def test_litex(sim):
    from interp.flows.synth import sources

    icarus_in_make_test(sim)
    generated = ROOT / "build" / "litex" / f"{NAME}.v"
    generate(generated)
    run_cocotb(toplevel=NAME, test_module="test_litex", sim=sim, name="litex",
               sources=[generated, *sources("controller")])
