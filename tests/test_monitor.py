# SPDX-License-Identifier: Apache-2.0
"""The motion monitor (interp.simulation.monitor) on synthetic steps CSVs.

An ideal trapezoid machine (monitor.ideal_rows: every event at the first clock its
command's trapezoid covers it) must pass every check; the same run made faster, with a
speed jump, with a lost or an extra step, or a hold that does not brake must fail the
check that concerns it.
"""
import math

import numpy as np
import pytest

from interp.testing.seeds import seeded_random
from interp.gcode.compile import FRAC, PF, compile_program
from interp.gcode.machine import load_machine
from interp.gcode.moves import Arc, Dwell, Line, Program
from interp.simulation.monitor import ideal_rows, monitor, read_rows, table, verdict

MACHINE = load_machine(clock_hz=1e6)
PROGRAM = Program([Line((0, 0, 0), (20, 0, 0), 3000, 1), Line((20, 0, 0), (25, 5, 1), 2400, 2),
                   Arc((25, 5, 1), (25, 15, 1), (25, 10, 1), "XY", True, 1, 1800, 3), Dwell(0.01, 4),
                   Line((25, 15, 1), (0, 0, 0), None, 5)])


@pytest.fixture(scope="module")
def run():
    out = compile_program(PROGRAM, MACHINE)
    return out, ideal_rows(out.commands, out.settings)


def checks(report) -> dict:
    return {c[0]: c[4] for c in report.checks}


def test_ideal_machine_passes(run):
    out, rows = run
    report = monitor(rows, out, MACHINE)
    print(table(report))
    assert report.ok, report.violations
    assert report.events == report.expected_events == out.step_events
    assert set(checks(report)) >= {"events", "path speed", "acceleration", "x speed", "y speed", "z speed"}
    assert verdict(report).startswith("monitor: ok")


def test_csv_file_round_trip(run, tmp_path):
    out, rows = run
    path = tmp_path / "s.csv"
    path.write_text("cycle,dx,dy,dz\n" + "".join(",".join(map(str, r)) + "\n" for r in rows))
    assert read_rows(path).tolist() == [list(r) for r in rows]


def test_faster_run_violates_the_speed(run):
    out, rows = run
    fast = [(int(r[0] / 1.2), *r[1:]) for r in rows]             # 20 % fast everywhere
    report = monitor(fast, out, MACHINE)
    assert not report.ok and checks(report)["path speed"] == "VIOLATED"
    assert verdict(report).startswith("monitor: ") and "violations" in verdict(report)


def test_speed_jump_violates_the_acceleration(run):
    out, rows = run
    n = len(rows) // 5                      # in the first line's cruise: 100 events at twice the speed
    jump = [(r[0] - (min(k - n, 100) * 100 if k > n else 0), *r[1:]) for k, r in enumerate(rows)]
    report = monitor(jump, out, MACHINE)
    assert checks(report)["acceleration"] == "VIOLATED"


@pytest.mark.parametrize("change", ["lost", "extra"])
def test_lost_or_extra_step(run, change):
    out, rows = run
    bad = rows[:-1] if change == "lost" else rows + [rows[-1]]
    report = monitor(bad, out, MACHINE)
    assert checks(report)["events"] == "VIOLATED" and not report.ok


def test_override_raises_the_cap():
    """At 150 % the ideal machine runs 1.5 x faster (up to the ceiling): fine with the override
    given to the monitor, a violation without it."""
    out = compile_program(Program([Line((0, 0, 0), (50, 0, 0), 1200, 1)]), MACHINE)
    c = out.commands[0]
    c.feed = c.feed * 3 // 2                # what the hardware does at 150 %
    rows = ideal_rows(out.commands, out.settings)
    c.feed = c.feed * 2 // 3
    assert monitor(rows, out, MACHINE, controls=[(0, "override", 150)]).ok
    assert checks(monitor(rows, out, MACHINE))["path speed"] == "VIOLATED"


def stopped_rows(out, hold_cycle: int, decel: float):
    """The ideal run with a hold at hold_cycle that brakes at `decel` x the acceleration and
    resumes (at full speed, at once) a second later."""
    rows = ideal_rows(out.commands, out.settings)
    c = out.commands[0]
    a = c.rate / (1 << PF) * out.settings["speed_quantum"] / (1 << out.settings["block_shift"]) / (1 << FRAC) * decel
    v = c.feed / (1 << FRAC)
    cost = c.cost / (1 << FRAC)
    k0 = next(k for k, r in enumerate(rows) if r[0] >= hold_cycle)
    x = 0.0
    brake, k = [], k0
    while k < len(rows):
        x += cost
        if x >= v * v / (2 * a):
            break
        brake.append((hold_cycle + math.ceil((v - math.sqrt(max(v * v - 2 * a * x, 0))) / a), *rows[k][1:]))
        k += 1
    resume = hold_cycle + 1_000_000
    shift = resume - rows[k][0] if k < len(rows) else 0
    return rows[:k0] + brake + [(r[0] + shift, *r[1:]) for r in rows[k:]], resume


def test_hold_distance():
    out = compile_program(Program([Line((0, 0, 0), (200, 0, 0), 3000, 1)]), MACHINE)
    hold = 1_000_000                        # 1 s: at cruise
    good, resume = stopped_rows(out, hold, 1.0)
    controls = [(hold, "hold", 0), (resume, "resume", 0)]
    report = monitor(good, out, MACHINE, controls=controls)
    assert checks(report)["hold 1 distance"] == "ok", table(report)
    slow, resume = stopped_rows(out, hold, 0.5)     # brakes at half the rate: twice the distance
    report = monitor(slow, out, MACHINE, controls=[(hold, "hold", 0), (resume, "resume", 0)])
    assert checks(report)["hold 1 distance"] == "VIOLATED"


def test_random_programs_pass_on_the_ideal_machine():
    rng, seed = seeded_random()
    for _ in range(4):
        here, moves = (0.0, 0.0, 0.0), []
        for n in range(1, 6):
            end = tuple(h + rng.uniform(-5, 5) for h in here)
            moves.append(Line(here, end, rng.choice([None, 600.0, 2400.0]), n))
            here = end
        out = compile_program(Program(moves), MACHINE)
        report = monitor(ideal_rows(out.commands, out.settings), out, MACHINE)
        assert report.ok, (seed, report.violations)


def test_speed_plot(run, tmp_path):
    from interp.plots.speed import plot_speed

    out, rows = run
    png = tmp_path / "speed.png"
    plot_speed(png, monitor(rows, out, MACHINE), title="ideal machine")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def _with_exits(out, change):
    """The ideal machine's rows of the commands with some exits changed (a corner or an end taken fast)."""
    import copy

    commands = copy.deepcopy(out.commands)
    moves = [c for c in commands if c.motion is not None]
    change(moves)
    return ideal_rows(commands, out.settings)


def test_new_checks_are_in_the_table(run):
    out, rows = run
    names = set(checks(monitor(rows, out, MACHINE)))
    assert {"x acceleration", "y acceleration", "z acceleration", "exit speeds", "junction speeds"} <= names


def test_corner_faster_than_its_exit_fails(run):
    out, rows = run
    quantum = out.settings["speed_quantum"]

    def fast_corner(moves):
        moves[0].exit = moves[0].feed // quantum               # line 1 -> 2 taken at full speed

    report = monitor(_with_exits(out, fast_corner), out, MACHINE)
    assert checks(report)["exit speeds"] == "VIOLATED"
    assert any("the end of command 1" in v for v in report.violations), report.violations
    assert checks(report)["junction speeds"] == "VIOLATED"


def test_tangent_arcs_through_their_joins_at_cruise_pass():
    """Tangent arcs keep their scaled cruise word through the joins (the exit takes the
    arcs' scale): the junction check bounds the charged speed by the junction's own limit
    and the cruise words, so it passes (bounded by the true cruise, it would fail)."""
    points = [(0, 0), (-10, 10), (-20, 0), (-10, -10), (0, 0)]
    arcs = Program([Arc((*s, 0), (*e, 0), (-10, 0, 0), "XY", True, 1, 3000, n)
                    for n, (s, e) in enumerate(zip(points, points[1:]), 1)])
    out = compile_program(arcs, MACHINE)
    report = monitor(ideal_rows(out.commands, out.settings), out, MACHINE)
    assert report.ok, verdict(report)


def test_program_ending_at_speed_fails():
    end = Program([Line((0, 0, 0), (20, 0, 0), 3000, 1)])
    single = compile_program(end, MACHINE)

    def no_stop(moves):
        moves[-1].exit = moves[-1].feed // quantum

    quantum = single.settings["speed_quantum"]
    report = monitor(_with_exits(single, no_stop), single, MACHINE)
    assert checks(report)["exit speeds"] == "VIOLATED"
    assert any("the program's end" in v for v in report.violations), report.violations


def test_axis_acceleration_above_the_axis_limit_fails(run):
    out, rows = run
    slow_x = load_machine(sets=["axis.x.accel_mm_s2=50"], clock_hz=1e6)
    report = monitor(rows, out, slow_x)
    assert checks(report)["x acceleration"] == "VIOLATED" and checks(report)["y acceleration"] == "ok"


def test_every_violation_is_printed(run):
    out, rows = run
    fast = [(int(r[0] / 1.5), *r[1:]) for r in rows]
    report = monitor(fast, out, MACHINE)
    lines = verdict(report).splitlines()
    assert len(report.violations) > 1 and len(lines) == len(report.violations) + 1
    assert "more)" not in verdict(report)


def test_speed_plot_cap_in_force_and_controls(run, tmp_path, monkeypatch):
    """The cap line is the cruise x the override at that moment (a step at the change), and
    the holds, resumes and override changes are vertical lines with legend entries."""
    import matplotlib.pyplot as plt

    from interp.plots import speed

    out, rows = run
    change = rows[len(rows) // 4][0]
    controls = [(change, "override", 50), (rows[len(rows) // 2][0], "hold", 0),
                (rows[len(rows) // 2][0] + 50000, "resume", 0)]
    report = monitor(rows, out, MACHINE, controls=controls)
    s = report.series
    before, after = s["t"] < change / 1e6 - 0.05, s["t"] > change / 1e6 + 0.05
    first = s["cruise"] == s["cruise"][0]
    assert np.allclose(s["cap"][before & first], np.minimum(s["cruise"], s["limit"])[before & first])
    assert np.allclose(s["cap"][after], np.minimum(s["cruise"] / 2, s["limit"])[after])
    seen = {}
    real_close = plt.close

    def keep(fig):
        seen["labels"] = [line.get_label() for line in fig.axes[0].get_lines()]
        seen["title"] = fig.axes[0].get_title()
        real_close(fig)

    monkeypatch.setattr(speed.plt, "close", keep)
    speed.plot_speed(tmp_path / "s.png", report, title="t")
    assert {"feed hold", "resume", "override change"} <= set(seen["labels"])
    assert "jerk" not in seen["title"]
    scurve = compile_program(PROGRAM, MACHINE, profile="scurve")
    speed.plot_speed(tmp_path / "c.png", monitor(ideal_rows(scurve.commands, scurve.settings), scurve, MACHINE),
                     title="t")
    assert "jerk limit" in seen["title"]
