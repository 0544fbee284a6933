# SPDX-License-Identifier: Apache-2.0
"""Grbl's planner as a reference for the machine-time benchmark.

Grbl planner.c (gnea/grbl, GPL-3.0), re-implemented: the look-ahead planner of Grbl 1.1
(plan_buffer_line, planner_recalculate with its "planned" pointer, the junction-deviation
speed, the block discard of the stepper), and the arc generator of its motion_control.c
(mc_arc: arcs as chords whose sagitta is at most arc_tolerance, points by an incremental
rotation corrected every N_ARC_CORRECTION chords).  Written from the description of their
behaviour for this benchmark; double precision where Grbl computes in float.

    result = run(program, GrblSettings.from_machine(machine))
    result.time_s                     # machine time of the program on Grbl

Streaming, as Grbl runs a program sent by a host: moves enter the ring buffer of
`buffer_size` slots (BLOCK_BUFFER_SIZE 16: at most 15 blocks, one slot stays empty) as soon
as there is room; each time a block enters, the buffer is re-planned with its newest block
ending at 0.  The block at the tail runs with the entry speed it had when it started and the
exit speed planned at that moment (the entry speed of the next block, or 0 when it is the
only block), a trapezoid at its acceleration; when it ends it leaves the buffer, which lets
the next move in.  Dwells, spindle, coolant and other M-word events wait until the buffer is
empty (Grbl's protocol_buffer_synchronize), so the motion stops before them; the time of a
dwell is added.  The machine time is the sum of the blocks' trapezoid times and the dwells.

Not modelled: Grbl's step-segment buffer and its ACCELERATION_TICKS_PER_SECOND updates (the
real stepper follows the same trapezoid to within a segment time), overrides, laser mode,
and the serial link (assumed to keep the buffer full).  Multi-turn arcs (a P word, which
Grbl refuses) are turned through the extra full turns.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..gcode.moves import PLANES, Arc, Dwell, Event, Line, Program
from ..gcode.planner import trapezoid_time

Vector = tuple[float, float, float]

# Grbl's config.h
MINIMUM_JUNCTION_SPEED = 0.0            # mm/s
MINIMUM_FEED_RATE = 1.0 / 60.0          # 1 mm/min, in mm/s
N_ARC_CORRECTION = 12
ARC_ANGULAR_TRAVEL_EPSILON = 5e-7       # radians
SOME_LARGE_VALUE = 1.0e38
BLOCK_BUFFER_SIZE = 16
DEFAULT_ARC_TOLERANCE = 0.002           # mm (Grbl's $12 default)


@dataclass(frozen=True)
class GrblSettings:
    steps_per_mm: Vector
    max_rate_mm_s: Vector                 # $110..$112, converted from mm/min
    accel_mm_s2: Vector                   # $120..$122
    junction_deviation_mm: float = 0.01   # $11
    arc_tolerance_mm: float = DEFAULT_ARC_TOLERANCE   # $12
    buffer_size: int = BLOCK_BUFFER_SIZE  # ring slots; it holds buffer_size - 1 blocks

    @classmethod
    def from_machine(cls, machine, *, arc_tolerance_mm: float = DEFAULT_ARC_TOLERANCE,
                     buffer_size: int = BLOCK_BUFFER_SIZE) -> GrblSettings:
        """The settings of an interp.gcode.machine.Machine (the same axes, the same junction
        deviation)."""
        axes = machine.axes
        return cls(steps_per_mm=tuple(a.steps_per_mm for a in axes),
                   max_rate_mm_s=tuple(a.max_rate_mm_min / 60.0 for a in axes),
                   accel_mm_s2=tuple(a.accel_mm_s2 for a in axes),
                   junction_deviation_mm=machine.values["motion"]["junction_deviation_mm"],
                   arc_tolerance_mm=arc_tolerance_mm, buffer_size=buffer_size)


def limit_by_axes(maxima: Vector, unit: Vector) -> float:
    """Grbl's limit_value_by_axis_maximum: min over moving axes of maxima_i / |unit_i|."""
    limit = SOME_LARGE_VALUE
    for most, part in zip(maxima, unit):
        if part != 0.0:
            limit = min(limit, abs(most / part))
    return limit


def lround(value: float) -> int:
    """C's lround: halves away from zero."""
    return int(math.floor(abs(value) + 0.5)) * (1 if value >= 0 else -1)


# ------------------------------------------------------------------------------ arcs (mc_arc)

def angular_travel(arc: Arc) -> float:
    """Signed angle (radians, counter-clockwise positive) an arc turns, as mc_arc measures it,
    plus the extra full turns of a P word."""
    u, v, _ = PLANES[arc.plane]
    r0 = (arc.start[u] - arc.centre[u], arc.start[v] - arc.centre[v])
    r1 = (arc.end[u] - arc.centre[u], arc.end[v] - arc.centre[v])
    travel = math.atan2(r0[0] * r1[1] - r0[1] * r1[0], r0[0] * r1[0] + r0[1] * r1[1])
    if arc.ccw:
        if travel <= ARC_ANGULAR_TRAVEL_EPSILON:
            travel += 2 * math.pi
    elif travel >= -ARC_ANGULAR_TRAVEL_EPSILON:
        travel -= 2 * math.pi
    return travel + math.copysign(2 * math.pi * (arc.turns - 1), travel)


def chord_count(radius: float, travel: float, tolerance: float) -> int:
    """mc_arc's number of chords (0 and 1 both mean: one line to the end point)."""
    return int(math.floor(abs(0.5 * travel * radius) / math.sqrt(tolerance * (2 * radius - tolerance))))


def arc_points(arc: Arc, tolerance: float = DEFAULT_ARC_TOLERANCE) -> list[Vector]:
    """The end points of the lines mc_arc sends to the planner for `arc` (the last is its end)."""
    u, v, w = PLANES[arc.plane]
    offset = (arc.centre[u] - arc.start[u], arc.centre[v] - arc.start[v])
    radius = math.hypot(*offset)
    travel = angular_travel(arc)
    segments = chord_count(radius, travel, tolerance)
    points: list[Vector] = []
    if segments:
        theta = travel / segments
        rise = (arc.end[w] - arc.start[w]) / segments
        # third-order small-angle rotation, as mc_arc
        cos_t = 2.0 - theta * theta
        sin_t = theta * 0.16666667 * (cos_t + 4.0)
        cos_t *= 0.5
        r_u, r_v = -offset[0], -offset[1]
        position = list(arc.start)
        count = 0
        for i in range(1, segments):
            if count < N_ARC_CORRECTION:
                r_u, r_v = r_u * cos_t - r_v * sin_t, r_u * sin_t + r_v * cos_t
                count += 1
            else:
                cos_i, sin_i = math.cos(i * theta), math.sin(i * theta)
                r_u = -offset[0] * cos_i + offset[1] * sin_i
                r_v = -offset[0] * sin_i - offset[1] * cos_i
                count = 0
            position[u] = arc.centre[u] + r_u
            position[v] = arc.centre[v] + r_v
            position[w] += rise
            points.append(tuple(position))
    points.append(tuple(arc.end))
    return points


# ------------------------------------------------------------------------------ the planner

@dataclass
class Block:
    millimeters: float
    unit: Vector
    acceleration: float
    nominal_speed: float
    max_junction_speed_sqr: float
    max_entry_speed_sqr: float = 0.0
    entry_speed_sqr: float = 0.0


class GrblPlanner:
    """The ring buffer: `blocks[0]` is the tail (running or next to run)."""

    def __init__(self, settings: GrblSettings):
        self.settings = settings
        self.blocks: list[Block] = []
        self.planned = 0                          # block_buffer_planned, relative to the tail
        self.position = [0, 0, 0]                 # steps
        self.previous_unit: Vector = (0.0, 0.0, 0.0)
        self.previous_nominal_speed = 0.0

    def full(self) -> bool:
        return len(self.blocks) >= self.settings.buffer_size - 1

    def buffer_line(self, target: Vector, feed_mm_s: float | None) -> bool:
        """plan_buffer_line: add a line to `target` (mm) at `feed_mm_s` (None = rapid).
        False when it moves no step (Grbl drops it)."""
        s = self.settings
        target_steps = [lround(t * n) for t, n in zip(target, s.steps_per_mm)]
        delta = [(t - p) / n for t, p, n in zip(target_steps, self.position, s.steps_per_mm)]
        if all(t == p for t, p in zip(target_steps, self.position)):
            return False
        millimeters = math.sqrt(sum(d * d for d in delta))
        unit = tuple(d / millimeters for d in delta)
        acceleration = limit_by_axes(s.accel_mm_s2, unit)
        rapid_rate = limit_by_axes(s.max_rate_mm_s, unit)
        if not self.blocks:
            max_junction_sqr = 0.0                 # from rest
        else:
            max_junction_sqr = junction_speed_sqr(self.previous_unit, unit, s.accel_mm_s2,
                                                  s.junction_deviation_mm)
        nominal = rapid_rate if feed_mm_s is None else min(feed_mm_s, rapid_rate)
        nominal = max(nominal, MINIMUM_FEED_RATE)
        block = Block(millimeters, unit, acceleration, nominal, max_junction_sqr)
        block.max_entry_speed_sqr = min(min(nominal, self.previous_nominal_speed) ** 2, max_junction_sqr)
        self.previous_nominal_speed = nominal
        self.previous_unit = unit
        self.position = target_steps
        self.blocks.append(block)
        self._recalculate()
        return True

    def _recalculate(self) -> None:
        """planner_recalculate: the reverse pass from the newest block (ending at 0) down to
        the planned pointer, then the forward pass, moving the planned pointer on."""
        blocks = self.blocks
        index = len(blocks) - 1
        if index == self.planned:
            return
        current = blocks[index]
        current.entry_speed_sqr = min(current.max_entry_speed_sqr,
                                      2 * current.acceleration * current.millimeters)
        index -= 1
        while index != self.planned:
            following, current = current, blocks[index]
            index -= 1
            if current.entry_speed_sqr != current.max_entry_speed_sqr:
                current.entry_speed_sqr = min(current.max_entry_speed_sqr,
                                              following.entry_speed_sqr
                                              + 2 * current.acceleration * current.millimeters)
        following = blocks[self.planned]
        for index in range(self.planned + 1, len(blocks)):
            current, following = following, blocks[index]
            if current.entry_speed_sqr < following.entry_speed_sqr:
                reachable = current.entry_speed_sqr + 2 * current.acceleration * current.millimeters
                if reachable < following.entry_speed_sqr:
                    following.entry_speed_sqr = reachable
                    self.planned = index
            if following.entry_speed_sqr == following.max_entry_speed_sqr:
                self.planned = index

    def exit_speed_sqr(self) -> float:
        """plan_get_exec_block_exit_speed_sqr: the tail's exit, the next block's entry."""
        return self.blocks[1].entry_speed_sqr if len(self.blocks) > 1 else 0.0

    def discard(self) -> None:
        """plan_discard_current_block: the tail has run."""
        self.blocks.pop(0)
        self.planned = max(self.planned - 1, 0)


def junction_speed_sqr(previous_unit: Vector, unit: Vector, accel: Vector, deviation: float) -> float:
    """Grbl's maximum junction speed squared between two lines' unit vectors."""
    cos_theta = -sum(p * u for p, u in zip(previous_unit, unit))
    if cos_theta > 0.999999:
        return MINIMUM_JUNCTION_SPEED ** 2
    if cos_theta < -0.999999:
        return SOME_LARGE_VALUE
    change = [u - p for u, p in zip(unit, previous_unit)]
    size = math.sqrt(sum(c * c for c in change))
    junction_accel = limit_by_axes(accel, tuple(c / size for c in change))
    sin_half = math.sqrt(0.5 * (1.0 - cos_theta))
    return max(MINIMUM_JUNCTION_SPEED ** 2, junction_accel * deviation * sin_half / (1.0 - sin_half))


# ------------------------------------------------------------------------------ a program

@dataclass
class GrblRun:
    time_s: float = 0.0           # machine time: motion and dwells
    dwell_s: float = 0.0
    blocks: int = 0               # planner blocks run (lines and chords that move a step)
    arcs: int = 0
    chords: int = 0               # lines the arcs became (before dropping empty ones)
    speeds: list[tuple[float, float, float]] = field(default_factory=list)   # (entry, exit, nominal) per block


def run(program: Program, settings: GrblSettings, *, keep_speeds: bool = False) -> GrblRun:
    """Stream `program` through the reference planner; its machine time (module docstring)."""
    result = GrblRun()
    items: list[tuple] = []                  # ("line", target, feed mm/s | None) | ("sync", s)
    for move in program.moves:
        if isinstance(move, Line):
            items.append(("line", move.end, None if move.feed is None else move.feed / 60.0))
        elif isinstance(move, Arc):
            points = arc_points(move, settings.arc_tolerance_mm)
            result.arcs += 1
            result.chords += len(points)
            items.extend(("line", p, move.feed / 60.0) for p in points)
        elif isinstance(move, Dwell):
            items.append(("sync", move.seconds))
        elif isinstance(move, Event):
            items.append(("sync", 0.0))
    planner = GrblPlanner(settings)
    speed = 0.0
    motion = 0.0
    index = 0
    while True:
        while index < len(items) and items[index][0] == "line" and not planner.full():
            planner.buffer_line(items[index][1], items[index][2])
            index += 1
        if planner.blocks:
            block = planner.blocks[0]
            entry = math.sqrt(block.entry_speed_sqr)
            exit_speed = math.sqrt(planner.exit_speed_sqr())
            assert abs(entry - speed) <= 1e-9 * max(1.0, speed), "tail entry moved while queued"
            motion += trapezoid_time(block.millimeters, entry, exit_speed, block.nominal_speed,
                                     block.acceleration)
            if keep_speeds:
                result.speeds.append((entry, exit_speed, block.nominal_speed))
            result.blocks += 1
            speed = exit_speed
            planner.discard()
            continue
        if index >= len(items):
            break
        result.dwell_s += items[index][1]               # a sync: the buffer is empty here
        speed = 0.0
        index += 1
    result.time_s = motion + result.dwell_s
    return result


def tables(quick: bool):
    """`interp bench` runs every module here: this one is the reference of machine_time.py
    and has no table of its own."""
    return []
