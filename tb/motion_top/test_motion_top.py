# SPDX-License-Identifier: Apache-2.0
"""motion_top: queues -> cores -> synchronization buffer -> path profile -> step/dir.

Every cycle the RTL is compared with the cycle model (interp.models.motion.MotionTop:
the block models wired as the RTL wires them: motion_cores (the cores and the choice of
the running one's steps) with line_pair (the two lin_exact cores of a line, lead
selection and axis mapping) and arc_plane (circ_arc in a plane, with the helix axis),
and path_profile (the profile queue, speed_ramp, jerk_filter, step_pacer)
are verified here, through motion_top) and a monitor checks
the drive timing (pulse width, dir setup and hold) and records each pulse; at the end
the pulses must equal, in order, the steps of the step-level models of every accepted
command (0 lost, 0 duplicated; arcs in all three planes, helices; also under random
feed hold / resume and override patterns and with commands arriving late), the
position counters must equal the programmed end point, the error strobes must name
exactly the bad commands (checked at the push), and the event strobes must come in
order, each after every earlier step is out, its pulse over and the speed 0 (an inline
event, which does not stop, within SDEPTH + 1 steps of its place).  The
virtual speed never changes by more than a quantum per block, and no step starts after
`stopped` (a hold at rest, the S-curve filter empty too).  Bench commands get
their profiles from interp.models.profile.profile_for.  Built at the benches' build
(interp.simulation.motion_build) and at the G-code build (W = 32, FRAC = 32, ...).
"""
from dataclasses import replace

import cocotb
from cocotb.triggers import FallingEdge

from interp.models.arc import arc_error, arc_steps
from interp.models.motion import (ARC_CCW, ARC_CW, CURVE, DWELL, E_CORE, E_FEED, E_KIND, E_OVERRUN, E_PLANE,
                                  E_PROFILE, E_QUEUE, E_RANGE, EVENT, LINE, Command, MotionTop, TimingMonitor,
                                  command_steps, inline, queue_steps)
from interp.models.profile import profile_for
from interp.models.speed_ramp import BLOCK_SHIFT_MIN
from interp.simulation import motion_build
from interp.simulation.native.build import CLI_PARAMETERS
from interp.simulation.runner import run_cocotb
from interp.testing.tbkit import TB, read, scoreboard, seeded_rng

# make test runs this bench on Verilator alone, its faster simulator (make test-all: both)
QUICK_SIMULATOR = "verilator"

ONE = 1 << 16                                  # FRAC = 16: feed ONE would be 1 step per clock
TOP = ONE - 1                                  # the largest feed FEED_W = 16 holds
QUANTUM = 64                                   # A at FRAC = 16: a quantum of speed, path units per clock
ACCEL = 32.0                                   # path units per clock^2 at FRAC = 16
PROFILE_PORTS = ("cmd_limit", "cmd_exit", "cmd_rate", "cmd_cost", "cmd_length", "cmd_budget")
IDLE = {"rst": 0, "cmd_valid": 0, "hold": 0, "cmd_kind": 0, "cmd_plane": 0, "cmd_feed": 0,
        **{f"cmd_{f}": 0 for f in "xyzijkl"}, **{p: 0 for p in PROFILE_PORTS}}
CLI_BUILD = CLI_PARAMETERS
FAST = {"pulse_width": 1, "setup": 0, "hold_time": 0}
PARAMS = ("W", "FEED_W", "FRAC", "NW", "PF", "LEN_W", "ZW", "MW", "QDEPTH", "QLW", "SDEPTH", "TW", "POS_W")


def bits(step):
    """(sx, sy, sz) -> (step bits, dir bits of the stepping axes)."""
    s = sum(1 << a for a in range(3) if step[a])
    d = sum(1 << a for a in range(3) if step[a] < 0)
    return s, d


class MotionTB(TB):
    async def start(self):
        p = {k: int(getattr(self.dut, k).value) for k in PARAMS}
        self.p = p
        self.width, self.qdepth, self.pf = p["W"], p["QDEPTH"], p["PF"]
        self.one = 1 << p["FRAC"]                  # feed of one step per clock
        self.top = min(self.one, 1 << p["FEED_W"]) - 1
        self.scale = self.one // ONE               # the W = 16 build's feeds -> this build's
        self.settings = {"speed_quantum": QUANTUM * self.scale, "block_shift": BLOCK_SHIFT_MIN, "jerk_shift": 0,
                         "override": 100}
        await self.reset({**IDLE, **FAST, **self.settings})
        self.ref = MotionTop(**{k.lower(): v for k, v in p.items()})
        self.ref.settled({**IDLE, **FAST, **self.settings})
        self.origin = [0, 0, 0]
        return self

    def profiled(self, cmds, accel=ACCEL, lecture=True, limit_factor=1.0):
        """`cmds` (the W = 16 bench's feeds) at this build, with bench profiles."""
        return profile_for([self.fit(c) for c in cmds], quantum=self.settings["speed_quantum"],
                           accel=accel * self.scale, frac=self.p["FRAC"], pf=self.pf,
                           block_shift=self.settings["block_shift"], width=self.width, lecture=lecture,
                           limit_factor=limit_factor, feed_max=self.top, feed_w=self.p["FEED_W"])

    async def run(self, cmds, timing=FAST, hold=lambda c: 0, respect_full=True, max_cycles=400_000,
                  context="", profiled=False, override=lambda c: 100, gap=lambda c: 0, fault=False):
        """Push `cmds` (given profiles unless `profiled`), clock until all is done, RTL and cycle
        model compared every cycle; then check pulses, position and errors against the
        step-level models.  hold(cycle), override(cycle): the machine inputs; gap(k): cycles
        to wait before pushing command k (late commands: underrun)."""
        cmds = list(cmds) if profiled else self.profiled(cmds)
        mon = TimingMonitor(3, timing["pulse_width"], timing["setup"], timing["hold_time"])
        pushed, errors, events = [], [], []
        quantum = self.settings["speed_quantum"]
        last = {"speed": 0, "step": 0, "stopped": 0}

        def observe(sample):
            step = sum(sample[f"step_{a}"] << k for k, a in enumerate("xyz"))
            mon.sample(step, sum(sample[f"dir_{a}"] << k for k, a in enumerate("xyz")))
            if sample["error"]:
                errors.append(sample["error_code"])
            if sample["event_valid"]:
                events.append((len(mon.pulses), sample["event_code"], sample["event_value"], sample["speed"], step))
            rising = step & ~last["step"]
            assert not (last["stopped"] and rising), f"{context}: cycle {mon.cycle}: a step after `stopped`"
            last["step"], last["stopped"] = step, sample["stopped"]
            jump = abs(sample["speed"] - last["speed"])
            assert (fault and {E_CORE, E_OVERRUN} & set(errors)) or jump <= 2 * quantum, f"{context}: cycle {mon.cycle}: speed jumps by {jump}"
            last["speed"] = sample["speed"]

        def stim():
            pending, full, cycle, wait = list(cmds), 0, 0, gap(0)
            while True:
                push = bool(pending) and (not respect_full or not full) and wait <= 0
                inputs = {**IDLE, **timing, **self.settings, "hold": int(bool(hold(cycle))),
                          "override": override(cycle)}
                if push:
                    cmd = pending.pop(0)
                    if not full:
                        pushed.append(cmd)
                    inputs.update(cmd.ports(), cmd_valid=1)
                    wait = gap(len(cmds) - len(pending))
                else:
                    wait -= 1
                sample = yield inputs
                cycle += 1
                observe(sample)
                full = sample["cmd_full"]
                if not pending and not push and not sample["busy"] and cycle > 4:
                    break
                assert cycle < max_cycles, f"{context}: not done after {max_cycles} cycles"
            for _ in range(4):                   # nothing moves afterwards
                observe((yield {**IDLE, **timing, **self.settings}))

        await scoreboard(self, self.ref, stim(), context=context)
        want, want_errors = queue_steps(pushed, self.width, self.pf)
        got = [(s, d) for _, s, d in mon.pulses]
        pos = [read(self.dut, f"pos_{a}", signed=True) for a in "xyz"]
        if fault:                                 # a fault flushes what waits: a prefix went out
            assert got == [bits(s) for s in want][:len(got)], f"{context}: pulse sequence differs"
            end = [o + m for o, m in zip(self.origin, mon.position)]
            assert pos == end, f"{context}: position {pos}, pulses counted {end}"
            self.origin = end
            return errors, want_errors, mon, mon.cycle
        assert len(got) == len(want), f"{context}: {len(got)} pulses, want {len(want)}"
        assert got == [bits(s) for s in want], f"{context}: pulse sequence differs"
        end = [o + sum(s[a] for s in want) for a, o in enumerate(self.origin)]
        assert pos == end, f"{context}: position {pos}, programmed end {end}"
        assert [m + o for m, o in zip(mon.position, self.origin)] == end
        self.origin = end
        assert 6 not in errors, f"{context}: step buffer overflow"
        # each event after exactly the steps of the commands before it, in order, at speed 0
        # with no pulse high; an inline one when the core has made them: at most SDEPTH steps
        # of them still to come out (the synchronization buffer) and one in the output stage
        want_events, before = [], 0
        for cmd in pushed:
            if cmd.kind == EVENT:
                want_events.append((before, cmd.x & 0xFF, cmd.y, inline(cmd)))
            before += len(command_steps(cmd, self.width, self.pf)[0])
        assert [e[1:3] for e in events] == [w[1:3] for w in want_events], \
            f"{context}: events {events}, want {want_events}"
        for (pulses, _, _, speed, step), (before, _, _, at_once) in zip(events, want_events):
            if at_once:
                assert before - self.p["SDEPTH"] - 1 <= pulses <= before, f"{context}: inline event after {pulses} of {before} steps"
            else:
                assert (pulses, speed, step) == (before, 0, 0), f"{context}: event after {pulses} steps, speed {speed}, pulse {step}"
        return errors, want_errors, mon, mon.cycle

    def fit(self, cmd):
        """A W = 16 bench command at this build: feeds scaled to the same speed."""
        if cmd.kind in (DWELL, EVENT) or self.scale == 1:
            return cmd
        return Command(**{**cmd.__dict__, "feed": min(cmd.feed * self.scale, self.top)})


def random_arc(rng, r=12):
    """An arc from the start about a random centre (not the start), ending a quarter, half or
    full turn on."""
    i, j = rng.randint(-r, r), rng.randint(-r, r)
    if i == j == 0:
        i = r
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
    d = [rng.randint(-n, n), rng.randint(-n, n), rng.randint(-n, n) if three else 0]
    if d == [0, 0, 0]:
        d[0] = 1
    return Command(LINE, rng.randint(ONE // 8, TOP), *d)


def random_moves(rng, count, dwell=True):
    cmds = []
    for _ in range(count):
        r = rng.random()
        if r < 0.5:
            cmds.append(random_line(rng, three=rng.random() < 0.5))
        elif r < 0.85:
            cmds.append(random_helix(rng))
        elif r < 0.93 and dwell:
            cmds.append(Command(DWELL, 0, rng.randint(0, 20)))
        else:
            cmds.append(Command(EVENT, 0, rng.randint(0, 255), rng.randint(-99, 99)))
    return cmds


def hold_pattern(rng):
    """A random feed hold pattern: none, short random pulses, long holds, periodic."""
    kind = rng.randrange(4)
    if kind == 0:
        return lambda c: 0
    if kind == 1:
        starts = sorted(rng.sample(range(20, 3000), 6))
        return lambda c: any(s <= c < s + 40 for s in starts)
    if kind == 2:
        return lambda c: (c // rng.choice([150, 400, 900])) % 2 == 1
    period = rng.randint(60, 500)
    return lambda c: (c % period) < period // 3


@cocotb.test()
async def lines_2d_3d(dut):
    """Axial, diagonal, 2- and 3-axis lines in every octant; a zero-length line is refused (profile)."""
    tb = await MotionTB(dut).start()
    moves = [(10, 0, 0), (0, -7, 0), (0, 0, 5), (6, 6, 0), (-5, 5, 5), (9, -4, 0), (3, 8, -5),
             (-4, -9, 12), (0, 0, 0), (1, 1, 1), (-13, 2, -6)]
    cmds = [Command(LINE, ONE // 2, *m) for m in moves]
    errors, want_errors, _, _ = await tb.run(cmds, context="lines")
    assert errors == want_errors == [E_PROFILE]


@cocotb.test()
async def arcs_and_curves(dut):
    """Quarter, half and full circles both ways; a parabola and an exponent by the tangent;
    true-length costs (cmd_cost) instead of the lecture's."""
    tb = await MotionTB(dut).start()
    cmds = [Command(ARC_CCW, ONE // 2, 10, 10, 0, 10, 0),       # quarter, centre (10, 0)
            Command(ARC_CW, ONE // 2, 0, 0, 0, -7, 3),          # full circle, CW
            Command(ARC_CCW, ONE // 3, -16, 0, 0, -8, 0),       # half circle
            Command(CURVE, ONE // 2, 8, 0, 25, 0, 0, 1, 0),      # ΔX = 8, ΔY = x: a parabola, 25 steps
            Command(CURVE, ONE // 2, 10, 20, 30, 0, 0, 0, 1),    # ΔX = 10, ΔY = 20 + y: an exponent
            Command(LINE, ONE // 2, 3, -4, 2)]
    for lecture in (True, False):
        errors, want_errors, _, _ = await tb.run(tb.profiled(cmds, lecture=lecture), profiled=True,
                                                 context=f"arcs and curves, lecture {lecture}")
        assert errors == want_errors == []


@cocotb.test()
async def core_error_is_a_fault(dut):
    """An arc whose centre does not fit its end: E_CORE, both queues flushed, every later push
    refused with E_CORE until rst; what went out is counted exactly; after rst all runs again."""
    tb = await MotionTB(dut).start()
    cmds = tb.profiled([Command(LINE, TOP, 9, 1), Command(ARC_CW, TOP, 5, 0, 0, 9, 9)]
                       + [Command(LINE, TOP, -1, 1, 1), Command(LINE, TOP, 2, 2)] * 4)
    cmds[1].length, cmds[1].budget = cmds[0].length, cmds[0].budget      # a profile the push accepts
    errors, _, mon, _ = await tb.run(cmds, context="fault", fault=True, profiled=True)
    assert errors[0] == E_CORE and set(errors) == {E_CORE} and len(errors) >= 2, errors
    assert len(mon.pulses) <= 9
    await tb.reset({**IDLE, **FAST, **tb.settings})
    tb.ref.reset()
    tb.ref.settled({**IDLE, **FAST, **tb.settings})
    tb.origin = [0, 0, 0]
    cmds = tb.profiled([Command(LINE, TOP, 2, 1), Command(CURVE, TOP, 0, 0, 10), Command(LINE, TOP, -3, 5, 1)])
    cmds[1].length, cmds[1].budget = cmds[0].length, cmds[0].budget
    errors, _, _, _ = await tb.run(cmds, context="curve fault", fault=True, profiled=True)
    assert errors[0] == E_CORE
    await tb.reset({**IDLE, **FAST, **tb.settings})
    tb.ref.reset()
    tb.ref.settled({**IDLE, **FAST, **tb.settings})
    tb.origin = [0, 0, 0]
    errors, _, _, _ = await tb.run([Command(LINE, TOP, -3, 5, 1)], context="after the fault")
    assert errors == []


@cocotb.test()
async def overrun_is_a_fault(dut):
    """Steps asked far faster than the output stage makes them (the feed at one step a clock,
    pulses of 15 clocks) with the S-curve's deepest window, until the pacer's phase saturates:
    E_OVERRUN once, both queues flushed, no step after it, every later push refused (E_CORE)
    until rst; the position counts what went out.  A line that stays below the output stage's
    rate with the same window runs exactly."""
    tb = await MotionTB(dut).start()
    tb.settings.update(jerk_shift=tb.p["MW"])
    slow = {**FAST, "pulse_width": 15}
    cmds = tb.profiled([Command(LINE, TOP, 3000, 1), Command(LINE, TOP, 5, 5)])
    errors, _, mon, _ = await tb.run(cmds, timing=slow, context="overrun", fault=True, profiled=True)
    assert errors[0] == E_OVERRUN and errors.count(E_OVERRUN) == 1 and set(errors) <= {E_OVERRUN, E_CORE}, errors
    assert 0 < len(mon.pulses) < 3000
    await tb.reset({**IDLE, **FAST, **tb.settings})
    tb.ref.reset()
    tb.ref.settled({**IDLE, **FAST, **tb.settings})
    tb.origin = [0, 0, 0]
    errors, want_errors, mon, _ = await tb.run([Command(LINE, ONE // 20, 300, 1)], timing=slow, context="below the rate")
    assert errors == want_errors == [] and len(mon.pulses) == 300
    tb.settings.update(jerk_shift=0)


@cocotb.test()
async def hold_resume_override_fuzz(dut):
    """Random feed hold / resume and override patterns over lines, arcs, helices, dwells and
    events: 0 lost, 0 duplicated steps, exact end positions."""
    rng = seeded_rng(dut, "hold_resume_override_fuzz")
    tb = await MotionTB(dut).start()
    for n in range(6):
        cmds = random_moves(rng, rng.randint(1, 6))
        timing = rng.choice([FAST, {"pulse_width": 2, "setup": 1, "hold_time": 1},
                             {"pulse_width": 3, "setup": 4, "hold_time": 2}])
        level = rng.choice([100, 100, 30, 150, 200, 0, 255])
        period = rng.randint(100, 2000)
        override = rng.choice([lambda c: level, lambda c: [level, 100, 170, 60][(c // period) % 4]])
        profiled = tb.profiled(cmds, limit_factor=rng.choice([1.0, 1.5, 2.0]))
        errors, want_errors, _, _ = await tb.run(profiled, timing, hold=hold_pattern(rng), override=override,
                                                 profiled=True, context=f"fuzz {n}")
        assert errors == want_errors == [], f"fuzz {n}: errors {errors}"


@cocotb.test()
async def s_curve_and_blocks(dut):
    """block_shift 2 .. 4 (acceleration changes once per block) and jerk_shift > 0 (the S-curve
    filter): every cycle as the model, 0 lost steps, also under feed hold."""
    rng = seeded_rng(dut, "s_curve_and_blocks")
    tb = await MotionTB(dut).start()
    for n, (block_shift, jerk_shift) in enumerate([(2, 2), (3, 0), (3, 3), (4, 4), (2, 6)]):
        tb.settings.update(block_shift=block_shift, jerk_shift=jerk_shift)
        cmds = random_moves(rng, rng.randint(2, 5))
        errors, want_errors, _, _ = await tb.run(cmds, hold=hold_pattern(rng),
                                                 context=f"S-curve {n} (block {block_shift}, jerk {jerk_shift})")
        assert errors == want_errors == []
    tb.settings.update(block_shift=BLOCK_SHIFT_MIN, jerk_shift=0)


@cocotb.test()
async def underrun_stops_and_restarts(dut):
    """Commands arriving late (gaps of 0 .. 3000 cycles between pushes): each underrun ends in a
    controlled stop, the speed never jumps (checked every cycle), every step comes out once."""
    rng = seeded_rng(dut, "underrun_stops_and_restarts")
    tb = await MotionTB(dut).start()
    for n in range(3):
        cmds = [random_line(rng, 30, three=False) for _ in range(rng.randint(3, 6))]
        gaps = [rng.choice([0, 0, 50, 400, 3000]) for _ in range(len(cmds) + 1)]
        errors, _, _, _ = await tb.run(cmds, gap=lambda k: gaps[k], context=f"underrun {n}")
        assert errors == []


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
    """EVENT: event_valid once, after every earlier step is out, its pulse over and the speed 0."""
    tb = await MotionTB(dut).start()
    slow = {"pulse_width": 5, "setup": 2, "hold_time": 3}
    cmds = [Command(EVENT, 0, 3, -17), Command(LINE, ONE // 2, 6, -2, 1), Command(EVENT, 0, 0x1A5, 1000),
            Command(EVENT, TOP, 255, -1), Command(ARC_CW, ONE // 4, 0, 0, 9, 0, 4, 40, plane=2),
            Command(DWELL, 0, 7), Command(EVENT, 0, 7, 0), Command(LINE, ONE // 5, -1, 0, 0)]
    _, _, mon, _ = await tb.run(cmds, timing=slow, context="events")
    assert mon.pulses[0][0] > 4


@cocotb.test()
async def inline_events_do_not_stop(dut):
    """An inline EVENT (plane bit 0, a laser's power) between two collinear lines: the path
    keeps its speed through it (the barrier form stops), the strobe comes when the first
    line's core is done, within SDEPTH + 1 steps of the join; with a hold it still comes."""
    tb = await MotionTB(dut).start()
    lines = [Command(LINE, ONE // 2, 40, 0, 0), Command(EVENT, 0, 4, 777, plane=1), Command(LINE, ONE // 2, 40, 0, 0),
             Command(EVENT, 0, 4, 0, plane=1), Command(EVENT, 0, 3, 0, plane=1), Command(LINE, ONE // 2, 40, 0, 0)]
    _, _, mon, cycles = await tb.run(lines, context="inline")
    barrier = [replace(c, plane=0) for c in lines]
    _, _, _, stopping = await tb.run(barrier, context="barrier")
    assert cycles < stopping, f"inline {cycles} cycles, barrier {stopping}"
    assert len(mon.pulses) == 120
    _, _, _, _ = await tb.run(lines, hold=lambda c: 300 <= c < 900, context="inline, held")


@cocotb.test()
async def random_mix(dut):
    """Seeded random queues of lines, arcs in all planes, helices, dwells, events, bad commands."""
    rng = seeded_rng(dut, "random_mix")
    tb = await MotionTB(dut).start()
    for n in range(5):
        cmds = []
        for _ in range(rng.randint(1, 7)):
            r = rng.random()
            if r < 0.3:
                cmds.append(random_line(rng, three=rng.random() < 0.7))
            elif r < 0.65:
                cmds.append(random_helix(rng))
            elif r < 0.75:
                cmds.append(Command(EVENT, rng.choice([0, TOP]), rng.randint(0, 1023), rng.randint(-999, 999),
                                    plane=rng.randrange(4)))
            elif r < 0.82:
                cmds.append(Command(DWELL, 0, rng.randint(0, 12)))
            elif r < 0.9:
                cmds.append(Command(rng.choice([ARC_CW, ARC_CCW]), TOP, 4, 4, 3, 4, 0, plane=3))
            else:
                cmds.append(Command(rng.randint(6, 7), TOP, 1, 2, 3))
        timing = rng.choice([FAST, {"pulse_width": 2, "setup": 1, "hold_time": 1}])
        errors, want_errors, _, _ = await tb.run(cmds, timing, hold=hold_pattern(rng), context=f"mix {n}")
        assert errors == want_errors, f"mix {n}: errors {errors}, want {want_errors}"


@cocotb.test()
async def bad_commands_keep_the_queue(dut):
    """Unknown kind, feed 0, a coordinate of -2^(W-1), plane 3, bad profiles (rate 0, rate above
    2^PF, length 0, limit below feed, a move while block_shift < 2): each refused at its push
    with its code; the rest runs."""
    tb = await MotionTB(dut).start()
    lo = -(1 << (tb.width - 1))
    good = tb.profiled([Command(LINE, TOP, 4, 1), Command(LINE, ONE // 3, -2, 7, 1)])
    bad = tb.profiled([Command(6, TOP, 5), Command(LINE, 0, 9, 9), Command(LINE, TOP, lo, 0),
                       Command(ARC_CW, TOP, 0, 0, 0, 3, 0, plane=3), Command(7, 0),
                       Command(ARC_CCW, 0, 0, 0, 0, 3, 0, plane=3)])
    line = tb.profiled([Command(LINE, ONE // 2, 3, 3)])[0]
    profiles = [Command(**{**line.__dict__, **change}) for change in
                ({"rate": 0}, {"rate": (1 << tb.pf) + 1}, {"length": 0}, {"limit": line.feed - 1})]
    cmds = [good[0], *bad, *profiles, good[1]]
    errors, want_errors, _, _ = await tb.run(cmds, profiled=True, context="bad commands")
    assert errors == want_errors == [E_KIND, E_FEED, E_RANGE, E_PLANE, E_KIND, E_FEED] + [E_PROFILE] * 4
    for shift in (0, BLOCK_SHIFT_MIN - 1):
        tb.settings.update(block_shift=shift)
        # (fault=True: the step models know no settings; no pulse may go out)
        errors, _, mon, _ = await tb.run([line], profiled=True, fault=True, context=f"block_shift {shift}")
        assert errors == [E_PROFILE] and not mon.pulses
    tb.settings.update(block_shift=BLOCK_SHIFT_MIN)


@cocotb.test()
async def queue_overflow(dut):
    """Commands pushed into a full queue are refused with E_QUEUE; the accepted ones all run."""
    tb = await MotionTB(dut).start()
    cmds = [Command(LINE, ONE // 4, k + 3, 1) for k in range(tb.qdepth + 5)]
    errors, want_errors, _, _ = await tb.run(cmds, hold=lambda c: c < 40, respect_full=False,
                                             context="overflow")
    assert errors.count(E_QUEUE) >= 3 and want_errors == []


@cocotb.test()
async def reset_at_random_cycles(dut):
    """rst at random cycles (full queues, a ramp under way, a pulse high, a hold): idle at once,
    no further step, positions 0; then a job runs exactly."""
    rng = seeded_rng(dut, "reset_at_random_cycles")
    tb = await MotionTB(dut).start()
    for n in range(3):
        cmds = tb.profiled([random_line(rng, 15) for _ in range(tb.qdepth + 1)])
        when = rng.randint(1, 600)
        for k in range(when):
            push = k < len(cmds)
            tb.drive({**IDLE, **(cmds[k].ports() if push else {}), "cmd_valid": int(push),
                      "hold": int(k % 200 > 150)})
            await FallingEdge(dut.clk)
        await tb.reset({**IDLE, **FAST, **tb.settings})
        tb.ref.reset()
        tb.ref.settled({**IDLE, **FAST, **tb.settings})
        for _ in range(30):
            await FallingEdge(dut.clk)
            tb.ref.clock({**IDLE, **FAST, **tb.settings})          # free-running counters go on
            assert not (int(dut.busy.value) or int(dut.step_x.value) or int(dut.step_y.value)
                        or int(dut.step_z.value) or int(dut.queue_level.value) or int(dut.speed.value))
            assert [read(dut, f"pos_{a}", signed=True) for a in "xyz"] == [0, 0, 0]
        tb.origin = [0, 0, 0]
        errors, _, _, _ = await tb.run([Command(LINE, TOP, -3, 5, 1)], context=f"after reset {n} at {when}")
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
    """At cruise (the middle of a long line) the measured path speed equals the feed within 1 %
    for axial, diagonal and 3-axis lines, with the lecture's costs and with true-length costs."""
    tb = await MotionTB(dut).start()
    # (long enough to cruise over their middle third at one quantum a block)
    for move in [(480, 0, 0), (320, 320, 0), (240, 240, 240), (400, 160, 0)]:
        for lecture in (True, False):
            feed = ONE // 6
            cmds = tb.profiled([Command(LINE, feed, *move)], accel=QUANTUM, lecture=lecture)
            _, _, mon, _ = await tb.run(cmds, profiled=True, context=f"speed {move}")
            rises = [c for c, _, _ in mon.pulses]
            want, _ = queue_steps(cmds)
            lo, hi = len(want) // 3, 2 * len(want) // 3
            if not cmds[0].cost:                    # the lecture's costs (or a cost too wide for FEED_W)
                length = sum(sum(abs(c) for c in s) ** 0.5 for s in want[lo:hi])
            else:
                length = (hi - lo) * cmds[0].cost / tb.one
            speed = length / (rises[hi] - rises[lo])
            assert abs(speed / (feed / ONE) - 1) < 0.01, f"{move}: {speed} vs {feed / ONE}"


def test_motion_top_cli_build(sim):
    """The G-code build: 32-bit fields, FRAC = 32, FEED_W = 34, NW = 24, PF = 16, ..."""
    run_cocotb(toplevel="motion_top", test_module="test_motion_top", sim=sim, parameters=CLI_BUILD,
               name="motion_top_cli", testcase=["planes_and_helices", "events_after_the_drive_stops",
                                                "random_mix", "bad_commands_keep_the_queue", "path_speed",
                                                "hold_resume_override_fuzz"])


def test_motion_top(sim, tmp_path):
    run_cocotb(toplevel="motion_top", test_module="test_motion_top", sim=sim,
               parameters=motion_build.PARAMETERS, name="motion_top")
