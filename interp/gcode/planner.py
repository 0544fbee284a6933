# SPDX-License-Identifier: Apache-2.0
"""The host's look-ahead planner: a path-speed plan for the motion commands of a program.

    plans = plan(segments, junction_deviation_mm=0.01)          # whole program
    plans = plan(segments, junction_deviation_mm=0.01, window=32)  # a 32-deep streaming host
    seconds = machine_time(plans)

One Segment is one motion COMMAND as the hardware runs it (after the compiler's rounding and
splitting): a line, or an exact arc or helix.  The planner gives each a Plan: the cruise
speed, the path acceleration, and the entry and exit speeds, so that

  * no segment is entered or left faster than the junction between it and its neighbour
    allows (Grbl's junction-deviation rule; G64 P lowers the deviation for one junction; an
    exact stop, `stop_before`, makes the junction speed 0);
  * every segment can always stop within what follows it (backward pass:
    v_entry^2 <= v_exit^2 + 2 a L, the last segment and the segment before every stop end
    at 0) and every speed is reachable from the one before (forward pass:
    v_exit^2 <= v_entry^2 + 2 a L);
  * the time of a segment is that of the trapezoid the hardware runs on it: accelerate at
    `accel` from the entry speed towards cruise, brake at `accel` so that the exit speed is
    reached at the end (a triangle when the segment is too short to reach cruise).

Lines take Grbl's rules: cruise = min(feed, min over axes of rate_i / |u_i|) and
accel = min over axes of a_i / |u_i|.  Arcs and helices are bounded for the whole arc, at
every angle of the circle (a safe bound, not the arc's own angular span): with the helix's
pitch angle alpha (sin alpha = the tangent's component along the plane's normal axis w),
the plane axes (p, q) see the speed v cos(alpha) turning round the circle and the normal
axis v sin(alpha) constantly, so

    cruise: v cos(alpha) <= min(rate_p, rate_q),  v sin(alpha) <= rate_w,
            (v cos(alpha))^2 / R <= a_n = CENTRIPETAL_SHARE * min(a_p, a_q)   (centripetal)
    accel:  (a_t cos(alpha))^2 + (v_c cos(alpha))^4 / R^2 <= min(a_p, a_q)^2,
            a_t sin(alpha) <= a_w

(a plane axis sees the tangential and the centripetal acceleration at right angles, each
at most once per turn, so the worst axis sees their Euclidean sum; the centripetal part is
taken at the cruise speed v_c, the highest speed on the arc).  CENTRIPETAL_SHARE reserves
part of the plane axes' acceleration for speeding up and slowing down on tight arcs.
docs/planner.md has the formulas, the rules and the limits.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

Vector = tuple[float, float, float]

# Grbl's thresholds for the junction angle: a cosine beyond them is a reversal (speed 0) or
# straight on (no limit from the junction).
REVERSAL_COS = 0.999999
STRAIGHT_COS = -0.999999
# The share of the plane axes' acceleration a tight arc may spend on centripetal
# acceleration at its cruise speed; the rest, sqrt(1 - share^2) of it, is left for the
# tangential acceleration (0.9 leaves 0.436; on the corpus of the machine-time
# benchmark 0.9 was the best of 0.5 .. 0.99).
CENTRIPETAL_SHARE = 0.9
# Relative tolerance of the feasibility checks (floating point).
EPSILON = 1e-9


@dataclass
class Segment:
    """One motion command as the hardware will run it (millimetres, seconds)."""
    length_mm: float                          # true path length (helix included)
    start_unit: Vector                        # unit tangent at the start (machine x, y, z)
    end_unit: Vector                          # at the end (= start for a line)
    feed_mm_s: float                          # requested speed (programmed F, or the rapid rate)
    axis_rate_mm_s: Vector                    # machine max rate per axis
    axis_accel_mm_s2: Vector                  # machine max accel per axis
    radius_mm: float | None = None            # arcs and helices: radius (in the arc plane)
    plane_axes: tuple[int, int] | None = None  # arcs: indices of the plane's (u, v) axes
    stop_before: bool = False                 # exact stop before this segment
    tolerance_mm: float | None = None         # G64 P tolerance for the junction INTO this segment


@dataclass
class Plan:
    """The planned speeds of one Segment (mm/s, mm/s^2, s)."""
    cruise_mm_s: float
    accel_mm_s2: float
    entry_mm_s: float
    exit_mm_s: float
    time_s: float


def _limit_by_axes(maxima: Vector, unit: Vector) -> float:
    """min over the axes the direction moves of maxima_i / |unit_i| (Grbl's rule)."""
    limit = math.inf
    for most, part in zip(maxima, unit):
        if abs(part) > 1e-12:
            limit = min(limit, most / abs(part))
    return limit


def _unit(vector: Vector) -> Vector:
    size = math.sqrt(sum(c * c for c in vector))
    if size == 0.0:
        raise ValueError("a segment's tangent must not be the zero vector")
    return tuple(c / size for c in vector)


def _check(segment: Segment) -> None:
    if not (segment.length_mm > 0.0 and math.isfinite(segment.length_mm)):
        raise ValueError(f"a segment's length must be positive (got {segment.length_mm!r})")
    if not segment.feed_mm_s > 0.0:
        raise ValueError(f"a segment's feed must be positive (got {segment.feed_mm_s!r})")
    if min(segment.axis_rate_mm_s) <= 0.0 or min(segment.axis_accel_mm_s2) <= 0.0:
        raise ValueError("every axis's rate and acceleration must be positive")
    if segment.radius_mm is not None:
        if not segment.radius_mm > 0.0:
            raise ValueError(f"an arc's radius must be positive (got {segment.radius_mm!r})")
        if segment.plane_axes is None or len(set(segment.plane_axes)) != 2 \
                or not set(segment.plane_axes) <= {0, 1, 2}:
            raise ValueError(f"an arc needs two different plane axes (got {segment.plane_axes!r})")


def limits(segment: Segment) -> tuple[float, float]:
    """(max cruise mm/s, path acceleration mm/s^2) of one segment (module docstring rules)."""
    _check(segment)
    rate, accel = segment.axis_rate_mm_s, segment.axis_accel_mm_s2
    if segment.radius_mm is None:
        unit = _unit(segment.start_unit)
        return min(segment.feed_mm_s, _limit_by_axes(rate, unit)), _limit_by_axes(accel, unit)
    p, q = segment.plane_axes
    w = 3 - p - q
    sin_a = min(abs(_unit(segment.start_unit)[w]), 1.0)
    cos_a = math.sqrt(max(0.0, 1.0 - sin_a * sin_a))
    radius = segment.radius_mm
    plane_accel = min(accel[p], accel[q])
    cruise = segment.feed_mm_s
    if cos_a > 1e-12:
        cruise = min(cruise, min(rate[p], rate[q]) / cos_a,
                     math.sqrt(CENTRIPETAL_SHARE * plane_accel * radius) / cos_a)
    if sin_a > 1e-12:
        cruise = min(cruise, rate[w] / sin_a)
    tangential = math.inf
    if cos_a > 1e-12:
        centripetal = (cruise * cos_a) ** 2 / radius
        tangential = math.sqrt(max(0.0, plane_accel ** 2 - centripetal ** 2)) / cos_a
    if sin_a > 1e-12:
        tangential = min(tangential, accel[w] / sin_a)
    return cruise, tangential


def junction_speed(before: Vector, after: Vector, axis_accel_mm_s2: Vector,
                   junction_deviation_mm: float) -> float:
    """Grbl's junction-deviation speed (mm/s) between the end tangent `before` of one
    segment and the start tangent `after` of the next: a circle tangent to both paths
    whose closest point lies `junction_deviation_mm` from the corner is driven at the
    acceleration the axes allow in the direction of the velocity change:

        v^2 = a_j * delta * sin(theta/2) / (1 - sin(theta/2))

    with theta the angle between the paths (cos theta = -before . after), a_j the axes'
    limit in the direction after - before.  Straight on: no limit (inf); reversal: 0."""
    before, after = _unit(before), _unit(after)
    cos_theta = -sum(b * a for b, a in zip(before, after))
    if cos_theta > REVERSAL_COS:
        return 0.0
    if cos_theta < STRAIGHT_COS:
        return math.inf
    change = _unit(tuple(a - b for a, b in zip(after, before)))
    accel = _limit_by_axes(axis_accel_mm_s2, change)
    sin_half = math.sqrt(0.5 * (1.0 - cos_theta))
    return math.sqrt(accel * junction_deviation_mm * sin_half / (1.0 - sin_half))


def trapezoid_time(length: float, entry: float, exit: float, cruise: float, accel: float) -> float:
    """Seconds to run `length` from `entry` to `exit` speed, accelerating and braking at
    `accel`, never above `cruise` (a triangle when the length is too short for cruise)."""
    if min(length, accel, cruise) <= 0.0 or min(entry, exit) < 0.0:
        raise ValueError("length, accel and cruise must be positive, speeds not negative")
    if max(entry, exit) > cruise * (1 + EPSILON) + 1e-12:
        raise ValueError(f"entry {entry} / exit {exit} above the cruise {cruise}")
    room = 2.0 * accel * length
    if abs(exit * exit - entry * entry) > room * (1 + EPSILON) + 1e-12:
        raise ValueError(f"{entry} -> {exit} mm/s is not reachable over {length} mm at {accel} mm/s^2")
    peak_sqr = (room + entry * entry + exit * exit) / 2.0
    if peak_sqr <= cruise * cruise:
        peak = max(math.sqrt(peak_sqr), entry, exit)
        return (2.0 * peak - entry - exit) / accel
    ramps = (2.0 * cruise * cruise - entry * entry - exit * exit) / (2.0 * accel)
    return (2.0 * cruise - entry - exit) / accel + (length - ramps) / cruise


def _junction_limits(segments: list[Segment], cruise: list[float],
                     junction_deviation_mm: float) -> list[float]:
    """The highest entry speed of every segment from its junction alone."""
    caps = []
    for index, segment in enumerate(segments):
        if index == 0 or segment.stop_before:
            caps.append(0.0)
            continue
        before = segments[index - 1]
        deviation = junction_deviation_mm
        if segment.tolerance_mm is not None:
            deviation = min(deviation, segment.tolerance_mm)
        speed = junction_speed(before.end_unit, segment.start_unit,
                               segment.axis_accel_mm_s2, deviation)
        caps.append(min(speed, cruise[index - 1], cruise[index]))
    return caps


def _backward(caps: list[float], reach: list[float], first: int, last: int) -> list[float]:
    """Entry speeds of segments first..last that can still stop at the end of `last`."""
    out = [0.0] * (last - first + 1)
    exit_sqr = 0.0
    for index in range(last, first - 1, -1):
        entry = min(caps[index], math.sqrt(exit_sqr + reach[index]))
        out[index - first] = entry
        exit_sqr = entry * entry
    return out


def plan(segments: list[Segment], *, junction_deviation_mm: float,
         window: int | None = None) -> list[Plan]:
    """The plan of every segment (module docstring).  window=None plans the whole program;
    window=k fixes each segment's exit speed from the k segments that follow it, the last of
    them ending at 0, as a streaming host with a k-deep buffer would (never faster than the
    whole-program plan)."""
    if not junction_deviation_mm >= 0.0:
        raise ValueError(f"the junction deviation must be >= 0 (got {junction_deviation_mm!r})")
    if window is not None and (not isinstance(window, int) or window < 1):
        raise ValueError(f"the look-ahead window must be a whole number >= 1 (got {window!r})")
    count = len(segments)
    if count == 0:
        return []
    bounds = [limits(segment) for segment in segments]
    cruise = [c for c, _ in bounds]
    accel = [a for _, a in bounds]
    reach = [2.0 * a * s.length_mm for a, s in zip(accel, segments)]
    caps = _junction_limits(segments, cruise, junction_deviation_mm)
    whole = _backward(caps, reach, 0, count - 1) + [0.0]         # entry speeds, then the end
    entry = [0.0] * (count + 1)
    for index in range(count):
        exit_speed = min(whole[index + 1], math.sqrt(entry[index] ** 2 + reach[index]))
        if window is not None and index + 1 < count:
            last = min(index + window, count - 1)
            if last < count - 1:
                exit_speed = min(exit_speed, _backward(caps, reach, index + 1, last)[0])
        entry[index + 1] = exit_speed
    return [Plan(cruise_mm_s=cruise[i], accel_mm_s2=accel[i], entry_mm_s=entry[i],
                 exit_mm_s=entry[i + 1],
                 time_s=trapezoid_time(segments[i].length_mm, entry[i], entry[i + 1],
                                       cruise[i], accel[i]))
            for i in range(count)]


def machine_time(plans: list[Plan]) -> float:
    """Seconds of motion of a plan: the sum of its segments' trapezoid times."""
    return math.fsum(p.time_s for p in plans)
