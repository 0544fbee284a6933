# SPDX-License-Identifier: Apache-2.0
"""motion_top: queue -> cores -> synchronization buffer -> feed -> step/dir.

Every cycle the RTL is compared with the cycle model (interp.models.motion.MotionTop:
the block models wired as the RTL wires them: line_pair (the two lin_exact cores of a
line, lead selection and axis mapping) and arc_plane (circ_arc in a plane, with the
helix axis) are verified here, through motion_top) and a monitor checks
the drive timing (pulse width, dir setup and hold) and records each pulse; at the end
the pulses must equal, in order, the steps of the step-level models of every accepted
command (0 lost, 0 duplicated; arcs in all three planes, helices), the position
counters must equal the programmed end point, the error strobes must name exactly
the bad commands, and the event strobes must come in order, each after every earlier
step is out and its pulse over.  Built at W = 16 and at the G-code build (W = 32,
FRAC = 48, FEED_W = 50, TW = 16).
"""
import csv

import cocotb
from cocotb.triggers import FallingEdge

from interp.models.arc import arc_error, arc_steps
from interp.models.motion import (ARC_CCW, ARC_CW, CURVE, DWELL, E_CORE, E_FEED, E_KIND, E_PLANE, E_QUEUE,
                                  E_RANGE, EVENT, LINE, Command, MotionTop, TimingMonitor, command_steps,
                                  queue_steps)
from interp.cli import main
from interp.commands import gcode
from interp.gcode.machine import load_machine
from interp.simulation import motion_build
from interp.simulation.runner import run_cocotb
from interp.testing.tbkit import TB, read, scoreboard, seeded_rng

ONE = 1 << 16                                  # FRAC = 16: feed ONE would be 1 step per clock
TOP = ONE - 1                                  # the largest feed FEED_W = 16 holds
IDLE = {"rst": 0, "cmd_valid": 0, "hold": 0, "cmd_kind": 0, "cmd_plane": 0, "cmd_feed": 0,
        **{f"cmd_{f}": 0 for f in "xyzijkl"}}
CLI_BUILD = {"W": 32, "FRAC": 48, "FEED_W": 50, "TW": 16, "POS_W": 32, "QDEPTH": 4, "QLW": 3, "SDEPTH": 2}
FAST = {"pulse_width": 1, "setup": 0, "hold_time": 0}
PARAMS = ("W", "FEED_W", "FRAC", "QDEPTH", "QLW", "SDEPTH", "TW", "POS_W")


def bits(step):
    """(sx, sy, sz) -> (step bits, dir bits of the stepping axes)."""
    s = sum(1 << a for a in range(3) if step[a])
    d = sum(1 << a for a in range(3) if step[a] < 0)
    return s, d


class MotionTB(TB):
    async def start(self):
        await self.reset({**IDLE, **FAST})
        p = {k: int(getattr(self.dut, k).value) for k in PARAMS}
        self.width, self.qdepth = p["W"], p["QDEPTH"]
        self.one = 1 << p["FRAC"]                  # feed of one step per clock
        self.top = min(self.one, 1 << p["FEED_W"]) - 1
        self.scale = self.one // ONE               # the W = 16 build's feeds -> this build's
        self.ref = MotionTop(**{k.lower(): v for k, v in p.items()})
        self.origin = [0, 0, 0]
        return self

    async def run(self, cmds, timing=FAST, hold=lambda c: 0, respect_full=True, max_cycles=200_000,
                  context=""):
        """Push `cmds`, clock until all is done, RTL and cycle model compared every cycle;
        then check pulses, position and errors against the step-level models."""
        cmds = [self.fit(c) for c in cmds]
        mon = TimingMonitor(3, timing["pulse_width"], timing["setup"], timing["hold_time"])
        pushed, errors, events = [], [], []

        def observe(sample):
            step = sum(sample[f"step_{a}"] << k for k, a in enumerate("xyz"))
            mon.sample(step, sum(sample[f"dir_{a}"] << k for k, a in enumerate("xyz")))
            if sample["error"]:
                errors.append(sample["error_code"])
            if sample["event_valid"]:
                assert step == 0, f"{context}: event while a pulse is high"
                events.append((len(mon.pulses), sample["event_code"], sample["event_value"]))

        def stim():
            pending, full, cycle = list(cmds), 0, 0
            while True:
                push = bool(pending) and (not respect_full or not full)
                inputs = {**IDLE, **timing, "hold": int(bool(hold(cycle)))}
                if push:
                    cmd = pending.pop(0)
                    if not full:
                        pushed.append(cmd)
                    inputs.update(cmd.ports(), cmd_valid=1)
                sample = yield inputs
                cycle += 1
                observe(sample)
                full = sample["cmd_full"]
                if not pending and not push and not sample["busy"] and cycle > 4:
                    break
                assert cycle < max_cycles, f"{context}: not done after {max_cycles} cycles"
            for _ in range(4):                   # nothing moves afterwards
                observe((yield {**IDLE, **timing}))

        await scoreboard(self, self.ref, stim(), context=context)
        want, want_errors = queue_steps(pushed, self.width)
        got = [(s, d) for _, s, d in mon.pulses]
        assert len(got) == len(want), f"{context}: {len(got)} pulses, want {len(want)}"
        assert got == [bits(s) for s in want], f"{context}: pulse sequence differs"
        end = [o + sum(s[a] for s in want) for a, o in enumerate(self.origin)]
        pos = [read(self.dut, f"pos_{a}", signed=True) for a in "xyz"]
        assert pos == end, f"{context}: position {pos}, programmed end {end}"
        assert [m + o for m, o in zip(mon.position, self.origin)] == end
        self.origin = end
        assert 6 not in errors, f"{context}: step buffer overflow"
        # each event after exactly the steps of the commands before it, in order
        want_events, before = [], 0
        for cmd in pushed:
            if cmd.kind == EVENT:
                want_events.append((before, cmd.x & 0xFF, cmd.y))
            before += len(command_steps(cmd, self.width)[0])
        assert events == want_events, f"{context}: events {events}, want {want_events}"
        return errors, want_errors, mon, mon.cycle

    def fit(self, cmd):
        """A W = 16 bench command at this build: feeds scaled to the same speed."""
        if cmd.kind in (DWELL, EVENT) or self.scale == 1:
            return cmd
        return Command(**{**cmd.__dict__, "feed": min(cmd.feed * self.scale, self.top)})


def random_arc(rng, r=12):
    """An arc from the start about a random centre, ending a quarter, half or full turn on."""
    i, j = rng.randint(-r, r), rng.randint(-r, r)
    u, v = -i, -j
    for _ in range(rng.randint(0, 3)):
        u, v = -v, u
    return Command(rng.choice([ARC_CW, ARC_CCW]), rng.randint(ONE // 8, TOP), i + u, j + v, 0, i, j)


def arc_count(cmd):
    """N for a helix: the number of steps of the arc alone (the host's rule); 0 for a bad arc."""
    if arc_error(cmd.i, cmd.j, 0, 0, cmd.x, cmd.y):
        return 0
    return len(arc_steps(cmd.i, cmd.j, 0, 0, cmd.x, cmd.y, cmd.kind == ARC_CCW, (cmd.x, cmd.y) == (0, 0)))


def random_helix(rng, r=10):
    """An arc in a random plane, with a helix of a random travel and a right, wrong or zero N."""
    arc = random_arc(rng, r)
    arc.plane = rng.randint(0, 2)
    arc.z = rng.choice([0, rng.randint(-15, 15), rng.randint(-60, 60)])
    n = arc_count(arc)
    arc.k = rng.choice([n, n, n // 2, 2 * n + 3, 0, -rng.randint(1, 9), abs(arc.z) // 3, n + 1])
    return arc


def random_line(rng, n=20, three=True):
    return Command(LINE, rng.randint(ONE // 8, TOP), rng.randint(-n, n), rng.randint(-n, n),
                   rng.randint(-n, n) if three else 0)


@cocotb.test()
async def lines_2d_3d(dut):
    """Axial, diagonal, 2- and 3-axis lines in every octant, zero-length lines."""
    tb = await MotionTB(dut).start()
    moves = [(10, 0, 0), (0, -7, 0), (0, 0, 5), (6, 6, 0), (-5, 5, 5), (9, -4, 0), (3, 8, -5),
             (-4, -9, 12), (0, 0, 0), (1, 1, 1), (-13, 2, -6)]
    cmds = [Command(LINE, ONE // 2, *m) for m in moves]
    errors, want_errors, _, _ = await tb.run(cmds, context="lines")
    assert errors == want_errors == []


@cocotb.test()
async def arcs_and_curves(dut):
    """Quarter, half and full circles both ways; a parabola and an exponent by the tangent."""
    tb = await MotionTB(dut).start()
    cmds = [Command(ARC_CCW, ONE // 2, 10, 10, 0, 10, 0),       # quarter, centre (10, 0)
            Command(ARC_CW, ONE // 2, 0, 0, 0, -7, 3),          # full circle, CW
            Command(ARC_CCW, ONE // 3, -16, 0, 0, -8, 0),       # half circle
            Command(CURVE, ONE // 2, 8, 0, 25, 0, 0, 1, 0),      # ΔX = 8, ΔY = x: a parabola, 25 steps
            Command(CURVE, ONE // 2, 10, 20, 30, 0, 0, 0, 1),    # ΔX = 10, ΔY = 20 + y: an exponent
            Command(LINE, ONE // 2, 3, -4, 2)]
    errors, want_errors, _, _ = await tb.run(cmds, context="arcs and curves")
    assert errors == want_errors == []


@cocotb.test()
async def bad_arc_and_curve(dut):
    """An arc whose centre does not fit the end point, a curve with no tangent: E_CORE, no step."""
    tb = await MotionTB(dut).start()
    cmds = [Command(LINE, TOP, 2, 1), Command(ARC_CW, TOP, 5, 0, 0, 9, 9),
            Command(CURVE, TOP, 0, 0, 10), Command(ARC_CCW, TOP, 0, 0, 0, 0, 0),
            Command(LINE, TOP, -1, 1, 1)]
    errors, want_errors, _, _ = await tb.run(cmds, context="bad arc")
    assert errors == want_errors == [E_CORE, E_CORE, E_CORE]


@cocotb.test()
async def back_pressure_fuzz(dut):
    """Random STOP (feed hold) patterns and random queue contents: 0 lost, 0 duplicated."""
    rng = seeded_rng(dut, "back_pressure_fuzz")
    tb = await MotionTB(dut).start()
    holds = [lambda c: 0, lambda c: rng.random() < 0.5, lambda c: rng.random() < 0.9,
             lambda c: (c // 17) % 3 == 0, lambda c: c % 5 != 0]
    for n in range(10):
        cmds = []
        for _ in range(rng.randint(1, 8)):
            r = rng.random()
            if r < 0.55:
                cmds.append(random_line(rng, three=rng.random() < 0.5))
            elif r < 0.7:
                cmds.append(random_arc(rng))
            elif r < 0.8:
                cmds.append(Command(DWELL, 0, rng.randint(0, 20)))
            elif r < 0.9:
                cmds.append(Command(rng.randint(5, 7), TOP))
            else:
                cmds.append(Command(LINE, 0, 3, 3))
        timing = rng.choice([FAST, {"pulse_width": 2, "setup": 1, "hold_time": 1},
                             {"pulse_width": 3, "setup": 4, "hold_time": 2}])
        errors, want_errors, _, _ = await tb.run(cmds, timing, hold=holds[n % len(holds)], context=f"fuzz {n}")
        assert errors == want_errors, f"fuzz {n}: errors {errors}, want {want_errors}"


@cocotb.test()
async def planes_and_helices(dut):
    """Arcs in XY, ZX, YZ, plain and helical, N right, too small, too large, 0 and negative."""
    tb = await MotionTB(dut).start()
    quarter = Command(ARC_CCW, ONE // 3, 8, 8, 0, 8, 0)            # centre (8, 0) -> (8, 8)
    n = arc_count(quarter)
    cmds = []
    for plane in (0, 1, 2):
        for z, k in [(0, 0), (5, n), (-5, n), (n, n), (-n - 7, n), (3, 1), (9, 0), (4, -3), (6, 4 * n)]:
            cmds.append(Command(**{**quarter.__dict__, "plane": plane, "z": z, "k": k}))
    full = Command(ARC_CW, ONE // 2, 0, 0, 0, -6, 2, plane=1)     # a full turn with a helix
    cmds += [Command(**{**full.__dict__, "z": -11, "k": arc_count(full)}), Command(LINE, ONE // 2, 1, -2, 3)]
    errors, want_errors, _, _ = await tb.run(cmds, context="planes and helices")
    assert errors == want_errors == []


@cocotb.test()
async def events_after_the_drive_stops(dut):
    """EVENT: event_valid once, after every earlier step is out and its pulse over; code, value."""
    tb = await MotionTB(dut).start()
    slow = {"pulse_width": 5, "setup": 2, "hold_time": 3}
    cmds = [Command(EVENT, 0, 3, -17), Command(LINE, ONE // 2, 6, -2, 1), Command(EVENT, 0, 0x1A5, 1000),
            Command(EVENT, TOP, 255, -1), Command(ARC_CW, ONE // 4, 0, 0, 9, 0, 4, 40, plane=2),
            Command(DWELL, 0, 7), Command(EVENT, 0, 7, 0), Command(LINE, ONE // 5, -1, 0, 0)]
    _, _, mon, _ = await tb.run(cmds, timing=slow, context="events")
    assert mon.pulses[0][0] > 4


@cocotb.test()
async def random_mix(dut):
    """Seeded random queues of lines, arcs in all planes, helices, dwells, events, bad commands."""
    rng = seeded_rng(dut, "random_mix")
    tb = await MotionTB(dut).start()
    for n in range(8):
        cmds = []
        for _ in range(rng.randint(1, 7)):
            r = rng.random()
            if r < 0.3:
                cmds.append(random_line(rng, three=rng.random() < 0.7))
            elif r < 0.65:
                cmds.append(random_helix(rng))
            elif r < 0.75:
                cmds.append(Command(EVENT, rng.choice([0, TOP]), rng.randint(0, 1023), rng.randint(-999, 999)))
            elif r < 0.82:
                cmds.append(Command(DWELL, 0, rng.randint(0, 12)))
            elif r < 0.9:
                cmds.append(Command(rng.choice([ARC_CW, ARC_CCW]), TOP, 4, 4, 3, 4, 0, plane=3))
            else:
                cmds.append(Command(rng.randint(6, 7), TOP, 1, 2, 3))
        timing = rng.choice([FAST, {"pulse_width": 2, "setup": 1, "hold_time": 1}])
        hold = rng.choice([lambda c: 0, lambda c: rng.random() < 0.4])
        errors, want_errors, _, _ = await tb.run(cmds, timing, hold=hold, context=f"mix {n}")
        assert errors == want_errors, f"mix {n}: errors {errors}, want {want_errors}"


@cocotb.test()
async def bad_commands_keep_the_queue(dut):
    """Unknown kind, feed 0, a coordinate of -2^(W-1): error code each, the rest still runs."""
    tb = await MotionTB(dut).start()
    lo = -(1 << (tb.width - 1))
    cmds = [Command(LINE, TOP, 4, 1), Command(6, TOP, 5), Command(LINE, 0, 9, 9),
            Command(LINE, TOP, lo, 0), Command(ARC_CW, TOP, 0, 0, 0, 3, 0, plane=3), Command(7, 0),
            Command(ARC_CCW, 0, 0, 0, 0, 3, 0, plane=3), Command(LINE, ONE // 3, -2, 7, 1)]
    errors, want_errors, _, _ = await tb.run(cmds, context="bad commands")
    assert errors == want_errors == [E_KIND, E_FEED, E_RANGE, E_PLANE, E_KIND, E_FEED]


@cocotb.test()
async def queue_overflow(dut):
    """Commands pushed into a full queue are refused with E_QUEUE; the accepted ones all run."""
    tb = await MotionTB(dut).start()
    cmds = [Command(LINE, ONE // 4, k + 3, 1) for k in range(tb.qdepth + 5)]
    errors, want_errors, _, _ = await tb.run(cmds, hold=lambda c: c < 40, respect_full=False,
                                             context="overflow")
    assert errors.count(E_QUEUE) >= 3 and want_errors == []


@cocotb.test()
async def reset_with_full_queue(dut):
    """rst with a full queue, a full step buffer and a pulse under way: idle, no further step."""
    tb = await MotionTB(dut).start()
    dut.hold.value = 0
    for k in range(tb.qdepth + 1):
        tb.drive({**IDLE, **Command(LINE, TOP, 7, -3, 2).ports(), "cmd_valid": 1, "hold": int(k < tb.qdepth)})
        await FallingEdge(dut.clk)
    tb.drive({"cmd_valid": 0, "hold": 0})
    for _ in range(3):
        await FallingEdge(dut.clk)
    assert int(dut.busy.value) and int(dut.queue_level.value) >= tb.qdepth - 1
    await tb.reset({**IDLE, **FAST})
    tb.ref.reset()
    for _ in range(30):
        await FallingEdge(dut.clk)
        assert not (int(dut.busy.value) or int(dut.step_x.value) or int(dut.step_y.value)
                    or int(dut.step_z.value) or int(dut.queue_level.value))
        assert [read(dut, f"pos_{a}", signed=True) for a in "xyz"] == [0, 0, 0]
    tb.origin = [0, 0, 0]
    errors, _, _, _ = await tb.run([Command(LINE, TOP, -3, 5, 1)], context="after reset")
    assert errors == []


@cocotb.test()
async def dwell_waits_after_the_drive_stops(dut):
    """A dwell of N cycles: the next move's first pulse comes > N cycles after the last one."""
    tb = await MotionTB(dut).start()
    cmds = [Command(LINE, TOP, 6, 2), Command(DWELL, 0, 50), Command(LINE, TOP, -1, 0)]
    _, _, mon, _ = await tb.run(cmds, context="dwell")
    rises = [c for c, _, _ in mon.pulses]
    assert rises[6] - rises[5] > 50, rises


@cocotb.test()
async def path_speed(dut):
    """Measured path speed equals the feed within 1 % for axial, diagonal and 3-axis lines."""
    tb = await MotionTB(dut).start()
    for move in [(60, 0, 0), (40, 40, 0), (30, 30, 30), (50, 20, 0)]:
        feed = ONE // 6
        _, _, mon, _ = await tb.run([Command(LINE, feed, *move)], context=f"speed {move}")
        rises = [c for c, _, _ in mon.pulses]
        want, _ = queue_steps([Command(LINE, feed, *move)])
        length = sum(sum(abs(c) for c in s) ** 0.5 for s in want[:-1])
        speed = length / (rises[-1] - rises[0])
        assert abs(speed / (feed / ONE) - 1) < 0.01, f"{move}: {speed} vs {feed / ONE}"


def test_motion_top_cli_build(sim):
    """The G-code build: 32-bit fields, FRAC = 48, FEED_W = 50, TW = 16."""
    run_cocotb(toplevel="motion_top", test_module="test_motion_top", sim=sim, parameters=CLI_BUILD,
               name="motion_top_cli", testcase=["planes_and_helices", "events_after_the_drive_stops",
                                                "random_mix", "bad_commands_keep_the_queue", "path_speed"])


def test_motion_top(sim, tmp_path):
    run_cocotb(toplevel="motion_top", test_module="test_motion_top", sim=sim,
               parameters=motion_build.PARAMETERS, name="motion_top")
    # `interp gcode` on the same build: the built-in program, steps equal to the models'
    src = tmp_path / "demo.nc"
    src.write_text(gcode.DEMO)
    argv = ["gcode", str(src), *gcode.DEMO_OPTIONS, "--sim", sim, "--steps", str(tmp_path / "steps.csv")]
    assert main(argv) == 0
    with open(tmp_path / "steps.csv") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["cycle", "dx", "dy", "dz"]
    compiled = gcode.compile_text(gcode.DEMO, load_machine(clock_hz=50_000))[1]
    want, _ = queue_steps(compiled.commands, 32)
    assert [tuple(int(v) for v in r[1:]) for r in rows[1:]] == want
