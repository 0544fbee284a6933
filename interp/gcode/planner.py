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
  * a run of lines shorter in all than the junction deviation between two others
    (step-rounding corrections, micro-segments) may take the corner between the tangents
    around it, unless an axis turns back in it;
  * every segment can always stop within what follows it (backward pass:
    v_entry^2 <= v_exit^2 + 2 a L, the last segment and the segment before every stop end
    at 0) and every speed is reachable from the one before (forward pass:
    v_exit^2 <= v_entry^2 + 2 a L);
  * the time of a segment is that of the trapezoid the hardware runs on it: accelerate at
    `accel` from the entry speed towards cruise, brake at `accel` so that the exit speed is
    reached at the end (a triangle when the segment is too short to reach cruise).

Lines take Grbl's rules: cruise = min(feed, min over axes of rate_i / |u_i|) and
accel = min over axes of a_i / |u_i|.  Arcs and helices are bounded once for the whole arc,
at every tangent direction phi (in the plane (p, q)) the arc passes through: with the
helix's pitch angle alpha (sin alpha = the tangent's component along the plane's normal
axis w), the plane axes see the speed v cos(alpha), the tangential acceleration
a_t cos(alpha) along the tangent and the centripetal c = (v cos(alpha))^2 / R across it:

    v cos(alpha) |cos phi| <= rate_p,   a_t cos(alpha) |cos phi| + c |sin phi| <= a_p
    v cos(alpha) |sin phi| <= rate_q,   a_t cos(alpha) |sin phi| + c |cos phi| <= a_q
    v sin(alpha) <= rate_w,             a_t sin(alpha) <= a_w
    c <= a_n = CENTRIPETAL_SHARE * min(a_p / max |sin phi|, a_q / max |cos phi|)

for every phi of the arc, c taken at the cruise speed v_c (the highest on the arc), a_t of
either sign.  Over a whole turn: v_c^2 cos^2(alpha) / R <= CENTRIPETAL_SHARE * min(a_p, a_q)
and (a_t cos(alpha))^2 + c^2 <= min(a_p, a_q)^2.  CENTRIPETAL_SHARE reserves part of the
plane axes' acceleration for speeding up and slowing down on tight arcs.

An arc's `pacing` P (the compiler's: its stepped length over its true length, >= 1) is the
hardware's: its step events are charged the lecture's costs, so the local speed along the
true arc is the mean x P x g, g in [cos(pi / 8), 1], and it changes by up to PACING_SLOPE
x v^2 / R along the tangent.  The rules above then take the local speed P v for v, the
centripetal c = (P v cos(alpha))^2 / R, and a_t P + PACING_SLOPE c for the tangential
acceleration: the centripetal bound becomes c (|sin phi| + PACING_SLOPE |cos phi|) <= a_n's
share of a_p (and the same on q), the largest over the span (lines: P = 1, exact).
A helix's events are charged evenly (`even_costs`): its plane's local speed is the mean x
P x sec(theta) / its largest (P = that largest x N / the plane's length in steps), its
change up to EVEN_SLOPE x c, and w runs steady at v sin(alpha).
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
# benchmark 0.9 to 0.95 gave the shortest times of 0.5 .. 0.99, within 0.02 %).
CENTRIPETAL_SHARE = 0.9
# The lecture's step costs charge a step event by its steps (1, sqrt 2, sqrt 3), so along an
# arc the speed follows the stepped path: the true local speed is the mean x pacing x g, g
# = sqrt(1 + t^2) / (1 + (sqrt 2 - 1) t) in [cos(pi / 8), 1] for a tangent at atan(t) from
# its octant's axis, and |dg / dangle| <= sqrt 2 - 1: the speed changes along the tangent by
# up to that x v^2 / R, which the plane axes see with the centripetal acceleration.
PACING_SLOPE = math.sqrt(2.0) - 1.0
# Charged evenly (a helix), an arc's events take equal times and cover sec(theta) of its
# plane each, theta the tangent's angle from its octant's axis: the plane's local speed is
# the mean x pacing x g, g = sec(theta) / its largest (sqrt 2 past a diagonal), |dg / dangle| =
# sec(theta) tan(theta) / that <= tan(theta) <= 1 (w, a step on evenly spread events, is steady).
EVEN_SLOPE = 1.0
# An arc's span of tangent directions is widened by this on each side (radians), so that
# the bounds hold however its tangents were rounded.
SPAN_MARGIN = 1e-3
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
    pacing: float = 1.0                       # arcs: the local path speed's largest ratio to the mean
    even_costs: bool = False                  # helices: events charged evenly (w steady, the plane paced)
    # the machine's velocities just before and just after the junction INTO this segment per
    # unit of planned speed (its local pace at the two ends); None: the unit tangents
    junction_velocities: tuple[Vector, Vector] | None = None


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
    for axis in range(3):
        part = abs(unit[axis])
        if part > 1e-12:
            value = maxima[axis] / part
            if value < limit:
                limit = value
    return limit


def _unit(vector: Vector) -> Vector:
    x, y, z = vector
    size = math.sqrt(x * x + y * y + z * z)
    if size == 0.0:
        raise ValueError("a segment's tangent must not be the zero vector")
    return (x / size, y / size, z / size)


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


def _arc_span(segment: Segment, cos_a: float) -> tuple[float, float] | None:
    """The tangent directions an arc sweeps in its plane, as an interval of angles
    (radians, from the plane's u axis towards v), widened by SPAN_MARGIN; None when it
    covers the whole circle or its tangents, length and radius do not agree."""
    p, q = segment.plane_axes
    sweep = segment.length_mm * cos_a / segment.radius_mm
    if cos_a <= 1e-12 or sweep >= 2 * math.pi - 2 * SPAN_MARGIN:
        return None
    start = math.atan2(segment.start_unit[q], segment.start_unit[p])
    end = math.atan2(segment.end_unit[q], segment.end_unit[p])
    counter = (end - start) % (2 * math.pi)            # the sweep if counter-clockwise
    if _circular_distance(counter, sweep) <= SPAN_MARGIN:
        return start - SPAN_MARGIN, start + sweep + SPAN_MARGIN
    if _circular_distance(2 * math.pi - counter, sweep) <= SPAN_MARGIN:
        return start - sweep - SPAN_MARGIN, start + SPAN_MARGIN
    return None


def _circular_distance(x: float, y: float) -> float:
    d = (x - y) % (2 * math.pi)
    return min(d, 2 * math.pi - d)


def _contains(span: tuple[float, float] | None, angle: float) -> bool:
    """Whether the span holds angle + k pi for some whole k."""
    if span is None:
        return True
    low, high = span
    return math.ceil((low - angle) / math.pi) <= math.floor((high - angle) / math.pi)


def _largest(span, function, peak: float) -> float:
    """Largest |function| (|cos| or |sin|) over the span; it peaks at peak + k pi."""
    if _contains(span, peak):
        return 1.0
    return max(abs(function(span[0])), abs(function(span[1])))


def _largest_mix(span, first, second, slope: float) -> float:
    """Largest |first(phi)| + slope |second(phi)| over the span ((first, second) = (sin, cos)
    or (cos, sin)): sqrt(1 + slope^2) where the span reaches a peak, else at an end."""
    if slope == 0.0:
        return _largest(span, first, 0.0 if first is math.cos else math.pi / 2)
    shift = math.atan(slope)
    centre = math.pi / 2 if first is math.sin else 0.0
    if _contains(span, centre - shift) or _contains(span, centre + shift):
        return math.hypot(1.0, slope)
    return max(abs(first(a)) + slope * abs(second(a)) for a in span)


def _tangential_room(span, along_p: float, along_q: float, centripetal: float) -> float:
    """The largest in-plane tangential acceleration A1 such that at every tangent angle phi
    of the span A1 |cos phi| + c |sin phi| <= along_p and A1 |sin phi| + c |cos phi| <=
    along_q.  Each bound (A - c |sin phi|) / |cos phi| has its least values where
    |sin phi| = c / A (per quarter turn), so the least over the span lies there or at an end."""
    angles = [] if span is None else [span[0], span[1]]
    for most, critical in ((along_p, 0.0), (along_q, math.pi / 2)):
        ratio = min(1.0, centripetal / most)
        for angle in (critical + math.asin(ratio), critical - math.asin(ratio)):
            if _contains(span, angle):
                angles.append(angle)
    room = math.inf
    for angle in angles:
        c, s = abs(math.cos(angle)), abs(math.sin(angle))
        if c > 1e-12:
            room = min(room, (along_p - centripetal * s) / c)
        if s > 1e-12:
            room = min(room, (along_q - centripetal * c) / s)
    return max(0.0, room)


def largest_secant(segment: Segment) -> float:
    """The largest 1 / max(|cos phi|, |sin phi|) over an arc's tangent directions phi in its
    plane: an event that steps the major axis once covers that much of the plane (sqrt 2
    where the arc passes a diagonal)."""
    _check(segment)
    p, q = segment.plane_axes
    sin_a = min(abs(_unit(segment.start_unit)[3 - p - q]), 1.0)
    span = _arc_span(segment, math.sqrt(max(0.0, 1.0 - sin_a * sin_a)))
    if _contains(span, math.pi / 4) or _contains(span, -math.pi / 4):
        return math.sqrt(2.0)
    return max(1.0 / max(abs(math.cos(a)), abs(math.sin(a))) for a in span)


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
    span = _arc_span(segment, cos_a)
    # over the span: the plane speed's largest share on p (|cos phi|) and on q (|sin phi|);
    # the centripetal acceleration points across the tangent, so its shares are swapped
    on_p, on_q = _largest(span, math.cos, 0.0), _largest(span, math.sin, math.pi / 2)
    cruise = segment.feed_mm_s
    # the stepped pace: the local speed is up to `pacing` x the mean, and it changes along
    # the arc by up to PACING_SLOPE x (v^2 / R) (module docstring)
    pace = max(1.0, segment.pacing)
    slope = EVEN_SLOPE if segment.even_costs else PACING_SLOPE if pace > 1.0 else 0.0
    # w's pace: the plane's, or steady where the events are charged evenly
    pace_w, slope_w = (1.0, 0.0) if segment.even_costs else (pace, slope)
    if cos_a > 1e-12:
        # the centripetal c across the tangent and the pace's change slope x c along it: on p
        # c (|sin phi| + slope |cos phi|), on q c (|cos phi| + slope |sin phi|)
        across_p = _largest_mix(span, math.sin, math.cos, slope)
        across_q = _largest_mix(span, math.cos, math.sin, slope)
        centripetal_most = min(accel[p] / across_p if across_p > 1e-12 else math.inf,
                               accel[q] / across_q if across_q > 1e-12 else math.inf)
        for most, share in ((rate[p], on_p), (rate[q], on_q)):
            if share > 1e-12:
                cruise = min(cruise, most / (share * cos_a * pace))
        cruise = min(cruise, math.sqrt(CENTRIPETAL_SHARE * centripetal_most * radius) / (cos_a * pace))
        if slope_w and sin_a > 1e-12:
            # a helix's w axis sees the speed's change x sin(alpha): keep it within half of a_w
            cruise = min(cruise, math.sqrt(accel[w] * cos_a / (2 * slope_w * sin_a) * radius) / (cos_a * pace))
    if sin_a > 1e-12:
        cruise = min(cruise, rate[w] / (sin_a * pace_w))
    tangential = math.inf
    centripetal = 0.0
    if cos_a > 1e-12:
        centripetal = (cruise * pace * cos_a) ** 2 / radius
        room = _tangential_room(span, accel[p], accel[q], centripetal) - slope * centripetal
        tangential = max(0.0, room) / (cos_a * pace)
    if sin_a > 1e-12:
        w_room = accel[w] - slope_w * centripetal * sin_a / max(cos_a, 1e-12)
        tangential = min(tangential, max(0.0, w_room) / (sin_a * pace_w))
    return cruise, tangential


def junction_speed(before: Vector, after: Vector, axis_accel_mm_s2: Vector,
                   junction_deviation_mm: float) -> float:
    """Grbl's junction-deviation speed (mm/s) between the end tangent `before` of one
    segment and the start tangent `after` of the next: a circle tangent to both paths
    whose closest point lies `junction_deviation_mm` from the corner is driven at the
    acceleration the axes allow in the direction of the velocity change:

        v^2 = a_j * delta * sin(theta/2) / (1 - sin(theta/2))

    with theta the angle between the paths (cos theta = -before . after), a_j the axes'
    limit in the direction after - before.  Straight on: no limit (inf); reversal: 0.

    `before` and `after` may also be the machine's velocities at the junction per unit of
    the planned speed, of any lengths (a stepped arc's local pace).  Then neither side may
    run faster than the rule above allows for their directions, and the velocity change
    may be no larger than at the corner whose change is the same share of the larger
    velocity, |after - before| / max(|before|, |after|) = 2 cos(theta/2): the lower of the
    two speeds, each over the larger length.  For unit tangents both are the rule above."""
    lengths = math.sqrt(sum(u * u for u in before)), math.sqrt(sum(u * u for u in after))
    size = max(lengths)
    if size == 0.0:
        raise ValueError("a junction's tangents must not both be the zero vector")
    change = tuple(a - b for a, b in zip(after, before))
    # cos theta = |change|^2 / (2 size^2) - 1: -before . after for unit tangents
    speed = _corner_speed(sum(u * u for u in change) / (2.0 * size * size) - 1.0, change,
                          axis_accel_mm_s2, junction_deviation_mm)
    if min(lengths) > 0.0 and abs(lengths[0] - lengths[1]) > 1e-12 * size and speed > 0.0:
        before, after = _unit(before), _unit(after)
        directions = _corner_speed(-sum(b * a for b, a in zip(before, after)),
                                   tuple(a - b for a, b in zip(after, before)), axis_accel_mm_s2,
                                   junction_deviation_mm)
        speed = min(speed, directions)
    return speed / size


def _corner_speed(cos_theta: float, change: Vector, axis_accel_mm_s2: Vector, junction_deviation_mm: float) -> float:
    """Grbl's junction speed of a corner of cos theta whose velocity changes along `change`."""
    if cos_theta > REVERSAL_COS:
        return 0.0
    if cos_theta < STRAIGHT_COS:
        return math.inf
    accel = _limit_by_axes(axis_accel_mm_s2, _unit(change))
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


def _deviation(segment: Segment, junction_deviation_mm: float) -> float:
    """The junction deviation of the junction into `segment` (G64 P lowers it)."""
    if segment.tolerance_mm is None:
        return junction_deviation_mm
    return min(junction_deviation_mm, segment.tolerance_mm)


def _reverses(segments: list[Segment], before: int, after: int) -> bool:
    """Whether an axis moving at the end of segments[before] or at the start of
    segments[after] moves the other way in a segment between them."""
    for axis in range(3):
        ends = {math.copysign(1.0, u) for u in (segments[before].end_unit[axis],
                                                segments[after].start_unit[axis]) if abs(u) > 1e-9}
        for index in range(before + 1, after):
            for u in (segments[index].start_unit[axis], segments[index].end_unit[axis]):
                if abs(u) > 1e-9 and -math.copysign(1.0, u) in ends:
                    return True
    return False


def _velocities(segments: list[Segment], index: int) -> tuple[Vector, Vector]:
    """The machine's velocities per unit of planned speed before and after the junction
    into segments[index]: its `junction_velocities`, or the unit tangents."""
    given = segments[index].junction_velocities
    if given is not None:
        return given
    return _unit(segments[index - 1].end_unit), _unit(segments[index].start_unit)


def _junction_limits(segments: list[Segment], junction_deviation_mm: float) -> list[float]:
    """The highest entry speed of every segment from its junction alone (inf: straight on;
    0: the first segment, an exact stop).  A run of lines whose lengths add up to no more
    than the junction deviation (step-rounding corrections, CAM micro-segments) between
    two others, in which no moving axis turns back, is a single corner: its junctions may
    also take the speed of the corner between the tangent before the run and the tangent
    after it."""
    count = len(segments)
    caps = []
    for index, segment in enumerate(segments):
        if index == 0 or segment.stop_before:
            caps.append(0.0)
            continue
        speed = junction_speed(*_velocities(segments, index), segment.axis_accel_mm_s2,
                               _deviation(segment, junction_deviation_mm))
        caps.append(speed)
    first = 1
    while first < count:
        after, total, deviation = first, 0.0, math.inf
        while after < count and not segments[after].stop_before:
            deviation = min(deviation, _deviation(segments[after], junction_deviation_mm))
            if total + segments[after].length_mm > deviation or segments[after].radius_mm is not None:
                break
            total += segments[after].length_mm
            after += 1
        if after == first:
            first += 1
            continue
        if after < count and not segments[after].stop_before and total <= deviation \
                and not _reverses(segments, first - 1, after):
            # a short run first..after-1, within every deviation of its junctions, in which
            # no moving axis turns back
            speed = junction_speed(_velocities(segments, first)[0], _velocities(segments, after)[1],
                                   segments[after].axis_accel_mm_s2, deviation)
            for index in range(first, after + 1):      # (never below the junction's own)
                caps[index] = max(caps[index], speed)
        first = after + 1
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


def _window_entry(caps: list[float], reach: list[float], whole: list[float], first: int,
                  last: int) -> float:
    """The entry speed of segment `first` that can still stop at the end of `last`: the
    backward pass over first..last.  Where it meets a junction's limit it joins the
    whole-program pass (which is at least as fast and at most that limit there), so the
    rest is that pass's."""
    exit_sqr = 0.0
    for index in range(last, first - 1, -1):
        speed = math.sqrt(exit_sqr + reach[index])
        if speed >= caps[index]:
            return whole[first]
        exit_sqr = speed * speed
    return math.sqrt(exit_sqr)


def _entry_caps(junctions: list[float], cruise: list[float]) -> list[float]:
    """The highest entry speed of every segment: its junction's limit, at most the two
    cruises it joins (the first segment: 0)."""
    return [min(limit, cruise[index - 1], cruise[index]) if index else 0.0
            for index, limit in enumerate(junctions)]


def plan(segments: list[Segment], *, junction_deviation_mm: float,
         window: int | None = None, smoothing_s: float = 0.0) -> list[Plan]:
    """The plan of every segment (module docstring).  window=None plans the whole program;
    window=k fixes each segment's exit speed from the k segments that follow it, the last of
    them ending at 0, as a streaming host with a k-deep buffer would (never faster than the
    whole-program plan).  smoothing_s = W > 0 (the S-curve's moving-average window, seconds):
    every junction's speed is lowered by a W / 2 (a the larger acceleration of its two
    segments, at least 0), so that the FILTERED speed at the junction stays within the
    junction's limit (docs/planner.md)."""
    if not junction_deviation_mm >= 0.0:
        raise ValueError(f"the junction deviation must be >= 0 (got {junction_deviation_mm!r})")
    if not (math.isfinite(smoothing_s) and smoothing_s >= 0.0):
        raise ValueError(f"the smoothing window must be >= 0 seconds (got {smoothing_s!r})")
    if window is not None and (not isinstance(window, int) or window < 1):
        raise ValueError(f"the look-ahead window must be a whole number >= 1 (got {window!r})")
    count = len(segments)
    if count == 0:
        return []
    bounds = [limits(segment) for segment in segments]
    cruise = [c for c, _ in bounds]
    accel = [a for _, a in bounds]
    reach = [2.0 * a * s.length_mm for a, s in zip(accel, segments)]
    caps = _entry_caps(_junction_limits(segments, junction_deviation_mm), cruise)
    if smoothing_s > 0.0:
        # the filtered speed is the mean of the planned speed over the last W seconds; the
        # steps pass the junction at a time whose window holds the virtual passage, and the
        # planned speed moves at most a per second: the mean is at most v_j + a W / 2
        caps = [max(0.0, cap - max(accel[i - 1] if i else 0.0, accel[i]) * smoothing_s / 2.0)
                for i, cap in enumerate(caps)]
    whole = _backward(caps, reach, 0, count - 1) + [0.0]         # entry speeds, then the end
    entry = [0.0] * (count + 1)
    for index in range(count):
        exit_speed = min(whole[index + 1], math.sqrt(entry[index] ** 2 + reach[index]))
        if window is not None and index + 1 < count:
            last = min(index + window, count - 1)
            if last < count - 1:
                exit_speed = min(exit_speed, _window_entry(caps, reach, whole, index + 1, last))
        entry[index + 1] = exit_speed
    return [Plan(cruise_mm_s=cruise[i], accel_mm_s2=accel[i], entry_mm_s=entry[i],
                 exit_mm_s=entry[i + 1],
                 time_s=trapezoid_time(segments[i].length_mm, entry[i], entry[i + 1],
                                       cruise[i], accel[i]))
            for i in range(count)]


def machine_time(plans: list[Plan]) -> float:
    """Seconds of motion of a plan: the sum of its segments' trapezoid times."""
    return math.fsum(p.time_s for p in plans)
