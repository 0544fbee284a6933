# SPDX-License-Identifier: Apache-2.0
"""`interp gcode`: options, --check --json, the summary, one-line errors with exit status 2.

The language layer and the simulator are replaced by fakes here (a hand-built
Program; a harness that adds up the commands), so these tests run without
them; the end-to-end tests at the bottom run the real ones and are skipped
where interp.gcode.interpreter or interp.simulation.native is missing.
"""
import csv
import importlib.util
import json
import math
import os
from pathlib import Path

import pytest

from interp.cli import main
from interp.commands import gcode
from interp.gcode.compile import EVENT, EVENT_CODES, FRAC, PF
from interp.gcode.moves import Arc, Dwell, Event, Line, Program
from interp.models.motion import ARC_CCW, ARC_CW, LINE

PROGRAM = Program(moves=[Line((0, 0, 0), (10, 0, 5), None, 2), Event("spindle_cw", 12000, 3),
                         Line((10, 0, 5), (10, 0, -1), 300, 4),
                         Arc((10, 0, -1), (0, 10, -1), (0, 0, -1), "XY", True, 1, 1200, 5),
                         Dwell(0.5, 6), Event("spindle_off", 0, 7), Event("program_end", 2, 8)],
                  warnings=["line 1: something the interpreter noticed"], end_work=(0.0, 10.0, -1.0),
                  units="mm", end_machine=(0.0, 10.0, -1.0))


def fake_harness(commands_path, sim, *, steps_path, timing, max_cycles, progress, vcd, settings, controls,
                 push_interval=1, shift=(0, 0, 0), errors=()):
    """An ideal motion_top: the command file's moves by the step models, each event at the time
    the command's trapezoid (its profile fields) covers it; one event per EVENT."""
    from interp.models.motion import Command, command_steps
    from interp.simulation.monitor import event_costs, trapezoid_times

    pos, events, rows = [0, 0, 0], [], []
    a_q, bs = settings["speed_quantum"], settings["block_shift"]
    speed, now = 0.0, 0.0
    with open(commands_path) as f:
        lines = [list(map(int, line.split())) for line in f]
    for n, fields in enumerate(lines, 1):
        if progress:                # command n is dispatched now
            progress(int(now), len(rows), n)
        kind, plane, feed, x, y, z, i, j, k, l, limit, exit, rate, cost, length, budget = fields
        if kind in (LINE, ARC_CW, ARC_CCW):
            steps, _ = command_steps(Command(kind, feed, x, y, z, i, j, k, l, plane=plane), 32)
            accel = rate / (1 << PF) * a_q / (1 << bs) / (1 << FRAC)
            exit_speed = exit * a_q / (1 << FRAC)
            times, duration = trapezoid_times(event_costs(cost, steps), speed, feed / (1 << FRAC), exit_speed,
                                              accel)
            rows += [(math.ceil(now + t), *s) for t, s in zip(times, steps)]
            now += duration
            speed = exit_speed
            for s in steps:
                pos = [p + d for p, d in zip(pos, s)]
        elif kind == EVENT:
            events.append([math.ceil(now), x, y])
        elif kind == 4:
            now += x & 0xFFFFFFFF
    if steps_path:
        with open(steps_path, "w", newline="") as f:
            out = csv.writer(f)
            out.writerow(["cycle", "dx", "dy", "dz"])
            out.writerows(rows)
    return {"cycles": math.ceil(now), "position": [p + s for p, s in zip(pos, shift)],
            "errors": [list(e) for e in errors], "events": events, "steps": len(rows), "hold_stops": []}


@pytest.fixture
def fakes(monkeypatch):
    monkeypatch.setattr(gcode, "interpret_program", lambda text, machine, start_steps=(0, 0, 0), saved=None, program=None,
                        start_line=None: PROGRAM)
    monkeypatch.setattr(gcode, "run_simulation", fake_harness)
    return monkeypatch


@pytest.fixture
def nc(tmp_path):
    src = tmp_path / "p.nc"
    src.write_text("G0 X10\n")
    return src


def one_line_error(capsys, code, argv, text):
    assert main(argv) == code
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and text in err[0] and "Traceback" not in err[0], err


def test_check_json_fields(fakes, nc, capsys):
    assert main(["gcode", str(nc), "--check", "--json"]) == 0
    captured = capsys.readouterr()
    info = json.loads(captured.out)
    assert info["end"] == [0, 10, -1] and info["end_steps"] == [0, 1000, -100]
    assert (info["moves"], info["arcs"], info["events"]) == (3, 1, 3)
    assert info["warnings"] == ["line 1: something the interpreter noticed"]
    # 10 mm x, 5 z at the axes' rate; 6 mm at 300 mm/min; a quarter of r = 10 at 1200 mm/min; 0.5 s;
    # plus the ramps (500 mm/s^2): a little more
    rapid = (10 ** 2 + 5 ** 2) ** 0.5 / (6000 * (10 ** 2 + 5 ** 2) ** 0.5 / 10) * 60
    want = rapid + 6 / 300 * 60 + 3.14159265 * 5 / 1200 * 60 + 0.5
    assert want < info["machine_time_s"] < want + 0.5
    assert info["profile"] == "trapezoid" and info["settings"]["block_shift"] == 2
    assert info["step_events"] == 1000 + 600 + 1414     # the rapid (x leads), z down, two octants of 1000 / sqrt 2
    assert "interp: warning: line 1: something the interpreter noticed" in captured.err


def test_check_summary_line(fakes, nc, capsys):
    assert main(["gcode", str(nc), "--check", "--set", "axis.x.steps_per_mm=80"]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    assert len(out) == 1 and "3 moves (1 arcs)" in out[0] and "(0, 1000, -100) steps" in out[0]


def test_simulation_summary_and_files(fakes, nc, tmp_path, capsys):
    steps, events = tmp_path / "s.csv", tmp_path / "e.csv"
    assert main(["gcode", str(nc), "--steps", str(steps), "--events", str(events), "--clock-hz", "1e6"]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    assert len(out) == 2 and out[0].startswith(f"{len(steps.read_text().splitlines()) - 1} step cycles, end X0 Y10 "
                                               "Z-1 mm (work) = (0, 1000, -100) steps, ")
    assert out[1].startswith("monitor: ok, ")
    rows = list(csv.reader(events.open()))
    assert rows[0] == ["cycle", "event", "value"]
    assert [r[1:] for r in rows[1:]] == [["spindle_cw", "12000"], ["spindle_off", "0"], ["program_end", "2"]]
    assert steps.read_text().startswith("cycle,dx,dy,dz\n")


def test_vcd_size_warning(fakes, nc, tmp_path, capsys):
    """--vcd of seconds of machine time at 50 MHz is many GB: a warning with the estimate; at
    1 MHz (the same program) no warning."""
    assert main(["gcode", str(nc), "--vcd", str(tmp_path / "w.vcd")]) == 0
    err = capsys.readouterr().err
    assert f"interp: warning: --vcd {tmp_path / 'w.vcd'}: about " in err and " GB for " in err, err
    assert main(["gcode", str(nc), "--vcd", str(tmp_path / "w.vcd"), "--clock-hz", "1e5"]) == 0
    assert "--vcd" not in capsys.readouterr().err


def test_plot_without_steps_file(fakes, nc, tmp_path):
    png = tmp_path / "p.png"
    assert main(["gcode", str(nc), "--plot", str(png)]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_end_mismatch_and_rtl_errors_exit_1(fakes, nc, capsys):
    fakes.setattr(gcode, "run_simulation", lambda *a, **k: fake_harness(*a, **k, shift=(1, 0, 0)))
    assert main(["gcode", str(nc)]) == 1
    err = capsys.readouterr().err
    assert "interp: error: the RTL ended at (1, 1000, -100) steps, the program at (0, 1000, -100)" in err
    starts = []
    fakes.setattr(gcode, "run_simulation", lambda *a, **k: fake_harness(*a, **k))
    assert main(["gcode", str(nc)]) == 0
    capsys.readouterr()
    fakes.setattr(gcode.Progress, "__call__", lambda self, cycle, steps, n: (starts.append(cycle),
                                                                             self.history.append((cycle, n))))
    assert main(["gcode", str(nc)]) == 0
    capsys.readouterr()
    cycle = starts[2] + 1               # during the third command: the line of source line 4
    fakes.setattr(gcode, "run_simulation", lambda *a, **k: fake_harness(*a, **k, errors=[(cycle, 4)]))
    starts.clear()
    assert main(["gcode", str(nc)]) == 1
    err = capsys.readouterr().err
    from interp.models.motion import ERROR_TEXT

    assert f"motion_top error 4 ({ERROR_TEXT[4]}) at cycle {cycle}, line 4" in err


def test_event_codes_in_the_commands(fakes, nc, tmp_path):
    seen = {}

    def harness(path, sim, **kw):
        seen["lines"] = open(path).read().splitlines()
        return fake_harness(path, sim, **kw)

    fakes.setattr(gcode, "run_simulation", harness)
    assert main(["gcode", str(nc)]) == 0
    kinds = [list(map(int, line.split())) for line in seen["lines"]]
    assert [k[3] for k in kinds if k[0] == EVENT] == [EVENT_CODES[n] for n in ("spindle_cw", "spindle_off",
                                                                               "program_end")]
    assert all(len(k) == 16 for k in kinds)


@pytest.mark.parametrize("argv,text", [
    (["gcode", "/nonexistent/p.nc", "--check"], "cannot read /nonexistent/p.nc"),
    (["gcode", "{nc}", "--machine", "/nonexistent/m.toml"], "cannot read machine file /nonexistent/m.toml"),
    (["gcode", "{nc}", "--set", "axis.x.steps_per_inch=3"], "unknown key axis.x.steps_per_inch"),
    (["gcode", "{nc}", "--clock-hz", "fast"], "invalid float value"),
    (["gcode", "{nc}", "--steps", "/nonexistent/dir/s.csv"], "cannot write /nonexistent/dir/s.csv: no directory"),
    (["gcode", "{nc}", "--events", "{tmp}"], "is a directory"),
    (["gcode", "{nc}", "--events", "/proc/x.csv"], "cannot write /proc/x.csv"),
    (["gcode", "{nc}", "--json"], "--json goes with --check"),
    (["gcode", "{nc}", "--pause-seconds", "-1"], "--pause-seconds"),
    (["gcode", "{nc}", "--push-interval", "0"], "--push-interval must be 1 .. 65536"),
    (["gcode", "{nc}", "--sim", "questa"], "invalid choice"),
    (["gcode", "{nc}", "--profile", "jerky"], "invalid choice"),
    (["gcode", "{nc}", "--resume-at", "1"], "--resume-at without a --hold-at"),
    (["gcode", "{nc}", "--hold-at", "1", "--resume-at", "2", "--resume-at", "3"], "--resume-at without a --hold-at"),
    (["gcode", "{nc}", "--hold-at", "2", "--resume-at", "1"], "--resume-at 1 is not after its --hold-at 2"),
    (["gcode", "{nc}", "--hold-at", "1", "--resume-at", "3", "--hold-at", "2", "--resume-at", "4"],
     "--hold-at 2 overlaps the hold from 1 s (resumed at 3 s)"),
    (["gcode", "{nc}", "--hold-at", "1", "--hold-at", "2"], "--hold-at 2 overlaps the hold from 1 s (never resumed)"),
    (["gcode", "{nc}", "--hold-at", "-1"], "--hold-at needs a finite time in seconds >= 0"),
    (["gcode", "{nc}", "--hold-at", "nan"], "--hold-at needs a finite time in seconds >= 0"),
    (["gcode", "{nc}", "--hold-at", "soon"], "invalid float value"),
    (["gcode", "{nc}", "--override", "0"], "--override 0: the percentage must be a whole number 1 .. 200"),
    (["gcode", "{nc}", "--override", "201@1"], "the percentage must be a whole number 1 .. 200"),
    (["gcode", "{nc}", "--override", "fast"], "--override fast: give PERCENT or PERCENT@SECONDS"),
    (["gcode", "{nc}", "--override", "50@x"], "give PERCENT or PERCENT@SECONDS"),
    (["gcode", "{nc}", "--override", "50@-2"], "--override 50@-2: the time after @ must be"),
    (["gcode", "{nc}", "--check", "--override", "50"], "go with a simulation, not --check"),
    (["gcode", "{nc}", "--plot-speed", "/nonexistent/dir/s.png"], "cannot write /nonexistent/dir/s.png"),
    (["gcode", "{nc}", "--steps", "{nc}"], "{nc}: an output would overwrite the input {nc}"),
    (["gcode", "{nc}", "--steps", "{tmp}/a.csv", "--events", "{tmp}/a.csv"], "{tmp}/a.csv: given for two outputs"),
    (["gcode", "{nc}", "--check", "--steps", "{tmp}/a.csv"], "are written by a simulation, not --check"),
    (["gcode", "/dev/zero", "--check"], "cannot read /dev/zero: not a file (a device?)"),
])
def test_errors_are_one_line_exit_2(fakes, nc, tmp_path, capsys, argv, text):
    def harness(*a, **k):
        raise AssertionError("the simulation must not start")

    fakes.setattr(gcode, "run_simulation", harness)
    argv = [a.format(nc=nc, tmp=tmp_path) for a in argv]
    one_line_error(capsys, 2, argv, text.format(nc=nc, tmp=tmp_path))
    assert Path(nc).read_text().startswith("G")              # the program is never overwritten


def test_controls_reach_the_harness_in_cycles(fakes, nc, tmp_path, capsys):
    seen = {}

    def harness(path, sim, **kw):
        seen.update(kw)
        return fake_harness(path, sim, **kw)

    fakes.setattr(gcode, "run_simulation", harness)
    png = tmp_path / "speed.png"
    # (the fake harness ignores holds and overrides: the monitor sees the 50 % broken; exit 1)
    assert main(["gcode", str(nc), "--clock-hz", "1e6", "--override", "150", "--override", "50@0.25",
                 "--hold-at", "0.5", "--resume-at", "0.75", "--hold-at", "1", "--resume-at", "1.5",
                 "--profile", "scurve", "--plot-speed", str(png)]) == 1
    assert seen["controls"] == [(250000, "override", 50), (500000, "hold", 0), (750000, "resume", 0),
                                (1000000, "hold", 0), (1500000, "resume", 0)]
    assert seen["settings"]["override"] == 150 and seen["settings"]["jerk_shift"] > 0
    assert seen["push_interval"] == 424                 # the record unpacker's pace (68-byte compact records, 348 clocks for codes)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "monitor: " in capsys.readouterr().out


def test_profile_flag_overrides_the_machine_file(fakes, nc, capsys):
    assert main(["gcode", str(nc), "--check", "--json", "--set", "motion.profile=scurve"]) == 0
    assert json.loads(capsys.readouterr().out)["profile"] == "scurve"
    assert main(["gcode", str(nc), "--check", "--json", "--set", "motion.profile=scurve", "--profile",
                 "trapezoid"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["profile"] == "trapezoid" and info["settings"]["jerk_shift"] == 0


def test_monitor_violation_fails_the_run(fakes, nc, capsys):
    def fast(path, sim, **kw):
        result = fake_harness(path, sim, **kw)
        rows = list(csv.reader(open(kw["steps_path"])))
        with open(kw["steps_path"], "w", newline="") as f:      # every event at half its time: 2x speed
            csv.writer(f).writerows([rows[0]] + [[int(r[0]) // 2, *r[1:]] for r in rows[1:]])
        return result

    fakes.setattr(gcode, "run_simulation", fast)
    assert main(["gcode", str(nc)]) == 1
    captured = capsys.readouterr()
    assert "monitor: " in captured.out and "violations" in captured.out
    assert "the motion monitor found" in captured.err


def test_bad_machine_file_one_line(fakes, nc, tmp_path, capsys):
    m = tmp_path / "machine.toml"
    m.write_text("[axis.x]\nsteps_per_inch = 3\n")
    one_line_error(capsys, 2, ["gcode", str(nc), "--machine", str(m)], "machine.toml: unknown key axis.x.steps_per_inch")


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes anywhere")
def test_unwritable_output(fakes, nc, tmp_path, capsys):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o500)
    one_line_error(capsys, 2, ["gcode", str(nc), "--steps", str(locked / "s.csv")], "Permission denied")


def test_soft_limit_error_one_line(fakes, nc, capsys):
    one_line_error(capsys, 2, ["gcode", str(nc), "--check", "--set", "axis.z.min_mm=0"],
                   "line 4: Z -1 mm is beyond the Z travel 0 .. 1000 mm (machine file)")


def test_bad_bytes_reach_the_interpreter_as_surrogates(monkeypatch, tmp_path, capsys):
    seen = {}

    def interpret(text, machine, start_steps=(0, 0, 0), saved=None, program=None, start_line=None):
        seen["text"] = text
        return Program()

    monkeypatch.setattr(gcode, "interpret_program", interpret)
    src = tmp_path / "bad.nc"
    src.write_bytes(b"G0 X1\n(caf\xe9)\n")
    assert main(["gcode", str(src), "--check"]) == 0
    assert seen["text"] == "G0 X1\n(caf\udce9)\n"


# ---------------- end to end: the real interpreter and simulator ----------------

def _have(module: str) -> bool:
    try:
        return importlib.util.find_spec(module) is not None
    except ModuleNotFoundError:
        return False


real = pytest.mark.skipif(not (_have("interp.gcode.interpreter") and _have("interp.simulation.native")),
                          reason="needs interp.gcode.interpreter and interp.simulation.native")


@real
def test_demo_program_end_to_end(tmp_path, capsys):
    src = tmp_path / "demo.nc"
    src.write_text(gcode.DEMO)
    events = tmp_path / "e.csv"
    assert main(["gcode", str(src), *gcode.DEMO_OPTIONS, "--check", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert main(["gcode", str(src), *gcode.DEMO_OPTIONS, "--steps", str(tmp_path / "s.csv"),
                 "--events", str(events)]) == 0
    out = capsys.readouterr().out
    assert f"= {tuple(info['end_steps'])} steps" in out
    names = [r[1] for r in list(csv.reader(events.open()))[1:]]
    assert names == ["spindle_cw", "spindle_off", "program_end"]
    rows = list(csv.reader((tmp_path / "s.csv").open()))[1:]
    assert [sum(int(r[k]) for r in rows) for k in (1, 2, 3)] == info["end_steps"]


SMALL = """G21 G90 G17
G01 X0.3 Y0.1 F3000
M3 S6000
G02 X0.5 Y0.3 I0 J0.2 F3000
G18 G03 X0.3 Z0.2 I-0.2 K0
M5
G17 G00 X0 Y0 Z0
"""


@real
@pytest.mark.skipif(not _have("cocotb"), reason="needs cocotb")
def test_icarus_and_verilator_give_the_same_steps(tmp_path, capsys):
    src = tmp_path / "small.nc"
    src.write_text(SMALL)
    files = {}
    for sim in ("verilator", "icarus"):
        steps, events = tmp_path / f"{sim}_steps.csv", tmp_path / f"{sim}_events.csv"
        assert main(["gcode", str(src), "--clock-hz", "20000", "--sim", sim, "--steps", str(steps),
                     "--events", str(events)]) == 0
        files[sim] = (steps.read_text(), events.read_text())
    assert files["verilator"] == files["icarus"]
    assert files["verilator"][1].count("spindle") == 2


@pytest.mark.parametrize("argv,text", [
    (["gcode", "{nc}", "--plot-speed", "{tmp}/x.txt"], "--plot-speed {tmp}/x.txt: '.txt' is not a plot format"),
    (["gcode", "{nc}", "--plot", "{tmp}/x.txt"], "--plot {tmp}/x.txt: '.txt' is not a plot format"),
    (["gcode", "{nc}", "--plot", "{tmp}/x"], "no extension is not a plot format"),
    (["gcode", "{nc}", "--hold-at", "0.3", "--resume-at", "0.4", "--hold-at", "0.4", "--resume-at", "0.5"],
     "--hold-at 0.4 must come after the previous --resume-at 0.4"),
    (["gcode", "{nc}", "--clock-hz", "100000", "--hold-at", "0.3", "--resume-at", "0.4", "--hold-at", "0.400004"],
     "--hold-at 0.400004 must come after the previous --resume-at 0.4 (at 100000 Hz both are clock cycle 40000"),
    (["gcode", "{nc}", "--override", "50@-1"], "--override 50@-1: the time after @"),
    (["gcode", "{nc}", "--override", "50@inf"], "--override 50@inf: the time after @ must be a finite"),
    (["gcode", "{nc}", "--override", "50.5"], "--override 50.5: the percentage must be a whole number"),
    (["gcode", "{nc}", "--hold-at", "inf"], "--hold-at needs a finite time in seconds >= 0 (got inf)"),
])
def test_review_option_errors_one_line_before_the_run(fakes, nc, tmp_path, capsys, argv, text):
    def harness(*a, **k):
        raise AssertionError("the simulation must not start")

    fakes.setattr(gcode, "run_simulation", harness)
    argv = [a.format(nc=nc, tmp=tmp_path) for a in argv]
    one_line_error(capsys, 2, argv, text.format(tmp=tmp_path))


@pytest.mark.parametrize("letter", ["P", "Q"])
def test_negative_g64_tolerance_is_one_line(tmp_path, capsys, letter):
    src = tmp_path / "p.nc"
    word = "P-1" if letter == "P" else "P0.1 Q-1"
    src.write_text(f"G21 G64 {word}\nG1 X10 F100\nG1 Y10\n")
    one_line_error(capsys, 2, ["gcode", str(src), "--check"],
                   f"line 1, column {9 if letter == 'P' else 14}: {letter}-1: the G64 tolerance cannot be negative")


def test_hold_lines_follow_the_steps_csv():
    # the harness says the speed was 0 at 1200, but steps left until 1500 (an S-curve's tail)
    controls = [(1000, "hold", 0), (3000, "resume", 0), (5000, "hold", 0), (6000, "resume", 0),
                (90000, "hold", 0)]
    holds = [(1.0, 3.0), (5.0, 6.0), (90.0, None)]
    stops = [[1000, 1200, 3], [5000, None, None]]
    steps = [900, 1100, 1300, 1500, 3100, 5100, 5500, 5900, 6100]
    import io
    from contextlib import redirect_stderr

    err = io.StringIO()
    with redirect_stderr(err):
        lines = gcode.hold_lines(holds, stops, controls, steps, 10000, 1000.0)
    assert lines == ["hold at 1 s: stopped 0.5 s later, 3 steps after it",
                     "hold at 5 s: did not stop before its resume, 3 steps after it"]
    assert "None" not in "".join(lines)
    assert err.getvalue().count("\n") == 1 and "--hold-at 90: after the program's end" in err.getvalue()


def test_empty_program_no_numpy_warning(fakes, nc, tmp_path, capsys):
    import warnings

    fakes.setattr(gcode, "interpret_program", lambda text, machine, start_steps=(0, 0, 0), saved=None, program=None,
                  start_line=None: Program(
        moves=[], warnings=[], end_work=(0.0, 0.0, 0.0), units="mm", end_machine=(0.0, 0.0, 0.0)))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert main(["gcode", str(nc)]) == 0
    out = capsys.readouterr().out
    assert "0-clock" not in out and "monitor: ok" in out


SHORT_COMMAND = "G21 G90\nG1 X10 F6000\nG1 X10.001\nG1 X20\nG1 X20 Y10\nM2\n"


@real
def test_one_step_command_keeps_the_profile(tmp_path, capsys):
    """A one-step move lasting fewer clocks than speed_ramp's look-ahead set-up used to end
    the profile early (the next corner at 34 mm/s against a planned 4.1, the program ending at
    speed); the compiler now keeps every move 2 (NW + 3) clocks long, and the monitor's corner,
    exit and end checks pass."""
    src = tmp_path / "short.nc"
    src.write_text(SHORT_COMMAND)
    sets = [a for axis in "xyz" for a in ("--set", f"axis.{axis}.steps_per_mm=1000")]
    code = main(["gcode", str(src), *sets, "--clock-hz", "5e6"])
    out = capsys.readouterr().out
    assert code == 0 and "monitor: ok" in out, out


SQUARE = "G21 G90\nG1 X10 F3000\nG1 X10 Y10\nG1 X0 Y10\nG1 X0 Y0\nM2\n"


@real
def test_scurve_corners_within_their_junction_limit(tmp_path, capsys):
    """The S-curve's moving average spreads the speed around a corner: planned for the
    unfiltered speed, the corners ran at about 1.8 x their junction limit (the monitor's
    "junction speeds" check); the planner lowers each junction by a W / 2."""
    src = tmp_path / "square.nc"
    src.write_text(SQUARE)
    sets = [a for axis in "xyz" for a in ("--set", f"axis.{axis}.steps_per_mm=1000")]
    code = main(["gcode", str(src), *sets, "--clock-hz", "5e6", "--profile", "scurve"])
    out = capsys.readouterr().out
    assert code == 0 and "monitor: ok" in out, out


def test_warning_count_includes_those_left_out(tmp_path, capsys):
    """30 feed moves above the axes' rate: 20 warnings printed, then "10 more warnings like the
    line above"; the summary and --json count all 30."""
    program = tmp_path / "fast.nc"
    program.write_text("G21 G90\n" + "".join(f"G1 X{n % 2} F100000\n" for n in range(1, 31)))
    assert main(["gcode", str(program), "--check"]) == 0
    captured = capsys.readouterr()
    assert "10 more warnings like the line above" in captured.err
    assert captured.out.rstrip().endswith(", 30 warnings"), captured.out
    assert main(["gcode", str(program), "--check", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["warning_count"] == 30 and len(info["warnings"]) == 21


def test_a_program_too_large_is_one_line(monkeypatch, tmp_path, capsys):
    """Above MAX_PROGRAM_BYTES (256 MiB; here 64 bytes) a program is refused, not read whole."""
    monkeypatch.setattr(gcode, "MAX_PROGRAM_BYTES", 64)
    program = tmp_path / "big.nc"
    program.write_text("G0 X1\n" * 20)
    one_line_error(capsys, 2, ["gcode", str(program), "--check"], f"{program}: a program of more than 0 MiB")


def test_subroutine_files(tmp_path, capsys):
    """`interp gcode` finds o<name> call's name.ngc in the program's folder, then in the
    machine file's gcode.subroutine_path (relative to the machine file); standard input's
    program looks in the current folder first."""
    (tmp_path / "jobs").mkdir()
    (tmp_path / "macros").mkdir()
    (tmp_path / "jobs" / "part.nc").write_text("G21 G90\no<square> call [4]\no<mark> call\nM2\n")
    (tmp_path / "jobs" / "square.ngc").write_text("o<square> sub\nG1 X#1 F600\nG1 Y#1\n(debug, side #1)\n"
                                                   "o<square> endsub\n")
    (tmp_path / "macros" / "mark.ngc").write_text("o<mark> sub\nG0 Z1\no<mark> endsub\n")
    machine = tmp_path / "m.toml"
    machine.write_text('[gcode]\nsubroutine_path = ["macros"]\n')
    part = str(tmp_path / "jobs" / "part.nc")
    assert main(["gcode", part, "--check", "--machine", str(machine)]) == 0
    out, err = capsys.readouterr()
    assert "3 moves" in out and err.splitlines() == ["interp: message: line 2: side 4.000000"], (out, err)
    assert main(["gcode", part, "--check"]) == 2
    assert capsys.readouterr().err.strip() == ("interp: error: line 3, column 1: o<mark> call: o<mark> is not "
                                               "defined: no 'o<mark> sub' in the program and no mark.ngc in the "
                                               "subroutine folders")
    machine.write_text('[gcode]\nsubroutine_path = "macros"\n')
    assert main(["gcode", part, "--check", "--machine", str(machine)]) == 2
    assert "gcode.subroutine_path must be a list of folder names (got 'macros')" in capsys.readouterr().err
