# SPDX-License-Identifier: Apache-2.0
"""The motion monitor: speeds, accelerations, jerk and holds measured from a run's steps CSV.

    report = monitor(rows, compiled, machine, controls=[(cycle, "hold" | "resume" | "override", value)])
    print(verdict(report)); print_table(report)

`rows` are the steps CSV's (cycle, dx, dy, dz), one row per step event; `compiled` the
interp.gcode.compile.Compiled the run came from (its commands' exact event counts N tell
which events belong to which command, their profile fields the limits the hardware was
given: cruise cmd_feed, ceiling cmd_limit, acceleration cmd_rate, and the settings).

Method.  Each event carries its command's path distance per event (cmd_cost, or the
lecture's cost of a 1/2/3-axis step when cmd_cost = 0), in steps.  The cumulative distance
X(t) is known at every event's cycle; it is interpolated linearly onto a grid of T clocks
and differenced: v = dX / T over each grid interval, a = dv / T, j = da / T.  Per axis the
same with the axis's step count.  A moving average never raises a speed or acceleration
bound, so the grid measures what the pacer did, up to the quantisation:

  * an event leaves at most q = 1 + pulse + setup + hold clocks after its distance is
    covered (the pacer's clock, the output stage), so X at a grid point is known within
    dX = c + v_max q steps (c the largest distance of one event);
  * speed within dv = 2 dX / T; acceleration within da = 2 dv / T + A / T (A the speed
    quantum: the virtual speed moves in steps of A); jerk within 2 da / T.

T is chosen so that da is a quarter of the smallest acceleration (T >= 64 clocks).

Checks (each a row of the table):
  * events: the CSV holds exactly the sum of N step events;
  * speed: v <= min(cmd_feed x override / 100, cmd_limit) + dv, with the override largest
    over the last ramp time (an override lowers the speed at the segment's acceleration),
    and the commands of the neighbouring intervals;
  * axis speed: each axis within its max_rate_mm_min + dv;
  * acceleration: |a| <= the segment's cmd_rate acceleration + da;
  * jerk (S-curve): |j| <= jerk_mm_s3 + dj (dj is reported: with short grids it is loose);
  * hold: the distance after a hold <= u^2 / 2a + u (W / 2 + 16 + A / a) + one event + dX,
    u = v + a W / 2 the virtual speed at most (v the speed at the hold: the largest mean over
    8 consecutive events near it, their time less 2q, plus the acceleration times the run's
    length; a the acceleration, W the S-curve's window);
  * resume: 90 % of that speed (at most the cap) is reached again within v / a + W + 2 T + 16
    clocks, where the command has room for it, the override does not change and no hold comes
    meanwhile (else the row says "not checked").
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..gcode.compile import FRAC, PF
from ..models.speed_ramp import BLOCK_SHIFT_MIN

TOLERANCE = 0.25        # the acceleration quantisation as a share of the smallest acceleration
MIN_GRID = 64           # clocks
HOLD_LATENCY = 16       # clocks from the hold input to the speed generator (pipeline, generous)
MAX_VIOLATIONS = 20


@dataclass
class Report:
    ok: bool = True
    events: int = 0
    expected_events: int = 0
    grid: int = 0                                        # T, clocks
    quantisation: dict = field(default_factory=dict)     # dX steps, dv, da, dj (steps / clock^n)
    checks: list = field(default_factory=list)           # (name, measured, limit, unit, verdict)
    violations: list = field(default_factory=list)       # one line each
    series: dict = field(default_factory=dict)           # for plots: t (s), path mm/s, axes mm/s

    def as_dict(self) -> dict:
        return {"ok": self.ok, "events": self.events, "expected_events": self.expected_events,
                "grid_clocks": self.grid, "quantisation": self.quantisation,
                "checks": [list(c) for c in self.checks], "violations": list(self.violations)}


def _costs(frac: int) -> dict[int, float]:
    from ..models.motion import interval_costs

    table = interval_costs(frac)
    return {n: table[n] / (1 << frac) for n in (1, 2, 3)}


def read_rows(path) -> np.ndarray:
    """The steps CSV as an (n, 4) integer array."""
    import warnings

    with warnings.catch_warnings():         # an empty run: no rows is an answer, not a warning
        warnings.filterwarnings("ignore", message=".*input contained no data.*", category=UserWarning)
        data = np.loadtxt(path, delimiter=",", skiprows=1, dtype=np.int64, ndmin=2)
    return data.reshape(-1, 4)


def _override_schedule(controls, initial: int):
    """[(cycle, percent)] of the override, from `initial` (the settings') at cycle 0."""
    out = [(0, initial)]
    for cycle, kind, value in controls:
        if kind == "override":
            out.append((int(cycle), max(1, min(200, int(value)))))
    return out


def monitor(rows, compiled, machine, *, controls=(), timing: dict | None = None) -> Report:
    """Measure a run (module docstring) and check it against the commands' limits."""
    rows = np.asarray(rows, dtype=np.int64).reshape(-1, 4)
    report = Report()
    moves = [c for c in compiled.commands if c.motion is not None]
    counts = np.array([c.motion.events for c in moves], dtype=np.int64)
    report.events, report.expected_events = len(rows), int(counts.sum())
    if report.events != report.expected_events:
        report.violations.append(f"the run has {report.events} step events, the program {report.expected_events}")
    settings = compiled.settings or {"speed_quantum": 1, "block_shift": BLOCK_SHIFT_MIN, "jerk_shift": 0}
    clock = machine.clock_hz
    timing = timing or machine.timing()
    q = 1 + timing["pulse_width"] + timing["setup"] + timing["hold"]
    n = min(len(rows), report.expected_events)
    if n < 2:
        report.checks.append(("events", report.events, report.expected_events, "", _ok(not report.violations)))
        report.ok = not report.violations
        return report
    rows = rows[:n]
    owner = np.repeat(np.arange(len(moves)), counts)[:n]
    t = rows[:, 0].astype(float)
    axes = np.abs(rows[:, 1:4]).sum(axis=1)
    lecture = _costs(FRAC)
    cost_cmd = np.array([c.cost / (1 << FRAC) for c in moves])
    cost = cost_cmd[owner]
    lect = cost == 0
    if lect.any():
        cost = cost.copy()
        cost[lect] = np.vectorize(lambda k: lecture.get(int(k), 0.0))(axes[lect])
    x = np.cumsum(cost)

    quantum = settings["speed_quantum"] / (1 << FRAC)
    bs, js = settings["block_shift"], settings["jerk_shift"]
    scurve = compiled.profile == "scurve"       # (the trapezoid has blocks too: bs alone says nothing)
    window = 1 << (bs + js) if scurve else 0
    feed = np.array([c.feed for c in moves]) / (1 << FRAC)                     # steps / clock
    limit = np.array([c.limit for c in moves]) / (1 << FRAC)
    accel = np.array([c.rate / (1 << PF) * settings["speed_quantum"] / (1 << bs) for c in moves]) / (1 << FRAC)
    spm = np.array([c.motion.spm for c in moves])

    c_max = float(cost.max())
    v_max = float(limit.max())
    a_min = float(accel.min())
    dx = c_max + v_max * q
    grid = max(MIN_GRID, math.ceil(math.sqrt(4 * dx / (TOLERANCE * a_min))), math.ceil(4 * quantum / (TOLERANCE * a_min)))
    dv = 2 * dx / grid
    da = 2 * dv / grid + quantum / grid
    dj = 2 * da / grid
    report.grid = grid
    report.quantisation = {"distance_steps": dx, "speed_steps_per_clock": dv, "accel_steps_per_clock2": da,
                           "jerk_steps_per_clock3": dj, "event_delay_clocks": q}

    start, end = t[0] - 1, t[-1]
    g = np.arange(start, end + grid, grid)
    xg = np.interp(g, np.concatenate(([start], t)), np.concatenate(([0.0], x)))
    v = np.diff(xg) / grid
    acc = np.diff(v) / grid
    # the commands over each interval and its neighbours
    lo = np.clip(np.searchsorted(t, g[:-1] - grid, side="left"), 0, n - 1)
    hi = np.clip(np.searchsorted(t, g[1:] + grid, side="right") - 1, 0, n - 1)
    c_lo, c_hi = owner[lo], owner[hi]
    overrides = _override_schedule(controls, settings.get("override", 100))
    ramp = float(np.max(limit / accel)) + window + grid
    ov_times = np.array([c for c, _ in overrides], dtype=float)
    ov_values = np.array([p for _, p in overrides], dtype=float)

    def override_max(a: float, b: float) -> float:
        k0 = max(0, np.searchsorted(ov_times, a, side="right") - 1)
        k1 = max(0, np.searchsorted(ov_times, b, side="right") - 1)
        return float(ov_values[k0:k1 + 1].max())

    feed_max = _range_max(feed, c_lo, c_hi)
    limit_max = _range_max(limit, c_lo, c_hi)
    accel_max = _range_max(accel, c_lo, c_hi)
    caps = np.array([min(f * override_max(a - ramp, b) / 100, lm)
                     for f, lm, a, b in zip(feed_max, limit_max, g[:-1], g[1:])])
    over = v - (caps + dv)
    _record(report, "path speed", v, caps, over, g, clock, "steps/clock")
    a_cap = np.maximum(accel_max[:-1], accel_max[1:])
    _record(report, "acceleration", np.abs(acc), a_cap, np.abs(acc) - (a_cap + da), g[1:], clock, "steps/clock^2")
    if scurve:
        jerk = np.diff(acc) / grid
        j_cap = machine.values["motion"]["jerk_mm_s3"] * spm[c_hi[1:-1]] / clock ** 3
        _record(report, "jerk", np.abs(jerk), j_cap, np.abs(jerk) - (j_cap + dj), g[2:], clock, "steps/clock^3")
    # per axis
    axis_speed = []
    junctions = _junction_caps(moves, machine)
    jumps = _junction_jumps(moves, [a.steps_per_mm for a in machine.axes], quantum, junctions)
    for k, a in enumerate(machine.axes):
        xa = np.cumsum(np.abs(rows[:, 1 + k]).astype(float))
        xag = np.interp(g, np.concatenate(([start], t)), np.concatenate(([0.0], xa)))
        va = np.diff(xag) / grid
        cap_a = a.max_rate_mm_min / 60 * a.steps_per_mm / clock
        dva = 2 * (1 + cap_a * q) / grid
        _record(report, f"{'xyz'[k]} speed", va, np.full_like(va, cap_a), va - (cap_a + dva), g, clock,
                "steps/clock")
        axis_speed.append(va * clock / a.steps_per_mm)
        # axis acceleration: the axis's accel_mm_s2, + at a junction the planned corner's jump of
        # this axis's velocity (a corner turns the velocity at once) spread over the grid
        acc_a = np.diff(va) / grid
        a_axis = a.accel_mm_s2 * a.steps_per_mm / clock ** 2
        jump = np.zeros(len(acc_a))
        for j in range(len(acc_a)):
            first, last = int(c_lo[j]), int(c_hi[j + 1])
            if last > first:
                jump[j] = jumps[first:last, k].max() / grid
        cap_acc = a_axis + jump
        da_a = 2 * dva / grid + quantum / grid
        _record(report, f"{'xyz'[k]} acceleration", np.abs(acc_a), cap_acc, np.abs(acc_a) - (cap_acc + da_a),
                g[1:], clock, "steps/clock^2")
    _exits(report, moves, t, x, owner, counts, accel, quantum, window, q, clock, junctions)
    _holds(report, controls, t, x, g, v, feed, limit, accel, owner, counts, dx, dv, grid, window, c_max, q, overrides,
           quantum)
    report.checks.insert(0, ("events", report.events, report.expected_events, "", _ok(report.events ==
                                                                                      report.expected_events)))
    mid = (g[:-1] + g[1:]) / 2
    # the cap actually in force: the cruise x the override at that moment (a step at each
    # override change), at most the ceiling
    ov_now = ov_values[np.maximum(np.searchsorted(ov_times, mid, side="right") - 1, 0)]
    cap_now = np.minimum(feed_max * ov_now / 100, limit_max)
    report.series = {"t": mid / clock, "path": v * clock / spm[c_lo], "axes": axis_speed,
                     "cruise": feed_max * clock / spm[c_lo], "limit": limit_max * clock / spm[c_lo],
                     "cap": cap_now * clock / spm[c_lo],
                     "controls": [(float(c) / clock, kind, value) for c, kind, value in controls],
                     "jerk_mm_s3": machine.values["motion"]["jerk_mm_s3"] if scurve else None,
                     "window_s": window / clock,
                     "axis_max": [a.max_rate_mm_min / 60 for a in machine.axes],
                     "accel": accel_max * clock * clock / spm[c_lo]}
    report.ok = not report.violations
    return report


def _junction_jumps(moves, steps_per_mm, quantum: float, junctions: list[float]) -> np.ndarray:
    """(len(moves), 3): per junction k (between moves k and k + 1) the jump of each axis's
    velocity, steps/clock, at the corner speed allowed (the junction's limit, or the exit
    field's speed if higher, + a quantum; the S-curve's filtered speed is within the limit):
    the change of the machine's velocity across it, each side at its local pace."""
    from ..gcode.compile import charged_per_mm, junction_velocities

    out = np.zeros((len(moves), 3))
    for k in range(len(moves) - 1):
        m0, m1 = moves[k].motion, moves[k + 1].motion
        charged = max(junctions[k], moves[k].exit * quantum) + quantum        # steps / clock, charged
        v_mm = charged / charged_per_mm(m0, m1)                              # planned mm / clock
        before, after = junction_velocities(m0, m1)
        for axis in range(3):
            out[k, axis] = abs(after[axis] - before[axis]) * v_mm * steps_per_mm[axis]
    return out


def _junction_caps(moves, machine) -> list[float]:
    """The junction limit (Grbl's junction deviation between the machine's velocities on
    its two sides, G64 P, exact stops; at most the two cruise words) at the end of each
    move, as the charged speed (steps/clock) of the speed word there; the last move's end
    is a stop (0)."""
    from ..gcode.compile import charged_per_mm, planner_segment
    from ..gcode.planner import _junction_limits

    rates = tuple(a.max_rate_mm_min / 60 for a in machine.axes)
    accels = tuple(a.accel_mm_s2 for a in machine.axes)
    motions = [c.motion for c in moves]
    segments = [planner_segment(m, motions[n - 1] if n else None, rates, accels) for n, m in enumerate(motions)]
    if not segments:
        return []
    caps = _junction_limits(segments, machine.values["motion"]["junction_deviation_mm"])
    clock, one = machine.clock_hz, 1 << FRAC
    return [min(caps[k + 1] * charged_per_mm(m0, m1) / clock, moves[k].feed / one,
                moves[k + 1].feed / one)
            for k, (m0, m1) in enumerate(zip(motions, motions[1:]))] + [0.0]


def _exits(report, moves, t, x, owner, counts, accel, quantum: float, window: int, q: int, clock: float,
           junctions: list[float]) -> None:
    """The speed at the end of each command is at most its planned exit (cmd_exit quanta):
    the mean speed of the last LOCAL_EVENTS events before the command's end (their distance
    over their time + 2q, a lower bound of the true mean) <= v_exit + one quantum + the
    acceleration x (the events' time + half the S-curve's window: the filtered speed at a
    junction is at most the virtual exit + a W / 2, which the planner keeps within the
    junction's limit); the program's last command
    (exit 0) must end from a decelerating profile."""
    ends = np.cumsum(counts)
    bad = []
    worst = (0.0, 0.0)
    for c, k, span, mean, a in _command_ends(ends, t, x, owner, accel, q):
        exit_speed = moves[c].exit * quantum
        bound = exit_speed + quantum + a * (span + window / 2 + 2 * q)
        if mean / max(bound, 1e-300) > worst[0] / max(worst[1], 1e-300):
            worst = (mean, bound)
        if mean > bound:
            what = "the program's end" if c == len(moves) - 1 else f"the end of command {c + 1}"
            source = getattr(moves[c], "source", None)
            line = f" (line {source})" if source else ""
            bad.append(f"speed {mean:.6g} steps/clock at {what}{line}, cycle {int(t[k])} "
                       f"({t[k] / clock:.6g} s), above its planned exit {exit_speed:.6g} + quantisation = {bound:.6g}")
    report.checks.append(("exit speeds", worst[0], worst[1], "steps/clock", _ok(not bad)))
    report.violations.extend(bad)
    # the junction limits themselves (the S-curve's FILTERED speed included): at most the
    # junction's limit + a quantum + the acceleration x the events' time
    bad, worst = [], (0.0, 0.0)
    for c, k, span, mean, a in _command_ends(ends[:-1], t, x, owner, accel, q):
        # S-curve: a junction whose limit is below a W / 2 is planned as a stop, and the
        # filtered speed there still reaches up to a W / 2 (docs/planner.md)
        bound = max(junctions[c], a * window / 2) + quantum + a * (span + 2 * q)
        if mean / max(bound, 1e-300) > worst[0] / max(worst[1], 1e-300):
            worst = (mean, bound)
        if mean > bound:
            source = getattr(moves[c], "source", None)
            line = f" (line {source})" if source else ""
            bad.append(f"speed {mean:.6g} steps/clock at the junction after command {c + 1}{line}, cycle "
                       f"{int(t[k])} ({t[k] / clock:.6g} s), above its junction limit {junctions[c]:.6g} + "
                       f"quantisation = {bound:.6g}")
    report.checks.append(("junction speeds", worst[0], worst[1], "steps/clock", _ok(not bad)))
    report.violations.extend(bad)


def _command_ends(ends, t, x, owner, accel, q: int):
    """(command, last event k, span, mean speed, largest acceleration) over the LOCAL_EVENTS
    events before each command's end: their distance over their time + 2q (a lower bound
    of the true mean), the largest acceleration allowed on them."""
    for c, end in enumerate(ends):
        k = int(end) - 1
        k0 = k - LOCAL_EVENTS
        if k0 < 0 or k >= len(t):
            continue
        span = float(t[k] - t[k0]) + 2 * q
        yield c, k, span, float(x[k] - x[k0]) / span, float(accel[owner[k0:k + 1]].max())


def _range_max(values: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """max(values[lo[k] .. hi[k]]) for every k (ranges short: the common case is lo == hi)."""
    out = np.maximum(values[lo], values[hi])
    for k in np.nonzero(hi - lo > 1)[0]:
        out[k] = values[lo[k]:hi[k] + 1].max()
    return out


def _ok(good: bool) -> str:
    return "ok" if good else "VIOLATED"


def _record(report: Report, name: str, measured, cap, excess, times, clock, unit) -> None:
    bad = np.nonzero(excess > 0)[0]
    worst = int(np.argmax(measured / np.maximum(cap, 1e-300))) if len(measured) else 0
    report.checks.append((name, float(measured[worst]) if len(measured) else 0.0,
                          float(cap[worst]) if len(measured) else 0.0, unit, _ok(len(bad) == 0)))
    for k in bad[:3]:
        report.violations.append(f"{name} {measured[k]:.6g} {unit} above {cap[k]:.6g} at cycle {int(times[k])} "
                                 f"({times[k] / clock:.6g} s)")
    if len(bad) > 3:
        report.violations.append(f"{name}: {len(bad) - 3} more intervals above the limit, the last at cycle "
                                 f"{int(times[bad[-1]])}")


LOCAL_EVENTS = 8        # events of the local speed at a hold and a resume


def _local_speeds(t, x, q: int):
    """(speed, span): an upper bound of the mean speed over each run of LOCAL_EVENTS events
    ending at event j (distance over the time less the events' timing uncertainty 2q), and
    the run's length in clocks, for j >= LOCAL_EVENTS."""
    m = LOCAL_EVENTS
    out, spans = np.zeros(len(t)), np.zeros(len(t))
    if len(t) <= m:
        return out, spans
    span = np.maximum(t[m:] - t[:-m] - 2 * q, 1.0)
    out[m:] = (x[m:] - x[:-m]) / span
    spans[m:] = span
    return out, spans


def _holds(report, controls, t, x, g, v, feed, limit, accel, owner, counts, dx, dv, grid, window, c_max, q,
           overrides, quantum) -> None:
    holds, pending = [], None
    for cycle, kind, _ in controls:
        if kind == "hold" and pending is None:
            pending = cycle
        elif kind == "resume" and pending is not None:
            holds.append((pending, cycle))
            pending = None
    if pending is not None:
        holds.append((pending, None))
    ends = np.cumsum(counts)
    local, spans = _local_speeds(t, x, q)
    for number, (h, r) in enumerate(holds, 1):
        k_h = int(np.searchsorted(t, h, side="left"))
        k_r = len(t) if r is None else int(np.searchsorted(t, r, side="left"))
        if k_h >= len(t):
            report.checks.append((f"hold {number} distance", 0.0, 0.0, "steps", "not checked (after the last step)"))
            continue
        # the speed at the hold: the largest local speed from 2 grid intervals before it to the
        # filter's window after it (the filtered speed still rises for up to a window)
        near = (t >= h - 2 * grid) & (t <= h + window + HOLD_LATENCY)
        near[:LOCAL_EVENTS] = False
        owners = owner[k_h:max(k_h + 1, k_r)]
        a = float(accel[owners].min())
        a_up = float(accel[owner[max(0, k_h - LOCAL_EVENTS):k_h + 1]].max())
        # a run's mean speed lags the speed at its end by up to a_up x its length (ramping up)
        speed = float((local[near] + a_up * spans[near]).max()) if near.any() else float(v.max())
        distance = float(x[k_r - 1] - (x[k_h - 1] if k_h else 0.0)) if k_r > k_h else 0.0
        # the virtual speed leads the filtered one by up to a W / 2 (S-curve); + the time of one
        # speed quantum at the speed (the generator's steps of A)
        virtual = speed + a * window / 2
        bound = virtual * virtual / (2 * a) + virtual * (window / 2 + HOLD_LATENCY + quantum / a) + c_max + dx
        good = distance <= bound
        report.checks.append((f"hold {number} distance", distance, bound, "steps", _ok(good)))
        if not good:
            report.violations.append(f"hold at cycle {h}: {distance:.6g} steps after it, above "
                                     f"v^2/2a + ... = {bound:.6g}")
        if r is None or k_r >= len(t):
            continue
        # the resume: back to the speed before the hold (90 %, at most the cap then) in v / a
        k_now = owner[k_r]
        percent = next(p for c, p in reversed(overrides) if c <= r)
        cap = min(feed[k_now] * percent / 100, limit[k_now])
        target = 0.9 * min(speed, cap)
        a_r = float(accel[owner[k_r]])
        allowed = target / a_r + window + 2 * grid + HOLD_LATENCY
        room = x[ends[owner[k_r]] - 1] - x[k_r]
        changes = [c for c, _ in overrides if r <= c <= r + allowed]
        later = [hh for hh, _ in holds[number:] if hh <= r + allowed]
        after = np.nonzero((t > r) & (local >= target))[0]       # (the run's mean: never early)
        after = after[after >= k_r + LOCAL_EVENTS]
        reached = float(t[after[0]] - r) if len(after) else math.inf
        if room < target * target / a_r + target * (window + grid) or changes or later:
            why = ("the override changes meanwhile" if changes else "held again meanwhile" if later
                   else "the command ends first")
            report.checks.append((f"resume {number} time", reached, allowed, "clocks", f"not checked ({why})"))
            continue
        good = reached <= allowed
        report.checks.append((f"resume {number} time", reached, allowed, "clocks", _ok(good)))
        if not good:
            report.violations.append(f"resume at cycle {r}: speed {target:.6g} reached after {reached:.6g} "
                                     f"clocks, above v/a + ... = {allowed:.6g}")


def verdict(report: Report) -> str:
    """One line: the monitor's verdict."""
    if report.ok:
        checked = sum(1 for c in report.checks if c[4] == "ok")
        if not report.grid:
            return (f"monitor: ok, {report.events} step events, {checked} checks passed "
                    "(too few steps to measure speeds)")
        return (f"monitor: ok, {report.events} step events, {checked} checks passed "
                f"(speed / acceleration over {report.grid}-clock windows)")
    return "\n".join([f"monitor: {len(report.violations)} violations:"] +
                      [f"  {violation}" for violation in report.violations])


def table(report: Report) -> str:
    """The checks as a text table."""
    lines = [f"{'check':<20} {'measured':>14} {'limit':>14}  {'unit':<14} verdict"]
    for name, measured, limit, unit, good in report.checks:
        lines.append(f"{name:<20} {measured:>14.6g} {limit:>14.6g}  {unit:<14} {good}")
    qd = report.quantisation
    if qd:
        lines.append(f"grid {report.grid} clocks; quantisation: distance {qd['distance_steps']:.3g} steps, speed "
                     f"{qd['speed_steps_per_clock']:.3g}, accel {qd['accel_steps_per_clock2']:.3g}, jerk "
                     f"{qd['jerk_steps_per_clock3']:.3g} (steps, clocks)")
    return "\n".join(lines)


# ---------------- the ideal hardware, for tests and comparisons ----------------

def event_costs(cmd_cost: int, steps) -> list[float]:
    """The path distance of each step event, steps: cmd_cost / 2^FRAC each, or with cmd_cost
    = 0 the lecture's cost of its 1-, 2- or 3-axis step (as the RTL rounds it)."""
    if cmd_cost:
        return [cmd_cost / (1 << FRAC)] * len(steps)
    lecture = _costs(FRAC)
    return [lecture[max(1, sum(map(abs, s)))] for s in steps]


def trapezoid_times(costs, entry: float, cruise: float, exit: float, accel: float):
    """(times, duration): the clock (from the command's start) at which each event, of
    `costs` steps each, is covered by the trapezoid entry -> cruise -> exit at `accel` (speeds
    in steps/clock, accel in steps/clock^2), and the trapezoid's duration."""
    ends = np.cumsum(np.asarray(costs, dtype=float))
    length = float(ends[-1]) if len(ends) else 0.0
    peak = min(cruise, math.sqrt((2 * accel * length + entry ** 2 + exit ** 2) / 2))
    up, down = (peak ** 2 - entry ** 2) / (2 * accel), (peak ** 2 - exit ** 2) / (2 * accel)
    t_up, t_flat = (peak - entry) / accel, (length - up - down) / peak
    out = []
    for x in ends:
        x = min(float(x), length)
        if x <= up:
            t = (math.sqrt(entry ** 2 + 2 * accel * x) - entry) / accel
        elif x <= length - down:
            t = t_up + (x - up) / peak
        else:
            left = max(length - x, 0.0)
            t = t_up + t_flat + (peak - math.sqrt(exit ** 2 + 2 * accel * left)) / accel
        out.append(t)
    return out, t_up + t_flat + (peak - exit) / accel


def ideal_rows(commands, settings: dict, width: int = 32) -> list[tuple[int, int, int, int]]:
    """The steps CSV rows (cycle, dx, dy, dz) of an ideal trapezoid machine running the
    commands (their profile fields and step costs): each event at the first clock at
    which the trapezoid has covered it; dwells wait their cycles."""
    from ..models.motion import ARC_CCW, ARC_CW, DWELL, LINE, command_steps

    a_q, bs = settings["speed_quantum"], settings["block_shift"]
    rows, speed, now = [], 0.0, 0.0
    for c in commands:
        if c.kind in (LINE, ARC_CW, ARC_CCW):
            steps, _ = command_steps(c, width)
            accel = c.rate / (1 << PF) * a_q / (1 << bs) / (1 << FRAC)
            exit_speed = c.exit * a_q / (1 << FRAC)
            times, duration = trapezoid_times(event_costs(c.cost, steps), speed, c.feed / (1 << FRAC),
                                              exit_speed, accel)
            rows += [(math.ceil(now + t), *s) for t, s in zip(times, steps)]
            now += duration
            speed = exit_speed
        elif c.kind == DWELL:
            now += c.x & 0xFFFFFFFF
    return rows
