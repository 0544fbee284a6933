# SPDX-License-Identifier: Apache-2.0
"""`interp gcode` end to end with the speed profile: random feed holds, resumes and overrides
over small programs of lines, arcs and helices, on Verilator (the native harness) and Icarus
(cocotb), at a low clock (50 kHz, like the demo): no step is lost (the run ends exactly at the
program's end, the steps CSV has exactly the sum of the commands' N events, every step once),
and the motion monitor finds nothing.  Each test prints its seed.

Skipped while the native harness does not take the profile settings and controls.
"""
import csv
import importlib.util
import inspect
import random

import pytest

from interp.testing.seeds import seeded_random
from interp.cli import main
from interp.commands import gcode

CLOCK_HZ = 50_000


def _harness_ready() -> str | None:
    if importlib.util.find_spec("interp.simulation.native") is None:
        return "no native harness"
    from interp.simulation import native

    if "controls" not in inspect.signature(native.run_native).parameters:
        return "the native harness does not take settings and controls yet"
    return None


def random_program(rng: random.Random, moves: tuple[int, int] = (2, 4)) -> str:
    """A few mm of lines, an arc and a helix in random planes, feeds and directions."""
    lines = ["G21 G90 G17", "G0 X0 Y0 Z0"]
    x = y = z = 0.0
    for _ in range(rng.randint(*moves)):
        kind = rng.choice(["line", "line", "arc", "helix"])
        feed = rng.choice([600, 1200, 3000])
        if kind == "line":
            x, y, z = x + rng.uniform(-3, 3), y + rng.uniform(-3, 3), z + rng.choice([0, rng.uniform(-1, 1)])
            lines.append(f"G1 X{x:.3f} Y{y:.3f} Z{z:.3f} F{feed}")
        else:
            r = rng.uniform(0.5, 2)
            cx, cy = x - r, y
            end_x, end_y = cx, cy + r if rng.random() < 0.5 else cy - r
            dz = rng.uniform(-1, 1) if kind == "helix" else 0.0
            z += dz
            lines.append(f"{rng.choice(['G2', 'G3'])} X{end_x:.3f} Y{end_y:.3f} Z{z:.3f} I{-r:.3f} J0 F{feed}")
            x, y = end_x, end_y
        if rng.random() < 0.3:
            lines.append("G4 P0.01")
    lines.append("G0 X0 Y0 Z0")
    lines.append("M2")
    return "\n".join(lines) + "\n"


def random_controls(rng: random.Random, seconds: float) -> list[str]:
    flags, t = [], 0.0
    for _ in range(rng.randint(0, 2)):
        t += rng.uniform(0.05, 0.4) * seconds
        hold_for = rng.uniform(0.01, 0.2)
        flags += ["--hold-at", f"{t:.4f}", "--resume-at", f"{t + hold_for:.4f}"]
        t += hold_for
    if rng.random() < 0.5:
        flags += ["--override", str(rng.choice([50, 80, 120, 200]))]
    if rng.random() < 0.5:
        flags += ["--override", f"{rng.choice([30, 70, 150, 200])}@{rng.uniform(0, seconds):.4f}"]
    return flags


def run_program(tmp_path, capsys, text: str, sim: str, flags: list[str], tag: str, clock: int = CLOCK_HZ):
    src = tmp_path / f"{tag}.nc"
    src.write_text(text)
    assert main(["gcode", str(src), "--clock-hz", str(clock), "--check", "--json"]) == 0
    import json

    info = json.loads(capsys.readouterr().out.strip().splitlines()[-1])     # (after the seed's line)
    steps = tmp_path / f"{tag}_steps.csv"
    status = main(["gcode", str(src), "--clock-hz", str(clock), "--sim", sim, "--steps", str(steps), *flags])
    captured = capsys.readouterr()
    print(captured.out, end="")                 # kept for the report of a failing test
    with open(steps, newline="") as f:
        rows = list(csv.reader(f))[1:]
    return status, captured, info, rows


def fuzz(tmp_path, capsys, sim: str, profile: str, programs: int, moves: tuple[int, int], clock: int):
    reason = _harness_ready()
    if reason:
        pytest.skip(reason)
    if sim == "icarus" and importlib.util.find_spec("cocotb") is None:
        pytest.skip("needs cocotb")
    rng, seed = seeded_random()
    for n in range(programs):
        text = random_program(rng, moves)
        program, compiled = gcode.compile_text(text, profile=profile, machine=gcode.load_machine(clock_hz=clock))
        flags = random_controls(rng, compiled.machine_time_s) + ["--profile", profile]
        status, captured, info, rows = run_program(tmp_path, capsys, text, sim, flags, f"p{n}", clock)
        context = (seed, n, flags, captured.out, captured.err)
        assert status == 0, context
        assert len(rows) == info["step_events"] == compiled.step_events, context
        assert [sum(int(r[k]) for r in rows) for k in (1, 2, 3)] == info["end_steps"], context
        assert "monitor: ok" in captured.out, context


@pytest.mark.parametrize("profile, clock", [("trapezoid", CLOCK_HZ), ("scurve", CLOCK_HZ), ("scurve", 1_000_000)])
def test_random_holds_and_overrides_lose_no_step(tmp_path, capsys, profile, clock):
    """Verilator: two programs of 2 to 4 moves at 50 kHz; the S-curve also at 1 MHz, where its
    window needs blocks of 2^4 clocks (block_shift 4, jerk_shift 12)."""
    fuzz(tmp_path, capsys, "verilator", profile, 2, (2, 4), clock)


@pytest.mark.parametrize("profile", ["trapezoid", "scurve"])
def test_random_holds_and_overrides_on_icarus(tmp_path, capsys, profile):
    """Icarus (cocotb): one program of 1 or 2 moves at 20 kHz (fewer cycles: Icarus is slow)."""
    fuzz(tmp_path, capsys, "icarus", profile, 1, (1, 2), 20_000)


@pytest.mark.slow
@pytest.mark.parametrize("sim", ["verilator", "icarus"])
@pytest.mark.parametrize("profile", ["trapezoid", "scurve"])
def test_random_holds_and_overrides_sweep(tmp_path, capsys, sim, profile):
    """The sweep: more and longer programs on both simulators."""
    fuzz(tmp_path, capsys, sim, profile, 10 if sim == "verilator" else 3, (2, 5), CLOCK_HZ)


def test_hold_stops_and_resumes_on_a_long_line(tmp_path, capsys):
    """A hold in the middle of a 20 mm line at F3000 (cruise 50 mm/s, 500 mm/s^2): the machine
    stops within v^2 / 2a = 2.5 mm (+ a step) after the hold, stands still, resumes, ends exact."""
    reason = _harness_ready()
    if reason:
        pytest.skip(reason)
    text = "G21 G90\nG1 X20 F3000\nM2\n"
    status, captured, info, rows = run_program(tmp_path, capsys, text, "verilator",
                                               ["--hold-at", "0.25", "--resume-at", "0.5"], "long")
    assert status == 0, captured
    hold, resume = int(0.25 * CLOCK_HZ), int(0.5 * CLOCK_HZ)
    during = [r for r in rows if hold <= int(r[0]) < resume]
    assert 0 < len(during) <= 250 + 1
    assert "hold at 0.25 s: stopped" in captured.out and "monitor: ok" in captured.out
    assert len(rows) == 2000 and sum(int(r[1]) for r in rows) == 2000


TIGHT_CIRCLES = "G21 G90 G0 X5 Y0\nG2 X5 Y0 I-5 J0 F6000\nG2 X5 Y0 I-5 J0\nG3 X-5 Y0 I-5 J0\nG1 X0\nM2\n"
TIGHT_HELICES = "G21 G90 G0 X5 Y0\nG2 X5 Y0 Z-3 I-5 J0 F6000\nG2 X5 Y0 Z-6 I-5 J0\nG3 X-5 Y0 Z-7 I-5 J0\nG1 X0\nM2\n"


def test_tight_fast_circles_keep_the_axes_limits(tmp_path):
    """Full circles of r 5 mm at F6000 (the centripetal limit binds) on the RTL at 200 kHz: the
    default costs (arcs by the lecture's step costs, scaled) keep every axis within its
    acceleration and the path speed within 3 % of its mean; events evenly charged
    (costs="even") run the diagonals 27 % fast and break the axes' 500 mm/s^2 where the
    octants meet.  Helices (charged evenly: the plane's local speed follows sec(theta), which
    the planner bounds) keep every limit too."""
    reason = _harness_ready()
    if reason:
        pytest.skip(reason)
    from interp.commands.gcode import compile_text
    from interp.gcode.compile import write_commands
    from interp.gcode.machine import load_machine
    from interp.simulation import native
    from interp.simulation.monitor import monitor, read_rows, table

    clock = 200e3
    machine = load_machine(clock_hz=clock)
    verdicts = {}
    for costs, program in (("true", TIGHT_CIRCLES), ("even", TIGHT_CIRCLES), ("helices", TIGHT_HELICES)):
        _, out = compile_text(program, machine, costs="true" if costs == "helices" else costs)
        write_commands(tmp_path / "c.txt", out.commands)
        t = machine.timing()
        native.run_native(str(tmp_path / "c.txt"), steps_path=str(tmp_path / "s.csv"),
                          timing=(t["pulse_width"], t["setup"], t["hold"]), settings=out.settings, controls=[],
                          max_cycles=int(3 * out.machine_time_s * clock) + 10**5)
        report = monitor(read_rows(tmp_path / "s.csv"), out, machine)
        verdicts[costs] = {name: verdict for name, *_, verdict in report.checks}
        print(costs, table(report))
    assert all(v == "ok" for v in verdicts["true"].values())
    assert all(v == "ok" for v in verdicts["helices"].values())
    assert "VIOLATED" in (verdicts["even"]["x acceleration"], verdicts["even"]["y acceleration"])
