# SPDX-License-Identifier: Apache-2.0
"""A Program (moves in machine mm, interp.gcode.moves) -> rtl/motion_top.v commands.

The build the command line uses: W = 32, FRAC = 32, FEED_W = 34.  The rules
(docs/gcode-cli.md is the user's page):

  * positions: every point is rounded to the nearest step ONCE, absolutely
    (round(mm x steps_per_mm)); a command moves from the previous rounded point
    to the next, so nothing drifts.  A line longer than 2^31 - 1 steps on an
    axis is split into equal pieces (integer arithmetic, exact).
  * joined moves (machine file motion.naive_cam, off by default): runs of G1 moves
    within G64's naive-CAM tolerance of a straight line run as that line
    (interp.gcode.naivecam, LinuxCNC's naive CAM detector).
  * soft limits: a move that goes beyond an axis's min_mm .. max_mm (an arc's
    bulge included) is refused before anything runs.
  * arcs (plane mapping (u, v, w) of interface 2: XY (x, y, z), ZX (z, x, y),
    YZ (y, z, x)): the centre is rounded once relative to the rounded start, the
    end absolutely.  If the rounded end is not within half a step of the circle
    through the start (the arc core would refuse it), the arc runs to the
    lattice point on that circle nearest the programmed end's direction, and the
    difference is `pending`: the next line takes it in (it starts there and ends
    on its own rounded end), so does the next arc if the difference lies in its
    plane and it then starts within TAKE_IN_STEPS of its programmed circle (its
    centre is rounded relative to its rounded start, so nothing drifts);
    otherwise, and before a dwell, an event, an exact-stop move or the program's
    end, a short line goes to the rounded end (settle).  P turns are full circles
    before the last part.  An
    arc whose rounded start and end coincide but which is short in the source
    (under half a turn) runs as nothing or a line, never as a full circle.
    Arcs whose radius is beyond the core's limit (2^29 steps) or whose plane
    axes have different steps_per_mm (an ellipse in steps) run as chords
    within a quarter step of the true arc, with a warning.
  * helices: cmd_z = the w travel in steps; cmd_k = the arc's exact step count
    (interp.gcode.stepcount).  A steep helix (|w travel| > cmd_k) is a helix of
    w travel ± cmd_k, then a line along w: the steps the hardware makes in one
    command, with the plane's stop a junction the planner sees.
  * the speed profile (docs/gcode-cli.md, "Speed profile"): every move command
    is a planner segment (interp.gcode.planner: junction deviation, G61 / G64 P,
    exact stops before the first move and after dwells and events); the plan
    becomes the profile fields of each command: cmd_feed = the planned cruise,
    cmd_limit = the axes' ceiling (for feed override), cmd_exit (quanta),
    cmd_rate, cmd_cost and cmd_length (lines and helices: cmd_cost = the TRUE path
    length / N with N the exact number of step events, cmd_length = N x cost; flat
    arcs: cmd_cost = 0, the lecture's 1, sqrt 2 per step event,
    cmd_length their sum, and the command's speeds and acceleration scaled by
    cmd_length / its true length, so that F holds along the true arc on average
    and within its `pacing` locally; costs="even": every move as a line, for
    comparison; costs="lecture": every move by the lecture's costs, unscaled,
    for tests), cmd_budget; and the global speed quantum A,
    block_shift, jerk_shift (Compiled.settings).  Speeds are path units
    (2^-32 steps) per clock: v = mm/s x spm x 2^32 / clock_hz, spm the path's
    steps per mm along the command.  F is capped so that no axis exceeds its
    max_rate_mm_min (with a warning), rapids run at that cap.  A cruise word
    that rounds to 0 is an error.
  * dwells: DWELL commands of at most 2^32 - 1 cycles; events: EVENT commands
    with the codes of EVENT_CODES; a pause event is followed by a DWELL of
    pause_seconds.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..cores import UsageError
from ..models.lecture import within_half_step
from ..models.motion import ARC_CCW, ARC_CW, DWELL, LINE, Command, command_steps, inline, interval_costs, next_not_inline
from ..models.speed_ramp import BLOCK_SHIFT_MIN
from .machine import AXES, Machine
from .moves import CONTINUOUS, EVENTS, PLANES, Arc, Dwell, Event, Line, Program
from .naivecam import collapse
from .stepcount import arc_count, arc_events, helix_count, line_count

EVENT = 5
W, FRAC, FEED_W = 32, 32, 34                 # the CLI's build of motion_top
NW, PF, LEN_W, ZW, MW = 24, 16, 66, 68, 12   # its profile widths (quanta, rate fraction, ...)
BLOCK_SHIFT_MAX = 15                         # block_shift [3:0]
EXIT_MARGIN = 4                              # quanta kept below the next command's braking reach
LINE_MAX = (1 << (W - 1)) - 1                # longest line command per axis (-2^31 is refused)
ARC_LIMIT = 1 << (W - 3)                     # circ_arc: |point - centre| < 2^(W-3) per axis
DWELL_MAX = (1 << W) - 1                     # cycles of one DWELL command (unsigned)
MAX_COMMANDS = 2_000_000                     # commands of one program (minutes to plan)
DWELL_SECONDS_MAX = 86_400                   # a dwell or pause of more than a day is refused
DIGITAL_OUTPUTS = 4                          # the controller's dout[3:0]: M62..M65 P 0 .. 3
FEED_MAX = (1 << FEED_W) - 1
VALUE_MAX = (1 << (W - 1)) - 1               # event values are signed W bits
LEN_MAX, ZW_MAX, NW_MAX = (1 << LEN_W) - 1, (1 << ZW) - 1, (1 << NW) - 1
# Every move lasts at least this many clocks, at any override: speed_ramp sets up the
# successor of a segment while the segment runs (about NW + 3 clocks); a shorter segment
# would end before it and stop at once (motion_top error 9).  Binding only at low clocks
# (a one-step move at 200 kHz: <= 37 mm/s at 100 steps/mm; at 50 MHz: <= 9.3 m/s).
SEGMENT_CLOCKS = 2 * (NW + 3)
COST_MODES = ("true", "even", "lecture")
PWM_FULL = 65535                             # spindle duty of S = max_s
EXACT_STOP_MODES = ("G61", "G61.1")            # path-control modes that stop before every move
TAKE_IN_STEPS = 2.0                          # an arc takes in a correction within this of its circle
CHORD_SAGITTA = 0.25                         # chords stay within this many steps of the true arc
PLANE_CODE = {"XY": 0, "ZX": 1, "YZ": 2}     # cmd_plane
WARNINGS_PER_KIND = 20                       # then one "... and N more" line per kind

# Event codes on event_code (one table; docs/gcode-cli.md lists it).  The value on
# event_value is the programmed value as an integer, except for the spindle's S
# (spindle_cw, spindle_ccw, spindle_speed): a PWM duty 0 .. 65535 = S / max_s.
EVENT_CODES = {"spindle_cw": 1, "spindle_ccw": 2, "spindle_off": 3, "spindle_speed": 4, "mist_on": 5,
               "flood_on": 6, "coolant_off": 7, "output_on": 8, "output_off": 9, "pause": 10,
               "tool_change": 11, "program_end": 12, "laser_mode": 13}
EVENT_NAMES = {code: name for name, code in EVENT_CODES.items()}
SPINDLE_DUTY = ("spindle_cw", "spindle_ccw", "spindle_speed")
assert set(EVENT_CODES) == set(EVENTS)


class CompileError(UsageError):
    """A move the machine cannot make; the message starts with "line L: "."""


@dataclass
class Motion:
    """What the planner needs of one move command (machine mm), and its step events."""

    length_mm: float
    start_unit: tuple[float, float, float]
    end_unit: tuple[float, float, float]
    feed_mm_s: float                       # requested (F capped by the axes, or the rapid rate)
    steps: float                           # true path length in steps (Euclidean in step space)
    events: int                            # N: step events of the command
    radius_mm: float | None = None
    plane_axes: tuple[int, int] | None = None
    stop_before: bool = False
    tolerance_mm: float | None = None
    # the largest local path speed over the mean the hardware's step costs give (planner.Segment)
    pacing: float = 1.0
    even_costs: bool = False               # a helix: its events charged evenly (planner.Segment)
    charge: float = 1.0                    # charged over true path length (flat arcs: the stepped one)
    # the local velocity at the start and at the end over the charged speed (mm/s per charged
    # mm/s, Compiler.local_pace); None: the unit tangents
    start_local: tuple[float, float, float] | None = None
    end_local: tuple[float, float, float] | None = None

    @property
    def spm(self) -> float:
        """Steps per mm along the path."""
        return self.steps / self.length_mm


def planner_segment(motion: Motion, before: Motion | None, rates, accels, *, feed_mm_s: float | None = None,
                    paced: bool = True):
    """The planner's view of a move (planner.Segment), `before` the move ahead of it (None:
    the first); paced=False leaves out the hardware's pace (lines' and arcs' rules alone)."""
    from .planner import Segment

    m = motion
    return Segment(m.length_mm, m.start_unit, m.end_unit, m.feed_mm_s if feed_mm_s is None else feed_mm_s,
                   rates, accels, radius_mm=m.radius_mm, plane_axes=m.plane_axes, stop_before=m.stop_before,
                   tolerance_mm=m.tolerance_mm, pacing=m.pacing if paced else 1.0,
                   even_costs=m.even_costs and paced,
                   junction_velocities=junction_velocities(before, m) if paced and before is not None else None)


def charged_per_mm(before: Motion, after: Motion) -> float:
    """Charged steps per mm of planned speed at the junction between two moves: the speed
    word there is the planned speed on the scale of the side that charges fewer (spm x
    charge; the exit rule of Compiler.profile)."""
    return min(before.spm * before.charge, after.spm * after.charge)


def junction_velocities(before: Motion, after: Motion) -> tuple[tuple, tuple]:
    """The machine's velocities (mm/s) on the two sides of the junction between two moves
    per mm/s of planned speed (planner.Segment.junction_velocities): each side runs the
    speed word there (charged_per_mm) at its own local pace."""
    word = charged_per_mm(before, after)
    end = before.end_local or before.end_unit
    start = after.start_local or after.start_unit
    return tuple(word / before.spm * u for u in end), tuple(word / after.spm * u for u in start)


@dataclass
class Cmd(Command):
    """A motion_top command of the W = 32 build (arc plane and the speed profile's fields are
    Command's), with what the planner needs of a move."""

    motion: Motion | None = field(default=None, compare=False, repr=False)
    # the program's line outside any subroutine that made it (a subroutine's call line), for
    # a run from a line after a stop; 0 where the move does not say (a Line built by hand)
    origin: int = field(default=0, compare=False, repr=False)

    def fields(self) -> tuple[int, ...]:
        """The command file's 16 integers: kind plane feed x y z i j k l limit exit rate cost
        length budget (x of a DWELL as signed W bits, the port's bit pattern)."""
        x = self.x - (1 << W) if self.kind == DWELL and self.x > LINE_MAX else self.x
        return (self.kind, self.plane, self.feed, x, self.y, self.z, self.i, self.j, self.k, self.l,
                self.limit, self.exit, self.rate, self.cost, self.length, self.budget)


@dataclass
class Compiled:
    commands: list[Cmd] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    warning_count: int = 0          # the warnings, those an "N more warnings like the line above" stands for too
    end_steps: tuple[int, int, int] = (0, 0, 0)
    machine_time_s: float = 0.0
    moves: int = 0              # lines and arcs run (joined lines count once)
    joined: int = 0             # G1 moves joined into the one before them (motion.naive_cam: interp.gcode.naivecam)
    arcs: int = 0
    chords: int = 0             # arcs run as chords
    corrected: int = 0          # arcs whose end is off their circle (a correction: taken in or a line)
    events: list[tuple[str, float, int]] = field(default_factory=list)   # (name, value, line), in order
    command_time: list[float] = field(default_factory=list)             # machine seconds at each command's end
    # the harness's settings: speed_quantum (A), block_shift, jerk_shift, override
    settings: dict[str, int] = field(default_factory=dict)
    # the record unpacker's limit and rate codes: limit_scale, limit_shift, rate_scale, rate_shift
    codes: dict[str, int] = field(default_factory=dict)
    plans: list = field(default_factory=list)       # planner.Plan of each move command, in order
    profile: str = "trapezoid"
    costs: str = "true"

    @property
    def step_events(self) -> int:
        """Step events of the whole program (the sum of every command's N)."""
        return sum(c.motion.events for c in self.commands if c.motion is not None)


def write_commands(path, commands: list[Cmd]) -> None:
    """The native harness's command file: one command per line, 16 decimal integers."""
    with open(path, "w") as f:
        f.write("".join(" ".join(map(str, c.fields())) + "\n" for c in commands))


def held_speed(feed: int, quantum: int) -> int:
    """The cruise speed_ramp holds for a feed word: whole quanta, at least one (its cap lowers n
    while n A > feed, down to 1)."""
    return max(1, feed // quantum) * quantum


SCALE_BITS, SHIFT_MAX = 32, 63              # LIMIT_SCALE / RATE_SCALE, MOTION's limit_shift / rate_shift


def scale_of(ratio: float) -> tuple[int, int]:
    """(scale, shift) with scale / 2^shift nearest `ratio`: scale below 2^32, the largest shift
    up to 63 that keeps it there."""
    if ratio <= 0:
        return 0, 0
    shift = max(0, min(SHIFT_MAX, SCALE_BITS - 1 - math.floor(math.log2(ratio))))
    while shift and round(ratio * (1 << shift)) >> SCALE_BITS:
        shift -= 1
    return min(round(ratio * (1 << shift)), (1 << SCALE_BITS) - 1), shift


def fit_scale(pairs, ratios, width: int) -> tuple[int, int]:
    """Of the candidate ratios' (scale, shift), the one for which floor(cost x scale /
    2^shift) mod 2^width equals the value of most (cost, value) pairs; (0, 0) without pairs."""
    best, hits = (0, 0), 0
    mask = (1 << width) - 1
    for candidate in dict.fromkeys(scale_of(r) for r in ratios):
        scale, shift = candidate
        count = sum(1 for cost, value in pairs if (cost * scale >> shift) & mask == value)
        if count > hits:
            best, hits = candidate, count
    return best


def _round(value: float) -> int:
    return math.floor(value + 0.5)


def _angle(a: float) -> float:
    return a % (2 * math.pi)


def _unit(vector) -> tuple[float, float, float]:
    norm = math.sqrt(sum(c * c for c in vector))
    return tuple(c / norm for c in vector) if norm else (0.0, 0.0, 0.0)


class Compiler:
    def __init__(self, machine: Machine, pause_seconds: float = 0.0, profile: str | None = None,
                 costs: str = "true", start_steps=(0, 0, 0)):
        if costs not in COST_MODES:
            raise ValueError(f"costs must be one of {COST_MODES}")
        self.machine = machine
        self.profile_name = profile or machine.values["motion"]["profile"]
        self.costs = costs
        self.spm = machine.steps_per_mm
        self.axes = machine.axes
        self.clock = machine.clock_hz
        if not 0 <= pause_seconds <= DWELL_SECONDS_MAX:
            raise CompileError(f"a pause of {pause_seconds:g} s is out of range (0 .. {DWELL_SECONDS_MAX} s, a day)")
        self.pause_cycles = _round(pause_seconds * self.clock)
        self.here = [int(v) for v in start_steps]      # the machine's position, steps
        # an arc's correction not yet made: (the rounded end, feed mm/s, source line, path
        # control) of an arc that ended on the lattice point beside it; the next line or arc
        # takes it in
        self.pending: tuple[list[int], float, int, tuple] | None = None
        self.out = Compiled(profile=self.profile_name, costs=costs)
        self.stop_next = True           # an exact stop before the next move
        self.first = True               # no command of the programmed move made yet (emit_move)
        # laser mode (spindle.laser): the beam's power (duty), whether M3 / M4 has it on, and
        # whether the path is in a G0 (the beam dark: power 0 until the next feed move)
        self.laser = bool(machine.values["spindle"]["laser"])
        self.power, self.beam_on, self.dark = 0, False, False
        self.path_control = CONTINUOUS  # the path-control mode of the move being compiled (Line.path_control)
        self.origin = 0                 # the origin of the move being compiled (Cmd.origin)
        self._warnings: dict[str, list[str]] = {}
        self._more: dict[str, int] = {}

    # ---------------- helpers ----------------
    def warn(self, kind: str, line: int, text: str) -> None:
        seen = self._warnings.setdefault(kind, [])
        message = f"line {line}: {text}"
        if len(seen) < WARNINGS_PER_KIND:
            if message not in seen:
                seen.append(message)
        else:
            self._more[kind] = self._more.get(kind, 0) + 1

    def check_step_rate(self, cmd, cruise_mm_s: float) -> None:
        """Warn of a move whose cruise steps an axis faster than the output stage allows: a
        pulse of output.pulse_ns and a clock low, at most clock / (pulse + 1) steps a second.
        Its steps then fall behind the plan and come late; a backlog the step pacer cannot hold
        stops the controller with error 10 (none is lost silently)."""
        m = cmd.motion
        pulse = self.machine.timing()["pulse_width"]
        most = self.clock / (pulse + 1)
        for axis, spm in enumerate(self.spm):
            share = 1.0 if m.plane_axes and axis in m.plane_axes else max(abs(m.start_unit[axis]), abs(m.end_unit[axis]))
            rate = cruise_mm_s * share * spm
            if rate > most * (1 + 1e-9):
                self.warn("step_rate", cmd.source, f"{rate:.0f} steps/s on {'XYZ'[axis]} is above the {most:.0f} "
                          f"that output.pulse_ns allows ({pulse} clocks of pulse and one low at "
                          f"{self.clock:g} Hz): its steps fall behind and come late (a long such move stops with "
                          f"error 10); shorten the pulse, "
                          f"raise the clock or lower the axis's max_rate_mm_min / the feed")
                return

    def steps(self, point) -> list[int]:
        return [_round(p * s) for p, s in zip(point, self.spm)]

    def check_travel(self, line: int, axis: int, value: float, inside_arc: bool = False) -> None:
        """inside_arc: the value is an arc's extreme, not a coordinate the program wrote."""
        a = self.axes[axis]
        if not a.min_mm - 1e-6 <= value <= a.max_mm + 1e-6:
            name = AXES[axis].upper()
            where = f"the arc reaches {name} {value:.6g} mm," if inside_arc else f"{name} {value:.6g} mm is"
            raise CompileError(f"line {line}: {where} beyond the {name} travel "
                               f"{a.min_mm:g} .. {a.max_mm:g} mm (machine file)")

    def room(self, count: int, line: int) -> None:
        """Refuse a program that would make more than MAX_COMMANDS commands."""
        if len(self.out.commands) + count > MAX_COMMANDS:
            raise CompileError(f"line {line}: the program makes more than {MAX_COMMANDS} motion_top commands: "
                               f"split it")

    def emit(self, cmd: Cmd) -> None:
        self.room(1, cmd.source)
        if cmd.motion is None and not inline(cmd):  # a dwell or an event: a barrier, a stop after it
            self.stop_next = True
        cmd.origin = self.origin
        self.out.commands.append(cmd)

    def emit_event(self, name: str, value: int, shown: float, line: int, inline_event: bool = False) -> None:
        """An EVENT command (value on event_value) and its entry in the events list (`shown`: the
        programmed value it stands for); inline_event: plane bit 0, motion_top runs it without
        a stop (a laser's power along its path)."""
        self.emit(Cmd(EVENT, 0, EVENT_CODES[name], value, plane=int(inline_event), source=line))
        self.out.events.append((name, shown, line))

    def inline_power(self, value: int, line: int, shown: float) -> None:
        """Laser mode: the beam's power (a spindle_speed event of duty `value`, S `shown`) set
        along the path, inline: no stop."""
        self.emit_event("spindle_speed", value, shown, line, inline_event=True)

    def laser_rapid(self, rapid: bool, line: int) -> None:
        """Laser mode: the beam off during a G0 (its power 0 inline before it), back to the
        programmed power before the next feed move, as Grbl's laser mode."""
        if not self.laser or rapid == self.dark:
            return
        self.dark = rapid                           # (whatever the power: an S during the G0 waits)
        if self.beam_on and self.power:
            self.settle()                           # (an arc's correction: before the change)
            self.inline_power(0 if rapid else self.power, line,
                              0 if rapid else self.power / PWM_FULL * self.machine.max_s)

    def emit_move(self, cmd: Cmd, feed_mm_s: float, start_mm, end_mm, steps: float, events: int,
                  length_mm: float, radius_mm: float | None = None, plane_axes=None, piece: bool = False) -> None:
        """A LINE or ARC command with what the planner needs of it.  An exact-stop mode stops
        before the first command of a programmed move only: not before its other pieces (an
        arc's turns and chords, a long line's parts) nor before a correction (`piece`) that
        finishes the move before it."""
        self.room(1, cmd.source)
        mode, tolerance = self.path_control
        exact = mode in EXACT_STOP_MODES and self.first and not piece
        cmd.motion = Motion(length_mm, _unit(start_mm), _unit(end_mm), feed_mm_s, steps, events, radius_mm,
                            plane_axes, stop_before=self.stop_next or exact, tolerance_mm=tolerance)
        self.stop_next = False
        self.first = self.first and piece
        cmd.origin = self.origin
        self.out.commands.append(cmd)

    def feed_cap(self, delta_mm) -> float:
        """The highest path speed (mm/min) along delta_mm at which no axis exceeds its max rate."""
        length = math.sqrt(sum(d * d for d in delta_mm))
        caps = [a.max_rate_mm_min * length / abs(d) for a, d in zip(self.axes, delta_mm) if d]
        return min(caps) if caps else min(a.max_rate_mm_min for a in self.axes)

    def feed_used(self, feed: float | None, cap: float, line: int) -> float:
        """The requested speed in mm/s: F (mm/min) capped by the axes, the cap for a rapid."""
        if feed is None:
            return cap / 60
        if feed > cap * (1 + 1e-9):
            self.warn("feed_cap", line, f"F{feed:g} mm/min is above the axes' max rate along this move; "
                      f"it runs at {cap:.6g} mm/min")
            return cap / 60
        return feed / 60

    # ---------------- lines ----------------
    def line_to(self, target: list[int], feed_mm_s: float, line: int, piece: bool = False) -> None:
        """LINE commands from here to target (steps), split into pieces below 2^31 steps."""
        self.line_by([t - h for t, h in zip(target, self.here)], feed_mm_s, line, piece)
        self.here = list(target)

    def line_by(self, delta: list[int], feed_mm_s: float, line: int, piece: bool = False) -> None:
        """LINE commands moving by delta (steps), split into pieces below 2^31 steps."""
        big = max(abs(d) for d in delta)
        if big == 0:
            return
        pieces = -(-big // LINE_MAX)
        done = [0, 0, 0]
        for p in range(1, pieces + 1):
            part = [(2 * d * p + pieces) // (2 * pieces) for d in delta]         # round(d * p / pieces)
            step = [a - b for a, b in zip(part, done)]
            mm = [d / s for d, s in zip(step, self.spm)]
            self.emit_move(Cmd(LINE, 0, *step, source=line), feed_mm_s, mm, mm,
                           math.sqrt(sum(d * d for d in step)), line_count(*step),
                           math.sqrt(sum(d * d for d in mm)), piece=piece)
            done = part

    def settle(self) -> None:
        """Make the pending correction: a short line to the arc's rounded end."""
        if self.pending is not None:
            target, feed, line, control = self.pending
            self.pending = None
            moving, self.path_control = self.path_control, control      # (the arc's tolerance)
            self.line_to(target, feed, line, piece=True)
            self.path_control = moving

    def exact_stop(self) -> bool:
        """Whether the move being compiled starts with an exact stop (its path-control mode)."""
        return self.path_control[0] in EXACT_STOP_MODES

    def segment(self, start, end, feed, line: int) -> None:
        """A straight move between two points in mm (a G0/G1 line or a chord); it takes in a
        pending correction (it starts where the arc before it ended)."""
        for k in range(3):
            self.check_travel(line, k, end[k])
        if self.exact_stop():
            self.settle()
        self.pending = None
        target = self.steps(end)
        if target == self.here:
            return
        delta = [e - s for e, s in zip(end, start)]
        length = math.sqrt(sum(d * d for d in delta))
        if length == 0:             # the rounded start differs from here: a repositioning
            delta = [(t - h) / s for t, h, s in zip(target, self.here, self.spm)]
        self.line_to(target, self.feed_used(feed, self.feed_cap(delta), line), line)

    # ---------------- arcs ----------------
    def arc(self, m: Arc) -> None:
        iu, iv, iw = PLANES[m.plane]
        s_u, s_v, s_w = self.spm[iu], self.spm[iv], self.spm[iw]
        su, sv = m.start[iu] - m.centre[iu], m.start[iv] - m.centre[iv]
        eu, ev = m.end[iu] - m.centre[iu], m.end[iv] - m.centre[iv]
        r = math.hypot(su, sv)
        a0, a1 = math.atan2(sv, su), math.atan2(ev, eu)
        full = abs(m.end[iu] - m.start[iu]) < 1e-9 and abs(m.end[iv] - m.start[iv]) < 1e-9
        part = 2 * math.pi if full else _angle(a1 - a0) if m.ccw else _angle(a0 - a1)
        if part == 0:
            part = 2 * math.pi
        turns = max(1, m.turns)
        sweep = part + 2 * math.pi * (turns - 1)
        dw = m.end[iw] - m.start[iw]
        self.arc_travel(m, iu, iv, iw, r, a0, sweep)
        if r < 1e-12:                   # no radius (the interpreter refuses these): a line
            return self.segment(m.start, m.end, m.feed, m.line)
        plane_len = r * sweep
        length = math.hypot(plane_len, dw)
        if length == 0:
            return
        turn = 1 if m.ccw else -1
        if s_u != s_v:
            return self.chords(m, r, a0, turn * sweep, "the plane's axes have different steps_per_mm "
                               "(an ellipse in steps)")
        if (r * s_u + 2 + TAKE_IN_STEPS) >= ARC_LIMIT:       # (+ a start taken in off the circle)
            return self.chords(m, r, a0, turn * sweep, f"its radius is beyond the arc core's limit "
                               f"({ARC_LIMIT} steps)")
        caps = [min(self.axes[iu].max_rate_mm_min, self.axes[iv].max_rate_mm_min) * length / plane_len
                if plane_len else math.inf]
        if dw:
            caps.append(self.axes[iw].max_rate_mm_min * length / abs(dw))
        feed = self.feed_used(m.feed, min(caps), m.line)

        def centre(start_steps) -> tuple[int, int]:
            """The centre in steps, rounded relative to the rounded start."""
            return start_steps[iu] + _round(-su * s_u), start_steps[iv] + _round(-sv * s_v)

        # a pending correction in this plane is taken in (the arc starts where the one
        # before ended) if that start is within TAKE_IN_STEPS of the programmed circle
        if self.pending is not None:
            cu, cv = centre(self.pending[0])
            if self.exact_stop() or self.pending[0][iw] != self.here[iw] or \
                    abs(math.hypot(cu - self.here[iu], cv - self.here[iv]) - r * s_u) > TAKE_IN_STEPS:
                self.settle()
            self.pending = None
        else:
            cu, cv = centre(self.here)
        start = list(self.here)
        ci, cj = cu - start[iu], cv - start[iv]                 # the centre relative to the start
        r2 = ci * ci + cj * cj
        end = self.steps(m.end)
        if r2 == 0:                                             # radius under half a step: a line
            return self.line_to(end, feed, m.line)
        w0 = start[iw]
        kind = ARC_CCW if m.ccw else ARC_CW
        plane = PLANE_CODE[m.plane]
        a_start = math.atan2(-cj, -ci)
        w_prev = w0
        for k in range(1, turns):                               # full circles first
            w_k = _round((m.start[iw] + dw * (2 * math.pi * k / sweep)) * s_w)
            self.arc_command(kind, plane, ci, cj, 0, 0, w_k - w_prev, 2 * math.pi, feed, m, a_start)
            w_prev = w_k
        # the last part: to the rounded end if the core accepts it, else to the lattice point
        pu, pv = end[iu] - cu, end[iv] - cv
        if not within_half_step(r2, pu * pu + pv * pv):
            target = math.atan2(m.end[iv] * s_v - cv, m.end[iu] * s_u - cu)
            pu, pv = self.lattice_point(r2, target, (m.end[iu] * s_u - cu, m.end[iv] * s_v - cv))
            self.out.corrected += 1
        cmd_part = 2 * math.pi if (pu, pv) == (-ci, -cj) else (
            _angle(math.atan2(pv, pu) - a_start) if m.ccw else _angle(a_start - math.atan2(pv, pu)))
        if abs(cmd_part - part) > math.pi:
            # the lattice circle closes where the source does not (or the reverse): a short
            # arc whose ends round together, or an almost-full one: chords are exact here
            self.here[iw] = w_prev
            if part < math.pi and (pu, pv) == (-ci, -cj):
                return self.line_to(end, feed, m.line)
            return self.chords(m, r, a0 + turn * 2 * math.pi * (turns - 1), turn * part, None,
                               start_w=m.start[iw] + dw * (sweep - part) / sweep)
        self.arc_command(kind, plane, ci, cj, pu + ci, pv + cj, end[iw] - w_prev, cmd_part, feed, m, a_start)
        here = [0, 0, 0]
        here[iu], here[iv], here[iw] = cu + pu, cv + pv, end[iw]
        self.here = here
        if here != end:                     # the correction: the next line or arc takes it in
            self.pending = (end, feed, m.line, m.path_control)

    def arc_command(self, kind, plane, ci, cj, x, y, travel, sweep, feed, m: Arc, a_start) -> None:
        """An ARC command (start 0, centre (ci, cj), end (x, y) in the plane, w travel) with
        the exact step count for cmd_k and the planner's view of it.  A steep helix, whose w
        travel is beyond its arc's steps, runs as the hardware would run it in one command:
        a helix whose every event steps w, then a line along w (its plane stops there, a
        corner the planner must see)."""
        iu, iv, iw = PLANES[m.plane]
        s_u, s_w = self.spm[iu], self.spm[iw]
        arc_n = arc_count(ci, cj, x, y, kind == ARC_CCW)
        count = arc_n
        rest = travel - (arc_n if travel > 0 else -arc_n) if abs(travel) > arc_n > 0 else 0
        travel -= rest
        rs = math.sqrt(ci * ci + cj * cj)
        r_mm, dw_mm = rs / s_u, travel / s_w
        length_mm = math.hypot(r_mm * sweep, dw_mm)
        turn = 1 if kind == ARC_CCW else -1

        def tangent(angle: float):
            out = [0.0, 0.0, 0.0]
            out[iu] = -turn * math.sin(angle) * r_mm * sweep
            out[iv] = turn * math.cos(angle) * r_mm * sweep
            out[iw] = dw_mm
            return out

        cmd = Cmd(kind, 0, x, y, travel, ci, cj, count, source=m.line, plane=plane)
        self.emit_move(cmd, feed, tangent(a_start), tangent(a_start + turn * sweep),
                       math.hypot(rs * sweep, travel), helix_count(arc_n, travel, count), length_mm,
                       radius_mm=r_mm, plane_axes=(iu, iv))
        if rest:
            self.line_by([rest if axis == iw else 0 for axis in range(3)], feed, m.line)

    def lattice_point(self, r2: int, angle: float, exact) -> tuple[int, int]:
        """The lattice point within half a step of the circle u^2 + v^2 = r2 nearest to
        the direction `angle` (ties: nearest to `exact`)."""
        rs = math.sqrt(r2)
        tu, tv = rs * math.cos(angle), rs * math.sin(angle)
        for reach in (2, 4):
            best = None
            for u in range(math.floor(tu) - reach, math.floor(tu) + reach + 2):
                for v in range(math.floor(tv) - reach, math.floor(tv) + reach + 2):
                    if not within_half_step(r2, u * u + v * v):
                        continue
                    off = abs(math.remainder(math.atan2(v, u) - angle, 2 * math.pi))
                    key = (off, math.hypot(u - exact[0], v - exact[1]))
                    if best is None or key < best[0]:
                        best = (key, (u, v))
            if best:
                return best[1]
        raise AssertionError(f"no lattice point within half a step of r^2 = {r2} near {angle}")

    def arc_travel(self, m: Arc, iu, iv, iw, r, a0, sweep) -> None:
        """Soft limits over the whole arc: its end, and its extremes in the plane."""
        for k in range(3):
            self.check_travel(m.line, k, m.end[k])
        for quarter in range(4):
            ang = quarter * math.pi / 2
            ahead = _angle(ang - a0) if m.ccw else _angle(a0 - ang)
            if sweep >= 2 * math.pi or ahead <= sweep:
                axis, value = (iu, m.centre[iu] + r * math.cos(ang)) if quarter % 2 == 0 else \
                    (iv, m.centre[iv] + r * math.sin(ang))
                self.check_travel(m.line, axis, round(value, 9), inside_arc=True)

    def chords(self, m: Arc, r: float, a0: float, signed_sweep: float, reason: str | None,
               start_w: float | None = None) -> None:
        """The arc as lines within CHORD_SAGITTA steps of it."""
        iu, iv, iw = PLANES[m.plane]
        big = r * max(self.spm[iu], self.spm[iv])
        # the angle whose chord is CHORD_SAGITTA inside: 1 - cos(step / 2) = sagitta / big, in a form
        # that stays above 0 for any radius
        step = 4 * math.asin(math.sqrt(CHORD_SAGITTA / (2 * big))) if big > CHORD_SAGITTA else math.pi / 2
        n = max(1, math.ceil(abs(signed_sweep) / step - 1e-9))
        w0 = m.start[iw] if start_w is None else start_w
        dw = m.end[iw] - w0
        self.room(n, m.line)
        if reason:
            self.out.chords += 1
            self.warn("chords", m.line, f"arc run as {n} chords: {reason}")
        prev = [0.0, 0.0, 0.0]
        prev[iu], prev[iv], prev[iw] = m.centre[iu] + r * math.cos(a0), m.centre[iv] + r * math.sin(a0), w0
        for k in range(1, n + 1):
            if k == n:
                point = list(m.end)
            else:
                a = a0 + signed_sweep * k / n
                point = [0.0, 0.0, 0.0]
                point[iu], point[iv] = m.centre[iu] + r * math.cos(a), m.centre[iv] + r * math.sin(a)
                point[iw] = w0 + dw * k / n
            self.segment(prev, point, m.feed, m.line)
            prev = point

    # ---------------- the rest ----------------
    def dwell(self, m: Dwell) -> None:
        self.settle()
        if not 0 <= m.seconds <= DWELL_SECONDS_MAX:
            raise CompileError(f"line {m.line}: a dwell of {m.seconds:g} s is out of range "
                               f"(0 .. {DWELL_SECONDS_MAX} s, a day)")
        self.pause(_round(m.seconds * self.clock), m.line, always=True)

    def pause(self, cycles: int, line: int, always: bool = False) -> None:
        if cycles == 0 and always:
            self.emit(Cmd(DWELL, 0, 0, source=line))
        while cycles > 0:
            part = min(cycles, DWELL_MAX)
            self.emit(Cmd(DWELL, 0, part, source=line))
            cycles -= part

    def event(self, m: Event) -> None:
        self.settle()
        if m.name not in EVENT_CODES:
            raise CompileError(f"line {m.line}: unknown event {m.name!r}")
        if m.name in SPINDLE_DUTY:
            s = max(m.value, 0.0)
            if s > self.machine.max_s:
                self.warn("spindle", m.line, f"S{m.value:g} is above the spindle's max_s "
                          f"{self.machine.max_s:g}; it runs at full duty")
                s = self.machine.max_s
            value = _round(s / self.machine.max_s * PWM_FULL)
        elif m.name in ("output_on", "output_off") and m.value not in range(DIGITAL_OUTPUTS):
            raise CompileError(f"line {m.line}: output {m.value:g}: the controller has digital outputs "
                               f"0 .. {DIGITAL_OUTPUTS - 1} (M62..M65 P)")
        else:
            if not math.isfinite(m.value) or abs(m.value) > VALUE_MAX:
                raise CompileError(f"line {m.line}: {m.name} value {m.value:g} does not fit the event "
                                   f"value (32 bits)")
            value = _round(m.value)
        if self.laser and m.name in SPINDLE_DUTY:
            self.power = value
        if self.laser and m.name == "spindle_speed":
            if self.beam_on and not self.dark:      # along the path, no stop; during a G0 it waits
                self.inline_power(value, m.line, m.value)
        else:
            shown = m.value
            if self.laser and m.name in ("spindle_cw", "spindle_ccw") and self.dark:
                value = shown = 0                   # M3 between G0s: the beam stays off until a feed move
            self.emit_event(m.name, value, shown, m.line)
        if self.laser and m.name in ("spindle_cw", "spindle_ccw", "spindle_off", "program_end"):
            self.beam_on = m.name in ("spindle_cw", "spindle_ccw")
        if m.name == "pause":
            self.pause(self.pause_cycles, m.line)

    # ---------------- the speed profile ----------------
    def shifts(self, accel_mm_s2: float, least: int = BLOCK_SHIFT_MIN) -> tuple[int, int]:
        """(block_shift, jerk_shift): `least` (at least BLOCK_SHIFT_MIN, blocks of 4 clocks,
        the least the speed generator's decision pipeline takes; more where the profile's
        words need it, least_block_shift) and 0 for the trapezoid; for the S-curve the
        smallest window 2^(jerk_shift + block_shift) clocks >= 2 accel / J seconds,
        jerk_shift <= MW, block_shift >= least.

        The moving average over W turns a step of the acceleration from a to a' into a
        jerk of |a - a'| / W: a / W where a ramp meets a cruise, 2 a / W where an
        acceleration turns straight into a deceleration (a short move, a hold).  The
        window 2 a / J keeps both within J."""
        if self.profile_name == "trapezoid":
            return least, 0
        jerk = self.machine.values["motion"]["jerk_mm_s3"]
        cycles = 2 * accel_mm_s2 / jerk * self.clock
        if cycles <= 1:
            total = 0
        else:                                                # (cycles is inf for a tiny jerk)
            total = math.ceil(math.log2(cycles) - 1e-12) if cycles < math.inf else math.inf
        jerk_shift = min(MW, max(0, total - least))
        block_shift = max(least, total - jerk_shift)
        if block_shift > BLOCK_SHIFT_MAX:
            raise CompileError(f"the S-curve's window 2 accel / jerk = 2 x {accel_mm_s2:g} / {jerk:g} s is "
                               f"{cycles:.4g} clock cycles, beyond the hardware's 2^{MW + BLOCK_SHIFT_MAX}: "
                               f"raise motion.jerk_mm_s3 or lower the clock")
        return block_shift, jerk_shift

    def code_scales(self, moves, block_shift: int, quantum: int) -> dict[str, int]:
        """The scales of the record unpacker's limit and rate codes (LIMIT_SCALE, RATE_SCALE and
        MOTION's shifts): a line whose dominant axis binds has limit = floor(cost x the axis's
        top speed in steps per clock) and rate = floor(cost x its acceleration's rate per unit
        of cost); of the axes' values, the one that gives the program's commands exactly most
        often (interp send sends the code only where it does)."""
        speeds = [a.max_rate_mm_min / 60 * a.steps_per_mm / self.clock for a in self.axes]
        accels = [a.accel_mm_s2 * a.steps_per_mm / self.clock ** 2 * (1 << (block_shift + PF)) / quantum
                  for a in self.axes]
        costed = [c for c in moves if c.cost]
        limit = fit_scale([(c.cost, c.limit) for c in costed], speeds, FEED_W)
        rate = fit_scale([(c.cost, c.rate) for c in costed], accels, PF + 1)
        return {"limit_scale": limit[0], "limit_shift": limit[1], "rate_scale": rate[0], "rate_shift": rate[1]}

    @staticmethod
    def least_block_shift(a_pu: float, speed_pu: float, braking: float) -> int:
        """The smallest block_shift >= BLOCK_SHIFT_MIN at which the profile's words hold the
        program: with A = ceil(2^block_shift x a_pu) (a_pu the largest path acceleration per
        clock^2), the fastest speed word (cruise or ceiling, speed_pu) is below 2^NW quanta
        and every budget, at most 2 x 2^PF x a_i x length_i / A^2 (braking: the largest
        a_i x length_i), below 2^ZW.  A larger block makes the quantum larger and both
        smaller (the speed by 2^block_shift, the budget by 4^block_shift); the quantum stays
        2^block_shift x the acceleration per clock (rounded up to a whole path unit), so the
        speeds' resolution is that of the acceleration over a block.  The block also holds
        at least 1/16 path unit of the largest acceleration (2^block_shift x a_pu >= 1/16, up
        to BLOCK_SHIFT_MAX), so that the rates keep their precision where A is rounded up to
        1.  BLOCK_SHIFT_MAX + 1 if the words fit no block."""
        for shift in range(BLOCK_SHIFT_MIN, BLOCK_SHIFT_MAX + 1):
            quantum = max(1, math.ceil((1 << shift) * a_pu))
            fits = speed_pu // quantum <= NW_MAX and (2 << PF) * braking / (quantum * quantum) <= ZW_MAX
            # ... and a block of at least 1/16 path unit of the largest acceleration (where A is
            # rounded up to 1, the largest rate is that x 2^PF: 2^(PF-4) at least, so the rates
            # keep their precision; the largest block if none has it)
            if fits and ((1 << shift) * a_pu >= 1 / 16 or shift == BLOCK_SHIFT_MAX):
                return shift
        return BLOCK_SHIFT_MAX + 1

    def hardware_exits(self, moves: list[Cmd]) -> None:
        """Make every exit reachable by the speed generator's discrete braking: the next
        command, entered at n = cmd_exit quanta, must brake to its own exit within its budget:
        (n + EXIT_MARGIN)^2 <= Z0 / 2^PF + n_exit^2 (quanta^2).  The plan's junction speeds
        are exactly feasible for the continuous trapezoid; the generator steps n by whole
        quanta and needs about 3n more, and its first tick in a command may keep n unchecked
        (2n more), so the tightest exits come down by a few quanta."""
        commands = self.out.commands
        following = {id(c): after for c, after in zip(commands, next_not_inline(commands))}  # (inline: no stop)
        for cmd in reversed(moves):
            nxt = following.get(id(cmd))
            if nxt is None or nxt.motion is None or nxt.motion.stop_before:
                cmd.exit = 0
                continue
            reach = math.isqrt((nxt.budget >> PF) + nxt.exit * nxt.exit) - EXIT_MARGIN
            quantum = self.out.settings["speed_quantum"]
            cmd.exit = max(0, min(cmd.exit, reach, cmd.feed // quantum, nxt.feed // quantum))

    def helix_pacing(self, motion: Motion) -> None:
        """A helix's events, charged evenly, cover sec(theta) of its plane each (an event
        steps the plane's major axis once): its plane's local speed is up to the largest
        sec(theta) over the plane's mean per event (planner.py, even_costs)."""
        from .planner import Segment, largest_secant

        p, q = motion.plane_axes
        cos_a = math.sqrt(max(0.0, 1.0 - motion.start_unit[3 - p - q] ** 2))
        plane_steps = motion.length_mm * cos_a * self.spm[p]
        motion.even_costs = True
        if plane_steps > 0:
            arc = Segment(motion.length_mm, motion.start_unit, motion.end_unit, 1.0, (1.0,) * 3, (1.0,) * 3,
                          radius_mm=motion.radius_mm, plane_axes=motion.plane_axes)
            motion.pacing = max(1.0, largest_secant(arc) * motion.events / plane_steps)

    def local_pace(self, cmd: Cmd) -> None:
        """A move's local velocity at its two ends over the charged speed (Motion.start_local,
        end_local).  A flat arc on the lecture's costs: its unit tangent x g(theta) =
        sqrt(1 + t^2) / (1 + (sqrt 2 - 1) t), t = tan(theta), theta the tangent's angle from its
        octant's axis (an event covers sqrt(1 + t^2) steps of the arc and is charged 1 + (sqrt 2
        - 1) t on average).  A helix, charged evenly: its plane part x sec(theta) x N / (the
        plane's length in steps), w's as is (arc_command splits a steep one: every event
        steps the plane).  (A line keeps None: its unit tangent.)"""
        m = cmd.motion
        p, q = m.plane_axes
        w = 3 - p - q
        ends = []
        for unit in (m.start_unit, m.end_unit):
            major, minor = max(abs(unit[p]), abs(unit[q])), min(abs(unit[p]), abs(unit[q]))
            if major == 0.0:
                factor = 1.0
            elif m.even_costs:
                plane = math.hypot(major, minor)
                factor = plane / major * m.events / (m.length_mm * plane * self.spm[p])
            else:
                t = minor / major
                factor = math.sqrt(1.0 + t * t) / (1.0 + (math.sqrt(2.0) - 1.0) * t)
            end = [u * factor for u in unit]
            end[w] = unit[w]
            ends.append(tuple(end))
        m.start_local, m.end_local = ends

    def stepped_length(self, cmd: Cmd) -> int:
        """The lecture's costs (1, sqrt 2, sqrt 3 x 2^FRAC per 1-, 2-, 3-axis step event,
        rounded as the RTL's step_cost) summed over the command's steps (a flat arc's by its
        step and diagonal counts, a helix's and a line's by the models' step list)."""
        costs = interval_costs(FRAC)
        if cmd.kind in (ARC_CW, ARC_CCW) and cmd.z == 0:   # a flat arc: counted in closed form
            n, diagonal = arc_events(cmd.i, cmd.j, cmd.x, cmd.y, cmd.kind == ARC_CCW)
            return (n - diagonal) * costs[1] + diagonal * costs[2]
        feed, cmd.feed = cmd.feed, cmd.feed or 1            # (the models refuse a zero feed)
        try:
            steps, _ = command_steps(cmd, W)
        finally:
            cmd.feed = feed
        return sum(costs[abs(x) + abs(y) + abs(z)] for x, y, z in steps)

    def profile(self) -> None:
        """Plan the move commands and fill in their profile fields and the settings."""
        moves = [c for c in self.out.commands if c.motion is not None]
        plans, caps = [], []
        # flat arcs run on the lecture's step costs (module docstring): their stepped length
        # over the true one scales the command's speeds, and bounds the local speed.  Helices
        # are charged as lines: core A spreads w evenly over the events, so with the lecture's
        # costs w would run faster near the plane's axes;
        # their plane's local speed follows sec(theta), which the planner bounds (helix_pacing)
        from .planner import limits, plan

        stepped = {}
        if self.costs == "true":
            for c in moves:
                if c.kind in (ARC_CW, ARC_CCW) and c.z == 0:
                    stepped[id(c)] = self.stepped_length(c)
                    c.motion.charge = stepped[id(c)] / (c.motion.steps * (1 << FRAC))
                    c.motion.pacing = max(1.0, c.motion.charge)
                    self.local_pace(c)
                elif c.kind in (ARC_CW, ARC_CCW):
                    self.helix_pacing(c.motion)
                    self.local_pace(c)
        if moves:
            rates = tuple(a.max_rate_mm_min / 60 for a in self.axes)
            accels = tuple(a.accel_mm_s2 for a in self.axes)
            motions = [c.motion for c in moves]
            shortest = [m.length_mm * self.clock / SEGMENT_CLOCKS for m in motions]
            segments = [planner_segment(m, motions[n - 1] if n else None, rates, accels,
                                        feed_mm_s=min(m.feed_mm_s, brief))
                        for n, (m, brief) in enumerate(zip(motions, shortest))]
            deviation = self.machine.values["motion"]["junction_deviation_mm"]
            plans = plan(segments, junction_deviation_mm=deviation)
            # the axes' ceiling for feed override > 100 %: the segment's limits without its feed
            # (one per distinct direction and radius: programs repeat them)
            ceiling: dict = {}
            for m in motions:
                key = (m.start_unit, m.end_unit, m.radius_mm, m.plane_axes, m.pacing, m.even_costs)
                if key not in ceiling:
                    ceiling[key] = limits(planner_segment(m, None, rates, accels, feed_mm_s=math.inf))[0]
                caps.append(min(ceiling[key], m.length_mm * self.clock / SEGMENT_CLOCKS))
        clock = self.clock
        # path units / clock per mm/s along the true path: the speeds' words (`scale`, the arcs'
        # stepped over true length in).  An exit is the plan's on the smaller of its two sides'
        # scales (charged_per_mm), which the planner's junction limits assumed: each side's
        # local velocity at that word is within the junction's rule, and a tangent join of two
        # arcs at their cruise keeps the cruise word
        along = [c.motion.spm * (1 << FRAC) / clock for c in moves]
        scale = [k * c.motion.charge for c, k in zip(moves, along)]
        # (the accelerations, and so the block, do not depend on the junction speeds)
        a_pu = [p.accel_mm_s2 * k / clock for p, k in zip(plans, scale)]
        # the block the profile's words need: the fastest word and the largest a x length
        # (margins: the cruise's rounding; a length of the lecture's costs, up to sqrt 3 x
        # the true one)
        speed_pu = max((max(p.cruise_mm_s, cap) * k for p, cap, k in zip(plans, caps, scale)), default=0.0)
        braking = max((a * c.motion.steps * c.motion.charge * (1 << FRAC) for c, a in zip(moves, a_pu)),
                      default=0.0)
        least = self.least_block_shift(max(a_pu, default=1.0), min(speed_pu, FEED_MAX) * 1.01, braking * 2)
        if least > BLOCK_SHIFT_MAX:
            raise CompileError(f"the program's speeds and moves do not fit the speed generator's words "
                               f"(NW {NW}, ZW {ZW} bits) at any block: shorten the longest move or lower the "
                               f"clock")
        block_shift, jerk_shift = self.shifts(max((p.accel_mm_s2 for p in plans), default=0.0), least)
        if moves and self.profile_name != "trapezoid":
            # the S-curve's moving average spreads the speed around a corner: plan the
            # junctions for the filtered speed (the window W = 2^(block + jerk shift) clocks)
            plans = plan(segments, junction_deviation_mm=deviation,
                         smoothing_s=(1 << (block_shift + jerk_shift)) / clock)
        self.out.plans = plans
        quantum = max(1, math.ceil((1 << block_shift) * max(a_pu, default=1.0)))
        if quantum > FEED_MAX:
            raise CompileError(f"the speed quantum {quantum} does not fit cmd_feed's {FEED_W} bits")
        self.out.settings = {"speed_quantum": quantum, "block_shift": block_shift, "jerk_shift": jerk_shift,
                             "override": 100}
        slower = {}                     # planned cruise over the speed the hardware holds
        for n, (cmd, p, k, a) in enumerate(zip(moves, plans, scale, a_pu)):
            want = p.cruise_mm_s * k
            feed = _round(want)
            if feed <= 0:
                slowest = 0.5 / k * 60
                raise CompileError(f"line {cmd.source}: feed {p.cruise_mm_s * 60:g} mm/min is too slow for "
                                   f"the controller: its speed word rounds to 0 (slowest {slowest:.3g} mm/min "
                                   f"at {clock:g} Hz)")
            cmd.feed = min(feed, FEED_MAX)
            held = held_speed(cmd.feed, quantum)
            slower[id(cmd)] = want / held
            if not 0.99 * want <= held <= 1.01 * want:
                cause, remedy = (("a path unit, 2^-32 step, per clock", "lower the clock") if quantum == 1 else
                                 ("2^block_shift x the largest acceleration per clock",
                                  "raise the clock or lower the accelerations"))
                self.warn("quantum", cmd.source, f"feed {p.cruise_mm_s * 60:g} mm/min runs at {held / k * 60:.3g} "
                          f"mm/min: the speed generator holds whole quanta of {quantum / k * 60:.3g} mm/min "
                          f"({cause} at {clock:g} Hz): {remedy}")
            self.check_step_rate(cmd, p.cruise_mm_s)
            cmd.limit = max(cmd.feed, min(FEED_MAX, math.floor(caps[n] * k)))
            cmd.exit = min(NW_MAX, math.floor(p.exit_mm_s * min(scale[n:n + 2]) / quantum))
            rate = a * (1 << block_shift) * (1 << PF) / quantum
            if rate < 1:
                raise CompileError(f"line {cmd.source}: its acceleration, {p.accel_mm_s2:g} mm/s^2, is below the "
                                   f"speed generator's resolution at {clock:g} Hz (a rate of {rate:.3g} of 2^{PF}): "
                                   f"lower the clock or raise the axes' accel_mm_s2")
            cmd.rate = min(1 << PF, math.floor(rate))
            if cmd.rate < 0.99 * rate:
                self.warn("accel", cmd.source, f"acceleration {p.accel_mm_s2:g} mm/s^2 runs at "
                          f"{p.accel_mm_s2 * cmd.rate / rate:.3g} mm/s^2: the speed generator's rate is a whole "
                          f"{cmd.rate} of 2^{PF} at {clock:g} Hz: lower the clock or raise the axes' accel_mm_s2")
            events = cmd.motion.events
            if id(cmd) in stepped:
                cmd.cost, cmd.length = 0, stepped[id(cmd)]
            elif self.costs == "lecture":
                cmd.cost, cmd.length = 0, self.stepped_length(cmd)
            else:
                cmd.cost = max(1, _round(cmd.motion.steps * (1 << FRAC) / events))
                cmd.length = events * cmd.cost
            cmd.budget = 2 * cmd.rate * cmd.length // (quantum << block_shift)
            if cmd.length > LEN_MAX or cmd.budget > ZW_MAX or cmd.limit // quantum > NW_MAX:
                raise CompileError(f"line {cmd.source}: the move is too long or too fast for cmd_length / "
                                   f"cmd_budget / the speed in quanta")
        self.hardware_exits(moves)
        self.out.codes = self.code_scales(moves, block_shift, quantum)
        # machine time: the plan's trapezoids, the dwells; the S-curve's filter adds its window
        # (2^(jerk_shift + block_shift) clocks) to every run between two stops
        window = (1 << (block_shift + jerk_shift)) / clock if self.profile_name != "trapezoid" else 0.0
        plan_of = {id(c): p for c, p in zip(moves, plans)}
        t = 0.0
        commands = self.out.commands
        self.out.command_time = []
        following_of = next_not_inline(commands)
        for n, cmd in enumerate(commands):
            if cmd.motion is not None:
                # at the speed the hardware holds, whole quanta (the warning above)
                t += plan_of[id(cmd)].time_s * slower[id(cmd)]
                following = following_of[n]
                if following is None or following.motion is None or following.motion.stop_before:
                    t += window
            elif cmd.kind == DWELL:
                t += (cmd.x & DWELL_MAX) / clock
            self.out.command_time.append(t)
        self.out.machine_time_s = t

    def run(self, program: Program) -> Compiled:
        if self.laser:
            self.emit_event("laser_mode", 1, 1, program.moves[0].line if program.moves else 0, inline_event=True)
        moves = program.moves
        if self.machine.values["motion"]["naive_cam"]:
            moves, self.out.joined = collapse(moves)
        for m in moves:
            self.first = True
            self.origin = m.origin
            if isinstance(m, (Line, Arc)):
                self.path_control = m.path_control
                self.first = not m.continues                   # (a G5 curve's pieces after its first)
            if isinstance(m, Line):
                self.out.moves += 1
                self.laser_rapid(m.feed is None, m.line)
                self.segment(m.start, m.end, m.feed, m.line)
            elif isinstance(m, Arc):
                self.out.moves += 1
                self.out.arcs += 1
                self.laser_rapid(False, m.line)
                self.arc(m)
            elif isinstance(m, Dwell):
                self.dwell(m)
            elif isinstance(m, Event):
                self.event(m)
            else:
                raise TypeError(f"not a move: {m!r}")
        self.settle()
        if self.laser:
            end = self.out.commands[-1].source
            if self.beam_on:                        # no beam left on at rest when laser mode ends
                self.emit_event("spindle_off", 0, 0, end)
                self.beam_on = False
            self.emit_event("laser_mode", 0, 0, end, inline_event=True)
        self.out.end_steps = tuple(self.here)
        self.profile()
        for kind, seen in self._warnings.items():
            self.out.warnings += seen
            self.out.warning_count += len(seen) + self._more.get(kind, 0)
            if self._more.get(kind):
                self.out.warnings.append(f"{self._more[kind]} more warnings like the line above")
        return self.out


def compile_program(program: Program, machine: Machine, pause_seconds: float = 0.0, *,
                    profile: str | None = None, costs: str = "true", start_steps=(0, 0, 0)) -> Compiled:
    """The program's motion_top commands with their speed profile, the harness settings, end
    point, time estimate and warnings.  profile: "trapezoid" | "scurve" (default: the machine
    file's); costs: "true" (lines, helices: cmd_cost = true length / N; flat arcs: the lecture's costs, their
    speeds scaled to the true length), "even" (every move cmd_cost = true length / N, for
    comparison) or "lecture" (every move cmd_cost 0, unscaled, for tests); start_steps: the
    machine's position when the program starts (steps; the program's interpretation must start
    at start_mm(machine, start_steps))."""
    return Compiler(machine, pause_seconds, profile, costs, start_steps).run(program)


def start_mm(machine: Machine, start_steps) -> tuple[float, float, float]:
    """A position in steps as machine mm (the interpreter's start for compile_program's
    start_steps: rounded back to steps it is start_steps exactly)."""
    return tuple(int(v) / s for v, s in zip(start_steps, machine.steps_per_mm))
