# SPDX-License-Identifier: Apache-2.0
"""controller: record bytes -> segment queue -> unpacker -> motion_top -> input guard -> pins,
with the Wishbone register block (cocotbext-wishbone's WishboneMaster on wb_*).

Every register's reset value, read-write / read-only / write-1-strobe behaviour and the
unknown addresses; records through CMD_DATA and through the byte stream compared field by
field with the commands pushed into motion_top; a line + arc + helix program ending at its
programmed position (POS_*); e-stop and a limit switch mid-arc (the step pins low in the
cycle the synchronized input shows it, error latched until clear); feed hold and resume
mid-helix (no step lost); abort (mid-record too; at speed: ERROR 19) and restart; CONTROL.fill (records held,
then released at the unpacker's pace); rst at random cycles (seeded);
events -> outputs, PWM duty; the probe latch; POS_X/Y/Z set at rest (homing) and refused
while busy; bad records (kind 6, 7; a curve when the
curve core is left out).  The benches' small build (W 16, FRAC 16, CURVES 0, a 256-byte
queue) for most; the G-code build (W 32, FRAC 32, CURVES 1) runs a compiled G-code program.
Records come from interp.testing.controllerkit's encoder (the record format of the docs).
"""
import cocotb
from cocotb.triggers import ClockCycles, FallingEdge

from interp.link import records
from interp.link.driver import settings_writes
from interp.models.motion import ARC_CCW, ARC_CW, CURVE, DWELL, EVENT, LINE, Command, queue_steps
from interp.models.profile import profile_for
from interp.models.speed_ramp import BLOCK_SHIFT_MIN
from interp.simulation import motion_build
from interp.simulation.native.build import CLI_PARAMETERS
from interp.simulation.runner import run_cocotb
from interp.testing.controllerkit import (ABORT, ALARM, CLEAR, ENABLE, FILL, HELD, HOLD, IDLE, PROBE_ARM, PROBE_STOP,
                                          REG, RUN,
                                          ControllerBench, icarus_in_make_test, pushed_fields)
from interp.testing.tbkit import seeded_rng

SMALL = {**motion_build.PARAMETERS, "POS_W": 32, "QUEUE_AW": 8, "CLK_HZ": 1_000_000, "CURVES": 0}
CLI = {**CLI_PARAMETERS, "QUEUE_AW": 12, "CLK_HZ": 50_000, "CURVES": 1}
ONE = 1 << 16
REFUSED = 1 << 7                                     # STATUS.refused


class Bench(ControllerBench):
    async def start(self):
        await super().start()
        self.frac = int(self.dut.FRAC.value)
        self.scale = 1 << (self.frac - 16)
        self.settings = {"QUANTUM": 64 * self.scale, "PULSE_WIDTH": 1, "DIR_SETUP": 0, "DIR_HOLD": 0}
        await self.configure()
        return self

    async def configure(self):
        q = self.settings["QUANTUM"]
        await self.write("QUANTUM_LO", q & 0xFFFFFFFF)
        await self.write("QUANTUM_HI", q >> 32)
        for name in ("PULSE_WIDTH", "DIR_SETUP", "DIR_HOLD"):
            await self.write(name, self.settings[name])

    def profiled(self, cmds):
        top = min(ONE * self.scale, 1 << self.build["FEED_W"]) - 1
        cmds = [c if c.kind in (DWELL, EVENT) else Command(**{**c.__dict__, "feed": min(c.feed * self.scale, top)})
                for c in cmds]
        return profile_for(cmds, quantum=self.settings["QUANTUM"], accel=32.0 * self.scale, frac=self.frac,
                           pf=self.build["PF"], width=self.build["W"], feed_max=top, feed_w=self.build["FEED_W"])

    def end_of(self, cmds, start=(0, 0, 0)):
        steps, errors = queue_steps(cmds, self.build["W"])
        assert not errors, errors
        # (end position, pulses: one per stepping axis of each step)
        return [o + sum(s[a] for s in steps) for a, o in enumerate(start)], sum(abs(v) for s in steps for v in s)

    async def wait_steps(self, n, max_cycles=100_000):
        for _ in range(max_cycles):
            if len(self.steps.edges) >= n:
                return
            await FallingEdge(self.dut.clk)
        raise AssertionError(f"fewer than {n} steps after {max_cycles} cycles")

    async def quiet(self, cycles):
        """No step edge for `cycles` cycles."""
        before = len(self.steps.edges)
        await self.clocks(cycles)
        assert len(self.steps.edges) == before, f"{len(self.steps.edges) - before} steps while stopped"


LINE_ARC_HELIX = [Command(LINE, ONE // 3, 12, -5, 3), Command(ARC_CCW, ONE // 3, 8, 8, 0, 8, 0),
                  Command(ARC_CW, ONE // 4, 0, 0, -9, -6, 2, 40, plane=1),     # a full turn, helix in y
                  Command(LINE, ONE // 2, -4, 0, 0)]


@cocotb.test()
async def registers(dut):
    """Reset values; RW fields read back (masked to their widths); RO registers ignore writes;
    CONTROL's strobes read 0; unknown addresses read 0 and ignore writes; ack in 1-2 cycles."""
    tb = await ControllerBench(dut).start()
    b, rb = tb.build, tb.rb
    aw, clk = int(dut.QUEUE_AW.value), int(dut.CLK_HZ.value)
    size, tw_mask, feed_mask = 1 << aw, (1 << b["TW"]) - 1, (1 << b["FEED_W"]) - 1
    half_us = max(1, clk // 2_000_000)
    reset = {"ID": 0x494E5450, "VERSION": 1 | rb << 8 | b["W"] << 16 | b["POS_W"] << 24,
             "BUILD0": b["FEED_W"] | b["FRAC"] << 8 | b["NW"] << 16 | b["PF"] << 24,
             "BUILD1": b["LEN_W"] | b["ZW"] << 8 | b["MW"] << 16 | b["TW"] << 24, "CLOCK_HZ": clk,
             "QUEUE_SIZE": size | aw << 16 | int(dut.CURVES.value) << 24, "STATUS": 0, "ERROR": 0,
             "QUEUE_FREE": size | (size // rb) << 16, "OVERRIDE": 100, "PULSE_WIDTH": half_us,
             "DIR_SETUP": half_us, "DIR_HOLD": half_us, "QUANTUM_LO": 1, "SPINDLE_PERIOD": clk // 20000,
             "MOTION": BLOCK_SHIFT_MIN, "INPUT_FILTER": 0x1F << 16, "SPINDLE_OVERRIDE": 256}
    names = sorted(REG, key=REG.get)
    want = {n: reset.get(n, 0) for n in names}
    for name in names:
        got = await tb.read(name)
        assert got == want[name], f"{name} after reset: {got:#x}, want {want[name]:#x}"
        assert tb.last_ack <= 2, f"{name}: ack after {tb.last_ack} cycles"
    rw = {"OVERRIDE": 0xFF, "PULSE_WIDTH": tw_mask, "DIR_SETUP": tw_mask, "DIR_HOLD": tw_mask,
          "QUANTUM_LO": feed_mask & 0xFFFFFFFF, "QUANTUM_HI": feed_mask >> 32, "MOTION": 0x3F3FFF,
          "LIMIT_SCALE": 0xFFFFFFFF, "RATE_SCALE": 0xFFFFFFFF,
          "SPINDLE_PERIOD": 0xFFFF, "POS_X": 0xFFFFFFFF, "POS_Y": 0xFFFFFFFF, "POS_Z": 0xFFFFFFFF,
          "OUTPUT_INVERT": 0xFFFF, "INPUT_FILTER": 0x1FFFFF, "SPINDLE_OVERRIDE": 0x3FF}
    for name, mask in rw.items():
        for value in (0xFFFFFFFF, 0x5A5A5A5A, 0):
            await tb.write(name, value)
            got = await tb.read(name)
            assert got == value & mask, f"{name}: wrote {value:#x}, read {got:#x}"
            assert tb.last_ack <= 2
    for name in ("ID", "VERSION", "BUILD0", "BUILD1", "CLOCK_HZ", "QUEUE_SIZE", "STATUS", "ERROR", "QUEUE_FREE",
                 "PROBE_Z", "INPUTS", "OUTPUTS", "LINK_FRAMES", "LINK_ERRORS", "EXECUTED"):
        before = await tb.read(name)
        await tb.write(name, 0xFFFFFFFF ^ before)
        assert await tb.read(name) == before, f"{name} is read-only"
    assert await tb.read("STATUS") >> 16 == 0b111       # position_set: every POS register written
    # CONTROL: hold, enable, fill and probe_stop are RW, abort / clear / probe_arm read 0
    await tb.write("CONTROL", 0xFFFFFFFF)
    assert await tb.read("CONTROL") == HOLD | ENABLE | FILL | PROBE_STOP
    assert int(dut.enable.value) == 1
    assert await tb.state() == HELD                  # hold at rest (filling): held
    await tb.write("CONTROL", HOLD)
    assert await tb.state() == HELD                  # hold at rest: held
    await tb.write("CONTROL", 0)
    assert await tb.read("CONTROL") == 0 and int(dut.enable.value) == 0
    # unknown addresses and CMD_DATA read 0; writes there change nothing
    snapshot = {n: await tb.read(n) for n in names}
    for address in (0x90, 0xA4, 0xFC, 0x91, 0x03):
        await tb.write(address, 0xFFFFFFFF)
        assert await tb.read(address) == (0 if address != 0x03 else 0x494E5450), f"address {address:#x}"
    assert {n: await tb.read(n) for n in names} == snapshot
    # link counters: inputs
    dut.link_frames.value, dut.link_duplicates.value = 0x1234, 0xABCD
    dut.link_errors.value, dut.link_gaps.value = 7, 0xFFFF
    assert await tb.read("LINK_FRAMES") == 0xABCD1234
    assert await tb.read("LINK_ERRORS") == 0xFFFF0007
    # INPUT_INVERT: every input reads active, the e-stop latches ERROR 16 (ALARM) until clear
    await tb.write("INPUT_INVERT", 0xFFFFFFFF)
    assert await tb.read("INPUT_INVERT") == 0x1F
    assert await tb.read("INPUTS") == 0x1F
    assert await tb.read("ERROR") == 16 and await tb.state() == ALARM
    await tb.write("CONTROL", CLEAR)
    assert await tb.read("ERROR") == 16              # the e-stop is still active
    await tb.write("INPUT_INVERT", 0)
    await tb.write("CONTROL", CLEAR)
    assert await tb.read("ERROR") == 0 and await tb.state() == IDLE
    # INPUT_FILTER: the pins go through the filter (then the polarity): with period 50 a
    # limit pin's change counts 4 samples later (151 .. 200 clocks), a glitch of 150 never;
    # the e-stop, left out of the mask (0x1E), counts at once
    await tb.write("INPUT_FILTER", 0x1E << 16 | 50)
    dut.limit.value = 0b001
    await ClockCycles(dut.clk, 150)
    dut.limit.value = 0
    await ClockCycles(dut.clk, 250)
    assert await tb.read("INPUTS") == 0 and await tb.read("ERROR") == 0, "a glitch of 150 clocks"
    dut.limit.value = 0b001
    assert await tb.read("INPUTS") == 0
    await ClockCycles(dut.clk, 210)
    assert await tb.read("INPUTS") == 0b0010 and await tb.read("ERROR") == 17 | 1 << 8
    dut.limit.value = 0
    dut.estop.value = 1
    await ClockCycles(dut.clk, 3)
    assert await tb.read("INPUTS") == 0b0011
    dut.estop.value = 0
    await ClockCycles(dut.clk, 210)
    await tb.write("CONTROL", CLEAR)
    assert await tb.read("ERROR") == 0 and await tb.state() == IDLE
    await tb.write("INPUT_FILTER", 0x1F << 16)
    # OUTPUT_INVERT: each output pin is its logical value XOR its bit (at rest all logical 0)
    pins = ("step", "dir", "enable", "spindle_on", "spindle_ccw", "spindle_pwm", "mist", "flood", "dout")
    for value in (0xFFFF, 0x5A5A, 0):
        await tb.write("OUTPUT_INVERT", value)
        got = [int(getattr(dut, pin).value) for pin in pins]
        assert got == [value & 7, value >> 3 & 7, *[value >> b & 1 for b in range(6, 12)], value >> 12], got
    # rst restores every reset value
    await tb.write("OUTPUT_INVERT", 0xFFFF)
    await tb.write("OVERRIDE", 33)
    await tb.reset()
    assert {n: await tb.read(n) for n in names} == {**want, "LINK_FRAMES": 0xABCD1234, "LINK_ERRORS": 0xFFFF0007}


@cocotb.test()
async def records_to_motion_top(dut):
    """Seeded random records (dwells and events with every field random at full width, and
    moves) through the byte stream and through CMD_DATA (compact records too, the bytes of a
    write its byte selects): motion_top sees exactly their fields, in order, none dropped
    although the queues fill; STATUS records and QUEUE_FREE agree."""
    rng = seeded_rng(dut, "records_to_motion_top")
    tb = await Bench(dut).start()
    b = tb.build

    def field(bits):
        return rng.getrandbits(bits)

    def signed(bits):
        return rng.randint(-(1 << (bits - 1)), (1 << (bits - 1)) - 1)

    cmds = []
    for n in range(24):
        if rng.random() < 0.2:
            cmds += tb.profiled([Command(LINE, rng.randint(ONE // 4, ONE - 1), rng.randint(-5, 5), rng.randint(1, 5))])
            continue
        kind = rng.choice([DWELL, EVENT])
        code = rng.randint(13, 255) if kind == EVENT else rng.randint(0, 400)   # no machine event
        cmds.append(Command(kind, field(b["FEED_W"]), code, *(signed(b["W"]) for _ in range(6)),
                            plane=rng.randint(0, 3), limit=field(b["FEED_W"]), exit=field(b["NW"]),
                            rate=field(b["PF"] + 1), cost=field(b["FEED_W"]), length=field(b["LEN_W"]),
                            budget=field(b["ZW"])))
    half = len(cmds) // 2
    encoder = records.Encoder(b)                  # (the bases: the last record of each class)
    await tb.send(b"".join(encoder.record(c, False) for c in cmds[:half]))
    # while the queue holds records: the counters agree
    status, free = await tb.read("STATUS"), await tb.read("QUEUE_FREE")
    assert free >> 16 == (free & 0xFFFF) // tb.rb, f"QUEUE_FREE {free:#x}"
    assert 0 <= (status >> 8 & 0xFF) - (half - len(tb.pushes)) <= 1, f"STATUS {status:#x}"   # a push may follow
    assert status & 8, "busy"
    # the rest through CMD_DATA as compact records (the stream's length is not a multiple of
    # 4): a write selecting no byte queues nothing, one selecting lanes 0 and 2 queues those two
    stream = b"".join(encoder.record(c, rng.random() < 0.7) for c in cmds[half:])
    await tb.write("CMD_DATA", rng.getrandbits(32), sel=0)
    await tb.write("CMD_DATA", stream[0] | rng.getrandbits(8) << 8 | stream[1] << 16 | rng.getrandbits(8) << 24,
                   sel=0b0101)
    await tb.send_words(stream[2:-5])
    await tb.send_words(stream[-5:])                         # 4 bytes, then 1
    await tb.wait_idle()
    want = [pushed_fields(c, b) for c in cmds]
    assert len(tb.pushes) == len(want), f"{len(tb.pushes)} commands pushed, want {len(want)}"
    for n, (got, exp) in enumerate(zip(tb.pushes, want)):
        assert got == exp, f"record {n}: pushed {got}, want {exp}"
    assert await tb.read("ERROR") == 0
    assert await tb.read("EXECUTED") == len(cmds)
    size = 1 << int(dut.QUEUE_AW.value)
    assert await tb.read("QUEUE_FREE") == size | (size // tb.rb) << 16


@cocotb.test()
async def program_ends_at_its_position(dut):
    """A line, an arc, a helix (a full turn in ZX with y travel) and a line through the record
    stream: every step once, POS_X/Y/Z = the programmed end, STATUS back to IDLE."""
    tb = await Bench(dut).start()
    cmds = tb.profiled(LINE_ARC_HELIX)
    await tb.send(tb.records(cmds))
    await tb.wait_idle()
    end, n = tb.end_of(cmds)
    assert await tb.position() == end == tb.steps.position(), f"end {await tb.position()}, programmed {end}"
    assert len(tb.steps.edges) == n
    assert await tb.read("STATUS") == IDLE and await tb.read("ERROR") == 0


async def trip_mid_arc(tb, pin, value, code):
    """Start a long arc, trip `pin` mid-way: the steps are gated in the cycle the synchronized
    input shows it; ERROR, ALARM; positions = the pulses that went out; EXECUTED counts the
    arc only, not the records the alarm discards from motion_top's queue."""
    dut = tb.dut
    executed = await tb.read("EXECUTED")
    cmds = tb.profiled([Command(ARC_CW, ONE // 2, 0, 0, 0, 15, 0)]     # a full circle, radius 15
                       + [Command(LINE, ONE // 2, 2, 1, 0)] * 3)        # waiting behind it
    await tb.send(tb.records(cmds))
    await tb.wait_steps(len(tb.steps.edges) + 20)
    getattr(dut, pin).value = value
    for waited in range(6):
        await FallingEdge(dut.clk)
        synced = int(dut.u_guard.inputs.value)
        if synced & 0xF:
            break
    assert synced & 0xF and waited <= 2, "the synchronizer takes two clocks"
    assert int(dut.step.value) == 0, "a step pin is high in the cycle the trip shows"
    await tb.quiet(200)
    assert await tb.read("ERROR") == code
    assert await tb.state() == ALARM
    assert await tb.position() == tb.steps.position()
    size = 1 << int(dut.QUEUE_AW.value)
    assert await tb.read("QUEUE_FREE") & 0xFFFF == size, "ALARM flushes the queue"
    assert await tb.read("EXECUTED") == executed + 1, "the records behind the arc never ran"


@cocotb.test()
async def inverted_step_and_dir_pins(dut):
    """OUTPUT_INVERT on step and dir (active-low drivers, a motor turning the wrong way): the pins
    carry the complements, so the pins' rising edges (the monitor's) are as many as the steps and
    the pins' travel is the negated one, while POS_X/Y/Z count the logical steps."""
    tb = await Bench(dut).start()
    await tb.write("OUTPUT_INVERT", 0x3F)
    assert len(tb.steps.edges) == 3
    tb.steps.edges.clear()                  # the write's edge on each step pin (documented)
    cmds = tb.profiled(LINE_ARC_HELIX)
    await tb.send(tb.records(cmds))
    await tb.wait_idle()
    end, n = tb.end_of(cmds)
    assert await tb.position() == end and tb.steps.position() == [-v for v in end], (end, tb.steps.position())
    assert len(tb.steps.edges) == n and int(dut.step.value) == 7


@cocotb.test()
async def polarity_from_the_reset(dut):
    """INPUT_INVERT_RESET and OUTPUT_INVERT_RESET (a board built for active-low drivers and a
    touch plate): the registers and the pins have them from rst on, before any write, and rst
    restores them after one."""
    tb = await Bench(dut).start()
    inputs, outputs = int(dut.INPUT_INVERT_RESET.value), int(dut.OUTPUT_INVERT_RESET.value)
    assert outputs and inputs == 0x10

    async def check():
        assert await tb.read("OUTPUT_INVERT") == outputs and await tb.read("INPUT_INVERT") == inputs
        assert await tb.read("INPUTS") == 0x10 and await tb.read("ERROR") == 0      # the probe pin at 0: touching
        assert [int(dut.step.value), int(dut.dir.value), int(dut.enable.value)] == \
            [outputs & 7, outputs >> 3 & 7, outputs >> 6 & 1]

    await check()
    await tb.write("OUTPUT_INVERT", 0)
    await tb.write("INPUT_INVERT", 0)
    assert int(dut.enable.value) == 0 and await tb.read("INPUTS") == 0
    await tb.reset()
    await check()


@cocotb.test()
async def estop_and_limit_mid_arc(dut):
    """E-stop mid-arc: steps gated at once, ERROR 16 until the e-stop is released and cleared.
    A limit switch (y) mid-arc: ERROR 17 with bit 9 (y); cleared while the switch is still
    active, it stays clear and the machine moves (off the switch); positions stay exact."""
    tb = await Bench(dut).start()
    await trip_mid_arc(tb, "estop", 1, 16)
    await tb.write("CONTROL", CLEAR)
    assert await tb.read("ERROR") == 16, "cleared while the e-stop is active"
    dut.estop.value = 0
    await tb.clocks(4)
    await tb.write("CONTROL", CLEAR)
    assert await tb.read("ERROR") == 0 and await tb.state() == IDLE
    start = await tb.position()
    await trip_mid_arc(tb, "limit", 0b010, 17 | 0b010 << 8)
    await tb.write("CONTROL", CLEAR)
    assert await tb.read("ERROR") == 0 and await tb.read("INPUTS") == 0b0100
    start = await tb.position()
    cmds = tb.profiled([Command(LINE, ONE // 2, 0, -6, 0)])
    await tb.send(tb.records(cmds))
    await tb.wait_idle()
    dut.limit.value = 0
    assert await tb.position() == tb.end_of(cmds, start)[0] == tb.steps.position()
    assert await tb.read("ERROR") == 0


@cocotb.test()
async def hold_resume_mid_helix(dut):
    """Feed hold mid-helix: decelerates to HELD, no step while held; resume: every step once,
    the end position exact."""
    tb = await Bench(dut).start()
    cmds = tb.profiled([Command(ARC_CCW, ONE // 2, 0, 0, 25, 0, 10, 63, plane=2),
                        Command(LINE, ONE // 2, 3, 3, 3)])
    await tb.send(tb.records(cmds))
    await tb.wait_steps(30)
    await tb.write("CONTROL", HOLD)
    for _ in range(2000):
        if await tb.state() == HELD:
            break
    assert await tb.state() == HELD
    assert await tb.read("STATUS") & 16, "stopped"
    await tb.quiet(500)
    await tb.write("CONTROL", 0)
    assert await tb.state() == RUN
    await tb.wait_idle()
    end, n = tb.end_of(cmds)
    assert await tb.position() == end == tb.steps.position()
    assert len(tb.steps.edges) == n


@cocotb.test()
async def abort_and_restart(dut):
    """Abort mid-program at speed: the steps stop, queue and partial record flushed, positions
    kept, and ERROR 19 (ALARM: the motors may have lost steps) until CONTROL.clear; half a
    record is not busy, and a record cut by an abort is dropped; the next program runs from
    where the machine is."""
    tb = await Bench(dut).start()
    cmds = tb.profiled([Command(LINE, ONE // 2, 40, 10, 0), Command(LINE, ONE // 2, -30, 20, 5)] * 3)
    await tb.send(tb.records(cmds))
    await tb.wait_steps(25)
    executed = await tb.read("EXECUTED")                 # the first record (no other has begun)
    await tb.write("CONTROL", ABORT)
    await tb.quiet(300)
    assert executed == 1 and await tb.read("EXECUTED") == 1, "the aborted records were never run"
    size = 1 << int(dut.QUEUE_AW.value)
    assert await tb.read("QUEUE_FREE") == size | (size // tb.rb) << 16
    assert await tb.read("ERROR") == 19 and await tb.state() == ALARM, "an abort at speed"
    await tb.write("CONTROL", CLEAR)
    assert await tb.read("STATUS") == IDLE and await tb.read("ERROR") == 0
    kept = await tb.position()
    assert kept == tb.steps.position() and kept != [0, 0, 0]
    # half a record: IDLE, not busy, no record (a host may start a program); then abort: dropped
    await tb.send(tb.records(cmds[:1])[:tb.rb // 2])
    await tb.clocks(tb.rb)
    status = await tb.read("STATUS")
    assert status & 0xFF0F == IDLE, f"STATUS {status:#x} with half a record"
    await tb.write("CONTROL", ABORT)
    again = tb.profiled([Command(LINE, ONE // 2, -5, 7, 1), Command(ARC_CW, ONE // 3, 0, 0, 0, 4, 0)])
    await tb.send(tb.records(again))
    await tb.wait_idle()
    assert await tb.position() == tb.end_of(again, kept)[0] == tb.steps.position()
    assert await tb.read("EXECUTED") == 1 + len(again)


@cocotb.test()
async def fill_then_run(dut):
    """CONTROL.fill: the records wait in the queue (none reaches motion_top, no step, STATUS
    counts them, RUN); cleared, the first record enters motion_top within two clocks of the
    write's ack and the next ones exactly RECORD_BYTES + 1 clocks apart (the unpacker's pace,
    which interp gcode keeps); the program ends at its position."""
    tb = await Bench(dut).start()
    await tb.write("CONTROL", ENABLE | FILL)
    cmds = tb.profiled([Command(EVENT, 0, 200), Command(EVENT, 0, 201), Command(LINE, ONE // 2, 6, -4, 1)])
    await tb.send(tb.records(cmds))
    await tb.clocks(3 * tb.rb)
    assert tb.pushes == [] and tb.steps.edges == []
    status = await tb.read("STATUS")
    assert status >> 8 & 0xFF == len(cmds) and status & 7 == RUN, f"STATUS {status:#x}"
    await tb.write("CONTROL", ENABLE)
    released = tb.cycle()
    await tb.wait_idle()
    assert len(tb.push_cycles) == len(cmds)
    assert abs(tb.push_cycles[0] - released) <= 2, (released, tb.push_cycles)
    assert [b - a for a, b in zip(tb.push_cycles, tb.push_cycles[1:])] == [tb.rb + 1] * (len(cmds) - 1)
    assert await tb.position() == tb.end_of(cmds[2:])[0] == tb.steps.position()


@cocotb.test()
async def reset_at_random_cycles(dut):
    """rst at seeded random cycles while records stream in, the machine moves and the spindle
    runs: IDLE at once, pins low, positions 0, registers at reset; then a program runs exactly."""
    rng = seeded_rng(dut, "reset_at_random_cycles")
    tb = await Bench(dut).start()
    job = tb.profiled([Command(EVENT, 0, 1, 30000), Command(LINE, ONE // 2, 20, -9, 4),
                       Command(ARC_CCW, ONE // 2, 0, 0, 0, 6, 0), Command(EVENT, 0, 5, 0)] * 2)
    for n in range(3):
        await tb.write("CONTROL", ENABLE)
        sender = cocotb.start_soon(tb.send(tb.records(job)))
        await tb.clocks(rng.randint(1, 1200))
        sender.cancel()
        dut.cmd_valid.value = 0
        dut.rst.value = 1
        await FallingEdge(dut.clk)
        dut.rst.value = 0
        for _ in range(20):
            assert int(dut.step.value) == 0 and int(dut.spindle_on.value) == 0 and int(dut.enable.value) == 0
            await FallingEdge(dut.clk)
        assert await tb.read("STATUS") == IDLE
        assert await tb.position() == [0, 0, 0]
        assert await tb.read("OUTPUTS") == 0 and await tb.read("EXECUTED") == 0
        size = 1 << int(dut.QUEUE_AW.value)
        assert await tb.read("QUEUE_FREE") == size | (size // tb.rb) << 16
        assert await tb.read("QUANTUM_LO") == 1
        await tb.configure()
        tb.steps.edges.clear()
        cmds = tb.profiled([Command(LINE, ONE // 2, 3, -4, 2)])
        await tb.send(tb.records(cmds))
        await tb.wait_idle()
        assert await tb.position() == tb.end_of(cmds)[0] == tb.steps.position(), f"after reset {n}"


async def pwm_high(tb, cycles):
    high = 0
    for _ in range(cycles):
        await FallingEdge(tb.dut.clk)
        high += int(tb.dut.spindle_pwm.value)
    return high


@cocotb.test()
async def events_drive_outputs(dut):
    """Spindle cw / ccw / speed / off with the PWM duty (and SPINDLE_OVERRIDE's scale on it,
    OUTPUTS keeping the programmed duty), mist, flood, coolant off, outputs on /
    off (a bad output number ignored), unknown codes ignored, program end; pause sets the hold
    (the next move waits until it is released), and two pauses in a row hold twice; abort
    switches the spindle off."""
    tb = await Bench(dut).start()
    await tb.write("SPINDLE_PERIOD", 100)

    async def events(*pairs):
        await tb.send(tb.records([Command(EVENT, 0, code, value) for code, value in pairs]))
        await tb.wait_idle()
        await tb.clocks(250)                         # the PWM threshold follows within two periods
        return await tb.read("OUTPUTS")

    assert await events((1, 16384)) == 1 | 16384 << 16
    assert await pwm_high(tb, 400) == 100           # 25 % of 100-clock periods
    assert await events((2, 32767)) == 3 | 32767 << 16
    assert abs(await pwm_high(tb, 400) - 200) <= 4
    for scale, high in ((384, 300), (128, 100), (1023, 400), (256, 200)):   # SPINDLE_OVERRIDE: 150, 50, 400, 100 %
        await tb.write("SPINDLE_OVERRIDE", scale)
        await tb.clocks(250)
        assert await tb.read("SPINDLE_OVERRIDE") == scale and await tb.read("OUTPUTS") >> 16 == 32767
        assert abs(await pwm_high(tb, 400) - high) <= 4, f"scale {scale}"
    assert await events((4, -5)) == 3
    assert await pwm_high(tb, 300) == 0
    assert await events((4, 65535 >> (16 - min(16, tb.build["W"] - 1))), (3, 0)) & 0xFFFF == 2
    assert await events((5, 0), (6, 0)) & 0xF == 0b1110

    async def pins_follow(mask):
        # each pin: its logical output (OUTPUTS) XOR its OUTPUT_INVERT bit
        await tb.write("OUTPUT_INVERT", mask)
        out = await tb.read("OUTPUTS")
        for pin, at, bit, width in (("spindle_on", 0, 7, 1), ("spindle_ccw", 1, 8, 1), ("mist", 2, 10, 1),
                                    ("flood", 3, 11, 1), ("dout", 4, 12, 4)):
            field = (1 << width) - 1
            assert int(getattr(dut, pin).value) == (out >> at & field) ^ (mask >> bit & field), (pin, hex(mask))

    for mask in (0xFF80, 0x5A80, 0):
        await pins_follow(mask)
    assert await events((7, 0)) & 0xF == 0b0010
    assert await events((8, 2), (8, 0), (8, 7), (8, -1)) & 0xF0 == 0b0101 << 4
    for mask in (0xF580, 0x3100, 0):
        await pins_follow(mask)
    assert await events((9, 2), (99, 1), (0, 3)) & 0xF0 == 0b0001 << 4
    assert await events((1, 100), (5, 0), (6, 0), (12, 0)) & 0xFF == 0b00010000   # program end
    # pause: CONTROL.hold set; the line after it waits
    cmds = tb.profiled([Command(EVENT, 0, 10, 0), Command(LINE, ONE // 2, 5, 0, 0)])
    await tb.send(tb.records(cmds))
    await tb.clocks(300)
    assert await tb.read("CONTROL") & HOLD and await tb.state() == HELD
    assert tb.steps.position() == [0, 0, 0]
    await tb.write("CONTROL", 0)
    await tb.wait_idle()
    assert await tb.position() == [5, 0, 0]
    # two pauses in a row (M0, then T2 M6: tool change 2, which does not hold, and pause 6): each
    # holds, the second only after the first's release
    cmds = tb.profiled([Command(EVENT, 0, 10, 0), Command(EVENT, 0, 11, 2), Command(EVENT, 0, 10, 6),
                        Command(LINE, ONE // 2, 5, 0, 0)])
    await tb.send(tb.records(cmds))
    for release in range(2):
        await tb.clocks(300)
        assert await tb.read("CONTROL") & HOLD and await tb.state() == HELD, f"pause {release + 1}"
        assert tb.steps.position() == [5, 0, 0]
        await tb.write("CONTROL", 0)
    await tb.wait_idle()
    assert await tb.position() == [10, 0, 0]
    # abort: spindle and coolant off at once
    await events((1, 1000), (6, 0))
    assert int(dut.spindle_on.value) and int(dut.flood.value)
    await tb.write("CONTROL", ABORT)
    assert await tb.read("OUTPUTS") & 0xD == 0 and not int(dut.spindle_pwm.value)


@cocotb.test()
async def probe_latch(dut):
    """probe_arm, a move, the probe's edge: PROBE_X/Y/Z = the position at the edge (within the
    synchronizer's two clocks), probe_valid; later edges change nothing until the next arm;
    an inverted probe input."""
    tb = await Bench(dut).start()
    await tb.write("CONTROL", PROBE_ARM)
    assert not await tb.read("STATUS") & 32
    cmds = tb.profiled([Command(LINE, ONE // 4, 30, 15, -5)])
    await tb.send(tb.records(cmds))
    await tb.wait_steps(20)
    at = tb.steps.position()
    dut.probe.value = 1
    await tb.clocks(4)
    after = tb.steps.position()
    probed = [await tb.signed(f"PROBE_{a}") for a in "XYZ"]
    assert all(min(a, b) <= p <= max(a, b) for p, a, b in zip(probed, at, after)), (probed, at, after)
    assert await tb.read("STATUS") & 32
    dut.probe.value = 0
    await tb.clocks(30)
    dut.probe.value = 1
    await tb.clocks(5)
    assert [await tb.signed(f"PROBE_{a}") for a in "XYZ"] == probed, "an edge without arming"
    await tb.wait_idle()
    # inverted: the probe pin low is active
    await tb.write("INPUT_INVERT", 0x10)
    await tb.write("CONTROL", PROBE_ARM)
    assert not await tb.read("STATUS") & 32
    dut.probe.value = 0
    await tb.clocks(5)
    assert await tb.read("STATUS") & 32
    assert [await tb.signed(f"PROBE_{a}") for a in "XYZ"] == await tb.position() == tb.end_of(cmds)[0]


@cocotb.test()
async def probe_stops_the_motion(dut):
    """CONTROL.probe_stop: the armed probe's touch latches the position and holds, so the move
    decelerates to rest on its path (steps slowing, none lost: the position counters equal the
    pulses), stopping short of its end; abort then flushes it (G38.2).  Without probe_stop the
    touch only latches (probe_latch)."""
    tb = await Bench(dut).start()
    await tb.write("CONTROL", PROBE_ARM | PROBE_STOP)
    assert await tb.read("CONTROL") == PROBE_STOP
    cmds = tb.profiled([Command(LINE, ONE // 4, 60, 0, 0)])
    end, _ = tb.end_of(cmds)
    await tb.send(tb.records(cmds))
    await tb.wait_steps(25)
    dut.probe.value = 1
    await tb.clocks(4)
    probed = [await tb.signed(f"PROBE_{a}") for a in "XYZ"]
    for _ in range(200):
        if await tb.state() == HELD:
            break
        await tb.clocks(50)
    assert await tb.state() == HELD and await tb.read("CONTROL") & HOLD
    stopped = await tb.position()
    assert stopped == tb.steps.position() and probed[0] <= stopped[0] < end[0], (probed, stopped, end)
    times = [t for t, _, _ in tb.steps.edges]
    gaps = [b - a for a, b in zip(times, times[1:])]
    assert gaps[-1] > gaps[24], "no deceleration after the touch"          # (the touch: after step 25)
    await tb.quiet(500)
    await tb.write("CONTROL", ABORT | PROBE_STOP)
    await tb.wait_idle()
    assert await tb.position() == stopped and await tb.read("ERROR") == 0
    dut.probe.value = 0


@cocotb.test()
async def bad_records(dut):
    """A record of kind 6 or 7: ERROR 18, ALARM; a curve in a build without the curve core:
    ERROR 1 (motion_top's); after clear the next program runs."""
    tb = await Bench(dut).start()
    good = tb.profiled([Command(LINE, ONE // 2, 2, 1, 0)])
    for kind, code in ((6, 18), (7, 18)) + (((CURVE, 1),) if not int(dut.CURVES.value) else ()):
        bad = tb.profiled([Command(kind, ONE // 2, 8, 0, 25, 0, 0, 1, 0)])
        if kind == CURVE:
            bad[0].length, bad[0].rate, bad[0].limit = 100, 1, bad[0].feed
        await tb.send(tb.records(bad + good))
        await tb.clocks(50)
        assert await tb.read("ERROR") == code and await tb.state() == ALARM, f"kind {kind}"
        await tb.write("CONTROL", CLEAR)
        assert await tb.state() == IDLE
    start = await tb.position()
    await tb.send(tb.records(good))
    await tb.wait_idle()
    assert await tb.position() == tb.end_of(good, start)[0]


@cocotb.test()
async def abort_meets_a_bad_record(dut):
    """CONTROL abort + clear (what `interp send` writes before a run) at every clock around
    a bad record's end: IDLE with ERROR 0 every time (an error found in the clock of an
    abort belongs to what the abort discards)."""
    tb = await Bench(dut).start()
    bad = tb.records(tb.profiled([Command(6, ONE // 2, 8, 0, 25, 0, 0, 1, 0)]))
    for delay in range(tb.rb + 24):
        await tb.send(bad)
        await tb.clocks(delay)
        await tb.write("CONTROL", ABORT | CLEAR)
        await tb.clocks(4)
        assert await tb.read("ERROR") == 0 and await tb.state() == IDLE, \
            f"abort and clear {delay} clocks after the bad record's last byte"


@cocotb.test()
async def gcode_program(dut):
    """The G-code build: a compiled G-code program (spindle, coolant, line, arc, helix, ZX arc,
    program end) with the machine settings the host writes: ends at its programmed end, the
    spindle ran during the moves and is off at the end."""
    from interp.commands.gcode import compile_text
    from interp.gcode.machine import load_machine

    tb = await ControllerBench(dut).start()
    machine = load_machine(clock_hz=int(dut.CLK_HZ.value))
    text = ("G21 G90 G17\nM3 S12000\nM8\nG01 X1 F1200\nG03 X1.5 Y0.5 I0 J0.5\nG03 X1 Y1 Z-0.3 I-0.5 J0\n"
            "G01 X0\nG18 G02 X-0.4 Z-0.3 I-0.2 K0\nG17 G00 X0.2 Y0.1 Z0.2\nM9\nM2\n")
    _, compiled = compile_text(text, machine, costs="true")
    for name, value in settings_writes(machine.timing(), compiled.settings, compiled):
        await tb.write(name, value)
    data = b"".join(
        __import__("interp.testing.controllerkit", fromlist=["encode"]).encode(c, tb.build) for c in compiled.commands)
    sender = cocotb.start_soon(tb.send(data))
    spun = False
    while not sender.done() or await tb.state() != IDLE or await tb.read("STATUS") & 8:
        spun |= bool(await tb.read("OUTPUTS") & 1)
        assert await tb.read("ERROR") == 0, f"ERROR {await tb.read('ERROR')}"
        await tb.clocks(200)
    assert spun, "the spindle never ran"
    assert await tb.position() == list(compiled.end_steps) == tb.steps.position()
    assert await tb.read("OUTPUTS") & 0xF == 0
    assert await tb.read("EXECUTED") == len(compiled.commands)


@cocotb.test()
async def laser_program(dut):
    """The G-code build in laser mode: with M4 the PWM's power follows the speed (power_scale:
    low while the move accelerates, the full S at its cruise, half for S500), and no stop at
    the S change; with M3 a feed hold that has stopped the machine turns the beam off, the
    release turns it on again."""
    from interp.commands.gcode import compile_text
    from interp.gcode.machine import load_machine

    tb = await ControllerBench(dut).start()
    await tb.write("SPINDLE_PERIOD", 100)
    machine = load_machine(sets=["spindle.laser=true", "spindle.max_s=1000"], clock_hz=int(dut.CLK_HZ.value))
    encode = __import__("interp.testing.controllerkit", fromlist=["encode"]).encode

    async def run(text, during=None):
        _, compiled = compile_text(text, machine, costs="true", start_steps=tuple(await tb.position()))
        for name, value in settings_writes(machine.timing(), compiled.settings, compiled):
            await tb.write(name, value)
        sender = cocotb.start_soon(tb.send(b"".join(encode(c, tb.build) for c in compiled.commands)))
        powers = []
        while not sender.done() or await tb.state() != IDLE or await tb.read("STATUS") & 8:
            if await tb.read("OUTPUTS") & 1:
                powers.append(await pwm_high(tb, 200) / 200)     # the PWM pin's duty over two periods
            if during:
                await during()
        assert await tb.read("ERROR") == 0 and await tb.position() == list(compiled.end_steps)
        return powers

    powers = await run("G21 G90\nM4 S1000\nG1 X3 F600\nG1 X4 S500\nM5\nM2\n")
    assert max(powers) >= 0.98, f"the cruise's power {max(powers)}"
    assert any(0 < p < 0.9 for p in powers[:len(powers) // 4]), f"no lower power while accelerating: {powers}"
    assert any(0.4 <= p <= 0.5 for p in powers[-len(powers) // 5:]), f"S500 not at half power: {powers}"

    held = {"seen": False}

    async def hold_once():
        if not held["seen"] and await tb.position() != [400, 0, 0] and await tb.state() == RUN:
            await tb.write("CONTROL", 1)                   # a feed hold mid-move
            while await tb.state() != HELD:
                await tb.clocks(20)
            assert await pwm_high(tb, 200) == 0, "the beam is on while held"
            held["seen"] = True
            await tb.write("CONTROL", 0)
            await tb.clocks(400)
            assert await pwm_high(tb, 200) > 0, "the beam stays off after the release"

    await run("G21 G90\nM3 S800\nG1 X0 F600\nM5\nM2\n", hold_once)           # from X4
    assert held["seen"]


@cocotb.test()
async def settings_wait_for_idle(dut):
    """QUANTUM_LO / HI, MOTION and the code scales are taken only while not busy, and CONTROL.fill rises only
    then (it would reset motion_top): written mid-move they keep their values, the move's steps come at the same cycles (from its first step on) as
    without the writes and end at its position, STATUS.refused is set until CONTROL.clear,
    and no error latches; at IDLE the same writes are taken."""
    tb = await Bench(dut).start()
    cmds = tb.profiled([Command(LINE, ONE // 2, 30, -20, 5)])
    end, _ = tb.end_of(cmds)
    timings = []
    for meddle in (False, True):
        tb.steps.edges.clear()
        await tb.send(tb.records(cmds))
        await tb.wait_steps(3)
        kept = ("QUANTUM_LO", "QUANTUM_HI", "MOTION", "LIMIT_SCALE", "RATE_SCALE")
        before = [await tb.read(n) for n in kept]
        if meddle:
            await tb.write("QUANTUM_LO", 4 * before[0])
            await tb.write("QUANTUM_HI", 1)
            await tb.write("MOTION", 0x31)
            await tb.write("LIMIT_SCALE", 12345)
            await tb.write("RATE_SCALE", 678)
            await tb.write("CONTROL", await tb.read("CONTROL") | FILL)
            assert [await tb.read(n) for n in kept] == before
            assert not await tb.read("CONTROL") & FILL
            assert await tb.read("STATUS") & REFUSED and await tb.read("ERROR") == 0
        await tb.wait_idle()
        assert await tb.position() == end == tb.steps.position(), f"meddle {meddle}"
        assert await tb.read("ERROR") == 0
        first = tb.steps.edges[0][0]
        timings.append([(t - first, axis, d) for t, axis, d in tb.steps.edges])
        await tb.reset()                                  # (MOTION back at its reset value)
        await tb.configure()
    assert timings[0] == timings[1]
    # sticky until clear; taken at IDLE
    await tb.send(tb.records(cmds))
    await tb.wait_steps(1)
    await tb.write("MOTION", 0x21)
    await tb.wait_idle()
    assert await tb.read("STATUS") & REFUSED
    await tb.write("CONTROL", CLEAR)
    assert not await tb.read("STATUS") & REFUSED
    await tb.write("MOTION", 0x21)
    assert await tb.read("MOTION") == 0x21 and not await tb.read("STATUS") & REFUSED


@cocotb.test()
async def position_set_at_rest(dut):
    """POS_X/Y/Z written at rest set the counters (homing) and the axis's STATUS.position_set
    bit; the next move's steps count on from there; a write while busy is refused
    (STATUS.refused: neither the count nor the bit changes); in ALARM (a limit switch) a write
    is taken; the reset clears the bits and the counters."""
    tb = await Bench(dut).start()
    assert await tb.read("STATUS") >> 16 == 0
    await tb.write("POS_Y", -7 & 0xFFFFFFFF)
    assert await tb.read("STATUS") >> 16 == 0b010 and await tb.position() == [0, -7, 0]
    cmds = tb.profiled([Command(LINE, ONE // 2, 30, -20, 5)])
    end, _ = tb.end_of(cmds, start=(0, -7, 0))
    await tb.send(tb.records(cmds))
    await tb.wait_steps(3)
    await tb.write("POS_X", 1000)
    assert await tb.read("STATUS") & REFUSED and await tb.read("STATUS") >> 16 == 0b010
    await tb.wait_idle()
    assert await tb.position() == end and await tb.read("ERROR") == 0
    await tb.write("CONTROL", CLEAR)
    await tb.write("POS_X", 1000)
    await tb.write("POS_Z", 0x7FFFFFF0)
    assert await tb.position() == [1000, end[1], 0x7FFFFFF0] and await tb.read("STATUS") >> 16 == 0b111
    dut.limit.value = 0b100                         # ALARM: a limit switch
    await tb.clocks(4)
    assert await tb.state() == ALARM
    await tb.write("POS_Z", 5)
    assert (await tb.position())[2] == 5 and not await tb.read("STATUS") & REFUSED
    dut.limit.value = 0
    await tb.reset()
    assert await tb.position() == [0, 0, 0] and await tb.read("STATUS") >> 16 == 0


SMALL_TESTS = ["registers", "records_to_motion_top", "program_ends_at_its_position", "inverted_step_and_dir_pins",
               "estop_and_limit_mid_arc",
               "hold_resume_mid_helix", "abort_and_restart", "fill_then_run", "reset_at_random_cycles",
               "events_drive_outputs", "probe_latch", "probe_stops_the_motion", "bad_records", "settings_wait_for_idle",
               "position_set_at_rest"]


def test_controller(sim):
    """The benches' small build, CURVES 0, a 256-byte queue."""
    icarus_in_make_test(sim)
    run_cocotb(toplevel="controller", test_module="test_controller", sim=sim, parameters=SMALL,
               name="controller", testcase=SMALL_TESTS)


def test_controller_reset_polarity(sim):
    """The small build with INPUT_INVERT_RESET and OUTPUT_INVERT_RESET set."""
    icarus_in_make_test(sim)
    run_cocotb(toplevel="controller", test_module="test_controller", sim=sim,
               parameters={**SMALL, "INPUT_INVERT_RESET": 0x10, "OUTPUT_INVERT_RESET": 0x0049},
               name="controller_polarity", testcase=["polarity_from_the_reset"])


def test_controller_cli_build(sim):
    """The G-code build (W 32, FRAC 32, ..., CURVES 1, a 4 KiB queue)."""
    icarus_in_make_test(sim)
    run_cocotb(toplevel="controller", test_module="test_controller", sim=sim, parameters=CLI,
               name="controller_cli", testcase=["gcode_program", "laser_program", "registers", "bad_records"])
