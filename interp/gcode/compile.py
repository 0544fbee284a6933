# SPDX-License-Identifier: Apache-2.0
"""A Program (moves in machine mm, interp.gcode.moves) -> rtl/motion_top.v commands.

The build the command line uses: W = 32, FRAC = 48, FEED_W = 50.  The rules
(docs/gcode-cli.md is the user's page):

  * positions: every point is rounded to the nearest step ONCE, absolutely
    (round(mm x steps_per_mm)); a command moves from the previous rounded point
    to the next, so nothing drifts.  A line longer than 2^31 - 1 steps on an
    axis is split into equal pieces (integer arithmetic, exact).
  * soft limits: a move that goes beyond an axis's min_mm .. max_mm (an arc's
    bulge included) is refused before anything runs.
  * arcs (plane mapping (u, v, w) of interface 2: XY (x, y, z), ZX (z, x, y),
    YZ (y, z, x)): the centre is rounded once relative to the rounded start, the
    end absolutely.  If the rounded end is not within half a step of the circle
    through the start (the arc core would refuse it), the arc runs to the
    lattice point on that circle nearest the programmed end's direction, and a
    short line then goes to the rounded end: the motion ends exactly at the
    programmed end point.  P turns are full circles before the last part.  An
    arc whose rounded start and end coincide but which is short in the source
    (under half a turn) runs as nothing or a line, never as a full circle.
    Arcs whose radius is beyond the core's limit (2^29 steps) or whose plane
    axes have different steps_per_mm (an ellipse in steps) run as chords
    within a quarter step of the true arc, with a warning.
  * helices: cmd_z = the w travel in steps; cmd_k = the arc's step count
    (exact from the arc model for short arcs, else the octant estimate).
  * feed word = round(F x spm / 60 / clock_hz x 2^48), spm the path's length
    in steps per mm along its direction (the axes' steps_per_mm when they are
    equal); F is capped so that no axis exceeds its max_rate_mm_min (with a
    warning), rapids run at that cap.  A word that rounds to 0 is an error; a
    quantisation error above 0.01 % a warning.
  * dwells: DWELL commands of at most 2^32 - 1 cycles; events: EVENT commands
    with the codes of EVENT_CODES; a pause event is followed by a DWELL of
    pause_seconds.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..cores import UsageError
from ..models.lecture import within_half_step
from ..models.motion import ARC_CCW, ARC_CW, DWELL, LINE, Command, FeedRate, line_steps
from .machine import AXES, Machine
from .moves import EVENTS, PLANES, Arc, Dwell, Event, Line, Program

EVENT = 5
W, FRAC, FEED_W = 32, 48, 50                 # the CLI's build of motion_top
LINE_MAX = (1 << (W - 1)) - 1                # longest line command per axis (-2^31 is refused)
ARC_LIMIT = 1 << (W - 3)                     # circ_arc: |point - centre| < 2^(W-3) per axis
DWELL_MAX = (1 << W) - 1                     # cycles of one DWELL command (unsigned)
FEED_MAX = (1 << FEED_W) - 1
VALUE_MAX = (1 << (W - 1)) - 1               # event values are signed W bits
FEED_TOLERANCE = 1e-4                        # 0.01 %: the feed word's quantisation warning
PWM_FULL = 65535                             # spindle duty of S = max_s
EXACT_COUNT_MAX = 256                        # helix step counts up to this come from the arc model
CHORD_SAGITTA = 0.25                         # chords stay within this many steps of the true arc
PLANE_CODE = {"XY": 0, "ZX": 1, "YZ": 2}     # cmd_plane
WARNINGS_PER_KIND = 20                       # then one "... and N more" line per kind

# Event codes on event_code (one table; docs/gcode-cli.md lists it).  The value on
# event_value is the programmed value as an integer, except for the spindle's S
# (spindle_cw, spindle_ccw, spindle_speed): a PWM duty 0 .. 65535 = S / max_s.
EVENT_CODES = {"spindle_cw": 1, "spindle_ccw": 2, "spindle_off": 3, "spindle_speed": 4, "mist_on": 5,
               "flood_on": 6, "coolant_off": 7, "output_on": 8, "output_off": 9, "pause": 10,
               "tool_change": 11, "program_end": 12}
EVENT_NAMES = {code: name for name, code in EVENT_CODES.items()}
SPINDLE_DUTY = ("spindle_cw", "spindle_ccw", "spindle_speed")
assert set(EVENT_CODES) == set(EVENTS)


class CompileError(UsageError):
    """A move the machine cannot make; the message starts with "line L: "."""


@dataclass
class Cmd(Command):
    """A motion_top command with the arc plane (cmd_plane) of the W = 32 build."""

    plane: int = 0

    def fields(self) -> tuple[int, ...]:
        """The command file's 10 integers: kind plane feed x y z i j k l (x of a DWELL as
        signed W bits, the port's bit pattern)."""
        x = self.x - (1 << W) if self.kind == DWELL and self.x > LINE_MAX else self.x
        return (self.kind, self.plane, self.feed, x, self.y, self.z, self.i, self.j, self.k, self.l)


@dataclass
class Compiled:
    commands: list[Cmd] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    end_steps: tuple[int, int, int] = (0, 0, 0)
    machine_time_s: float = 0.0
    moves: int = 0              # lines and arcs of the program
    arcs: int = 0
    chords: int = 0             # arcs run as chords
    corrected: int = 0          # arcs whose end needed the short line
    events: list[tuple[str, float, int]] = field(default_factory=list)   # (name, value, line), in order
    command_time: list[float] = field(default_factory=list)             # machine seconds at each command's end


def write_commands(path, commands: list[Cmd]) -> None:
    """The native harness's command file: one command per line, 10 decimal integers."""
    with open(path, "w") as f:
        f.write("".join(" ".join(map(str, c.fields())) + "\n" for c in commands))


def _round(value: float) -> int:
    return math.floor(value + 0.5)


# What the speed block charges for a step on 1, 2, 3 axes, in axial steps (rtl/feed_rate.v's
# costs, rounded as the RTL rounds them): the interval after the step is cost / feed.
COSTS = {n: FeedRate(FRAC).costs[n] / (1 << FRAC) for n in (1, 2, 3)}
EXACT_COST_MAX = 4096           # moves up to this many steps are costed step by step (the models)


def line_cost(d) -> float:
    """Sum of the speed block's charges over the steps of a LINE command."""
    big, m1, m2 = sorted(map(abs, d), reverse=True)
    if big == 0:
        return 0.0
    if big <= EXACT_COST_MAX:
        return sum(COSTS[sum(map(abs, s))] for s in line_steps(*d))
    both = m1 * m2 / big                        # steps on all three axes, on average
    return (big - m1 - m2 + both) + (m1 + m2 - 2 * both) * COSTS[2] + both * COSTS[3]


def arc_cost(cmd: Cmd) -> float:
    """Sum of the speed block's charges over the steps of an ARC command (with its helix)."""
    ci, cj, x, y, dw = cmd.i, cmd.j, cmd.x, cmd.y, abs(cmd.z)
    full = (x, y) == (0, 0)
    a_start, a_end = math.atan2(-cj, -ci), math.atan2(y - cj, x - ci)
    ccw = cmd.kind == ARC_CCW
    part = 2 * math.pi if full else _angle(a_end - a_start) if ccw else _angle(a_start - a_end)
    n, diagonal = arc_counts(math.hypot(ci, cj), a_start, part if ccw else -part)
    if n <= EXACT_COST_MAX:
        from ..models.arc import arc_steps
        from ..models.su1571551 import steps as su_steps

        path = arc_steps(ci, cj, 0, 0, x, y, ccw, full)
        helix = [s.dy != 0 for s in su_steps(max(cmd.k, 0), dw)] if dw else []
        axes = [abs(s.dx) + abs(s.dy) + (k < len(helix) and helix[k]) for k, s in enumerate(path)]
        rest = dw - sum(helix[:len(path)]) if dw else 0
        return sum(COSTS[a] for a in axes if a) + rest
    f = min(1.0, dw / n)
    axial = n - diagonal
    return (axial * ((1 - f) + f * COSTS[2]) + diagonal * ((1 - f) * COSTS[2] + f * COSTS[3])
            + max(0, dw - n))


def arc_counts(r: float, a0: float, sweep: float) -> tuple[int, int]:
    """(steps, diagonal steps) of an arc of radius r (steps) from angle a0 through `sweep`:
    in each octant the major axis moves by one every step, the minor one on the diagonal ones."""
    major = minor = 0.0
    a, end, q = a0, a0 + sweep, math.pi / 4
    up = sweep > 0
    while (a < end) if up else (a > end):
        nxt = (math.floor(a / q + 1e-12) + 1) * q if up else (math.ceil(a / q - 1e-12) - 1) * q
        nxt = min(nxt, end) if up else max(nxt, end)
        du, dv = abs(math.cos(nxt) - math.cos(a)) * r, abs(math.sin(nxt) - math.sin(a)) * r
        major, minor = major + max(du, dv), minor + min(du, dv)
        a = nxt
    return max(1, _round(major)), _round(minor)


def _angle(a: float) -> float:
    return a % (2 * math.pi)


def steps_estimate(r: float, a0: float, sweep: float) -> int:
    """Steps of an arc of radius r (steps) from angle a0 through `sweep` (signed, rad)."""
    return arc_counts(r, a0, sweep)[0] if sweep else 1


class Compiler:
    def __init__(self, machine: Machine, pause_seconds: float = 0.0):
        self.machine = machine
        self.spm = machine.steps_per_mm
        self.axes = machine.axes
        self.clock = machine.clock_hz
        self.pause_cycles = _round(pause_seconds * self.clock)
        self.here = [0, 0, 0]
        self.out = Compiled()
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

    def steps(self, point) -> list[int]:
        return [_round(p * s) for p, s in zip(point, self.spm)]

    def check_travel(self, line: int, axis: int, value: float) -> None:
        a = self.axes[axis]
        if not a.min_mm - 1e-6 <= value <= a.max_mm + 1e-6:
            name = AXES[axis].upper()
            raise CompileError(f"line {line}: {name} {value:.6g} mm is beyond the {name} travel "
                               f"{a.min_mm:g} .. {a.max_mm:g} mm (machine file)")

    def emit(self, cmd: Cmd, seconds: float = 0.0) -> None:
        if cmd.kind in (LINE, ARC_CW, ARC_CCW) and seconds > 0:
            # the speed block charges sqrt(2) / sqrt(3) for a step on 2 / 3 axes: the word that
            # makes this command last `seconds`, so the path speed is the programmed feed
            cost = line_cost((cmd.x, cmd.y, cmd.z)) if cmd.kind == LINE else arc_cost(cmd)
            cmd.feed = self.word(cost * (1 << FRAC) / (seconds * self.clock), cmd.source)
        self.out.commands.append(cmd)
        self.out.machine_time_s += seconds
        self.out.command_time.append(self.out.machine_time_s)

    def feed_cap(self, delta_mm) -> float:
        """The highest path speed (mm/min) along delta_mm at which no axis exceeds its max rate."""
        length = math.sqrt(sum(d * d for d in delta_mm))
        caps = [a.max_rate_mm_min * length / abs(d) for a, d in zip(self.axes, delta_mm) if d]
        return min(caps) if caps else min(a.max_rate_mm_min for a in self.axes)

    def feed_word(self, feed: float | None, cap: float, spm: float, line: int) -> tuple[int, float]:
        """(word, feed used in mm/min) for a move whose path has `spm` steps per mm."""
        if feed is None:
            f = cap
        elif feed > cap * (1 + 1e-9):
            self.warn("feed_cap", line, f"F{feed:g} mm/min is above the axes' max rate along this move; "
                      f"it runs at {cap:.6g} mm/min")
            f = cap
        else:
            f = feed
        exact = f * spm / 60 / self.clock * (1 << FRAC)
        if _round(exact) <= 0:
            slowest = 0.5 / (1 << FRAC) * self.clock * 60 / spm
            raise CompileError(f"line {line}: feed F{f:g} mm/min is too slow for the controller: its feed "
                               f"word rounds to 0 (slowest {slowest:.3g} mm/min at {self.clock:g} Hz)")
        return self.word(exact, line), f

    def word(self, exact: float, line: int) -> int:
        """The feed word nearest `exact`, with a warning where it is off by more than 0.01 %."""
        word = max(1, min(_round(exact), FEED_MAX))
        if abs(word - exact) > FEED_TOLERANCE * exact:
            self.warn("feed_quantum", line, f"the feed word {word} is off by {abs(word - exact) / exact:.3%} "
                      f"from the programmed speed; a faster feed or clock is more precise")
        return word

    # ---------------- lines ----------------
    def line_to(self, target: list[int], word: int, line: int, seconds: float) -> None:
        """LINE commands from here to target (steps), split into pieces below 2^31 steps."""
        delta = [t - h for t, h in zip(target, self.here)]
        big = max(abs(d) for d in delta)
        if big == 0:
            return
        pieces = -(-big // LINE_MAX)
        done = [0, 0, 0]
        for p in range(1, pieces + 1):
            part = [(2 * d * p + pieces) // (2 * pieces) for d in delta]         # round(d * p / pieces)
            step = [a - b for a, b in zip(part, done)]
            self.emit(Cmd(LINE, word, *step, source=line), seconds / pieces)
            done = part
        self.here = list(target)

    def segment(self, start, end, feed, line: int) -> None:
        """A straight move between two points in mm (a G0/G1 line or a chord)."""
        for k in range(3):
            self.check_travel(line, k, end[k])
        target = self.steps(end)
        if target == self.here:
            return
        delta = [e - s for e, s in zip(end, start)]
        length = math.sqrt(sum(d * d for d in delta))
        if length == 0:             # the rounded start differs from here: a repositioning
            delta = [(t - h) / s for t, h, s in zip(target, self.here, self.spm)]
            length = math.sqrt(sum(d * d for d in delta))
        spm = math.sqrt(sum((d * s) ** 2 for d, s in zip(delta, self.spm))) / length
        word, f = self.feed_word(feed, self.feed_cap(delta), spm, line)
        self.line_to(target, word, line, length / f * 60)

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
        if (r * s_u + 2) >= ARC_LIMIT:
            return self.chords(m, r, a0, turn * sweep, f"its radius is beyond the arc core's limit "
                               f"({ARC_LIMIT} steps)")
        spm = math.hypot(plane_len * s_u, dw * s_w) / length
        caps = [min(self.axes[iu].max_rate_mm_min, self.axes[iv].max_rate_mm_min) * length / plane_len
                if plane_len else math.inf]
        if dw:
            caps.append(self.axes[iw].max_rate_mm_min * length / abs(dw))
        word, f = self.feed_word(m.feed, min(caps), spm, m.line)
        seconds = length / f * 60

        start = list(self.here)
        su_s, sv_s = start[iu], start[iv]
        ci, cj = _round(-su * s_u), _round(-sv * s_v)          # centre relative to the rounded start
        r2 = ci * ci + cj * cj
        end = self.steps(m.end)
        if r2 == 0:                                             # radius under half a step: a line
            return self.line_to(end, word, m.line, seconds)
        cu, cv = su_s + ci, sv_s + cj                           # the centre in steps
        w0 = start[iw]
        kind = ARC_CCW if m.ccw else ARC_CW
        plane = PLANE_CODE[m.plane]
        rs = math.sqrt(r2)
        a_start = math.atan2(-cj, -ci)
        w_prev = w0
        for k in range(1, turns):                               # full circles first
            w_k = _round((m.start[iw] + dw * (2 * math.pi * k / sweep)) * s_w)
            count = self.count(ci, cj, 0, 0, m.ccw, 2 * math.pi * rs, w_k != w_prev, a_start, turn * 2 * math.pi)
            self.emit(Cmd(kind, word, 0, 0, w_k - w_prev, ci, cj, count, source=m.line, plane=plane),
                      seconds * 2 * math.pi / sweep)
            w_prev = w_k
        last_seconds = seconds * part / sweep
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
                return self.line_to(end, word, m.line, last_seconds)
            return self.chords(m, r, a0 + turn * 2 * math.pi * (turns - 1), turn * part, None,
                               start_w=m.start[iw] + dw * (sweep - part) / sweep)
        count = self.count(ci, cj, pu + ci, pv + cj, m.ccw, rs * cmd_part, end[iw] != w_prev,
                           a_start, turn * cmd_part)
        self.emit(Cmd(kind, word, pu + ci, pv + cj, end[iw] - w_prev, ci, cj, count, source=m.line,
                      plane=plane), last_seconds)
        here = [0, 0, 0]
        here[iu], here[iv], here[iw] = cu + pu, cv + pv, end[iw]
        self.here = here
        self.line_to(end, word, m.line, 0.0)                    # the correction, if any

    def count(self, ci, cj, x, y, ccw, length, helix, a_start, signed_sweep) -> int:
        """The arc's step count for cmd_k (start 0, centre (ci, cj), end (x, y) relative)."""
        estimate = steps_estimate(math.hypot(ci, cj), a_start, signed_sweep)
        if helix and estimate <= EXACT_COUNT_MAX:
            from ..models.arc import arc_steps

            return max(1, len(arc_steps(ci, cj, 0, 0, x, y, ccw, (x, y) == (0, 0))))
        return estimate

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
                self.check_travel(m.line, axis, round(value, 9))

    def chords(self, m: Arc, r: float, a0: float, signed_sweep: float, reason: str | None,
               start_w: float | None = None) -> None:
        """The arc as lines within CHORD_SAGITTA steps of it."""
        iu, iv, iw = PLANES[m.plane]
        big = r * max(self.spm[iu], self.spm[iv])
        step = 2 * math.acos(1 - CHORD_SAGITTA / big) if big > CHORD_SAGITTA else math.pi / 2
        n = max(1, math.ceil(abs(signed_sweep) / step - 1e-9))
        w0 = m.start[iw] if start_w is None else start_w
        dw = m.end[iw] - w0
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
        if not m.seconds >= 0 or not math.isfinite(m.seconds):
            raise CompileError(f"line {m.line}: dwell of {m.seconds:g} s")
        self.pause(_round(m.seconds * self.clock), m.line, always=True)

    def pause(self, cycles: int, line: int, always: bool = False) -> None:
        if cycles == 0 and always:
            self.emit(Cmd(DWELL, 0, 0, source=line))
        while cycles > 0:
            part = min(cycles, DWELL_MAX)
            self.emit(Cmd(DWELL, 0, part, source=line), part / self.clock)
            cycles -= part

    def event(self, m: Event) -> None:
        if m.name not in EVENT_CODES:
            raise CompileError(f"line {m.line}: unknown event {m.name!r}")
        if m.name in SPINDLE_DUTY:
            s = max(m.value, 0.0)
            if s > self.machine.max_s:
                self.warn("spindle", m.line, f"S{m.value:g} is above the spindle's max_s "
                          f"{self.machine.max_s:g}; it runs at full duty")
                s = self.machine.max_s
            value = _round(s / self.machine.max_s * PWM_FULL)
        else:
            if not math.isfinite(m.value) or abs(m.value) > VALUE_MAX:
                raise CompileError(f"line {m.line}: {m.name} value {m.value:g} does not fit the event "
                                   f"value (32 bits)")
            value = _round(m.value)
        self.emit(Cmd(EVENT, 0, EVENT_CODES[m.name], value, source=m.line))
        self.out.events.append((m.name, m.value, m.line))
        if m.name == "pause":
            self.pause(self.pause_cycles, m.line)

    def run(self, program: Program) -> Compiled:
        for m in program.moves:
            if isinstance(m, Line):
                self.out.moves += 1
                self.segment(m.start, m.end, m.feed, m.line)
            elif isinstance(m, Arc):
                self.out.moves += 1
                self.out.arcs += 1
                self.arc(m)
            elif isinstance(m, Dwell):
                self.dwell(m)
            elif isinstance(m, Event):
                self.event(m)
            else:
                raise TypeError(f"not a move: {m!r}")
        self.out.end_steps = tuple(self.here)
        for kind, seen in self._warnings.items():
            self.out.warnings += seen
            if self._more.get(kind):
                self.out.warnings.append(f"{self._more[kind]} more warnings like the line above")
        return self.out


def compile_program(program: Program, machine: Machine, pause_seconds: float = 0.0) -> Compiled:
    """The program's motion_top commands, end point, time estimate and warnings."""
    return Compiler(machine, pause_seconds).run(program)
