# SPDX-License-Identifier: Apache-2.0
"""The machine file and the compiler from moves (machine mm) to motion_top commands.

Programs here are built by hand from interp.gcode.moves, so these tests need
neither the G-code language layer nor the simulator.
"""
import math
import random
import tomllib
from dataclasses import replace

import pytest

from hypothesis import given, settings
from hypothesis import strategies as st

from interp.testing.seeds import seeded_random
from interp.models.speed_ramp import BLOCK_SHIFT_MIN
from interp.gcode.compile import (ARC_LIMIT, BLOCK_SHIFT_MAX, DWELL_MAX, EVENT, EVENT_CODES, EXIT_MARGIN, FRAC,
                                  LINE_MAX, NW_MAX, PF, PWM_FULL, ZW_MAX, TAKE_IN_STEPS, CompileError, Compiler, compile_program)
from interp.gcode.planner import junction_speed
from interp.gcode.stepcount import arc_count, arc_events, helix_count
from interp.gcode.machine import SCHEMA, MachineError, default_machine_text, load_machine
from interp.gcode.moves import PLANES, Arc, Dwell, Event, Line, Program
from interp.models.arc import arc_error, arc_steps
from interp.models.lecture import within_half_step
from interp.models.motion import ARC_CCW, ARC_CW, DWELL, LINE, Command, command_steps, interval_costs

MACHINE = load_machine()


def total(commands) -> list[int]:
    """The displacement of a command list in steps (x, y, z), arcs mapped from (u, v, w)."""
    pos = [0, 0, 0]
    for c in commands:
        if c.kind == LINE:
            pos = [p + d for p, d in zip(pos, (c.x, c.y, c.z))]
        elif c.kind in (ARC_CW, ARC_CCW):
            iu, iv, iw = list(PLANES.values())[c.plane]
            pos[iu] += c.x
            pos[iv] += c.y
            pos[iw] += c.z
    return pos


def steps_of(point, spm=(100, 100, 100)) -> list[int]:
    return [math.floor(p * s + 0.5) for p, s in zip(point, spm)]


# ---------------- the machine file ----------------

def test_default_file_is_the_documented_defaults():
    shipped = tomllib.loads(default_machine_text())
    for section, keys in SCHEMA.items():
        head, _, sub = section.partition(".")
        body = shipped[head][sub] if sub else shipped[head]
        assert set(body) == set(keys), section
        for key, spec in keys.items():
            value = tuple(body[key]) if isinstance(body[key], list) else body[key]
            assert value == spec[1], (section, key)
    assert MACHINE.clock_hz == 50e6 and MACHINE.steps_per_mm == (100, 100, 100)
    assert MACHINE.timing() == {"pulse_width": 50, "setup": 50, "hold": 50}


def test_omitted_keys_take_the_defaults(tmp_path):
    f = tmp_path / "m.toml"
    f.write_text("[axis.x]\nsteps_per_mm = 80\n[tool.3]\nlength_mm = 12.5\n")
    m = load_machine(str(f))
    assert m.steps_per_mm == (80, 100, 100) and m.axes[0].max_rate_mm_min == 6000
    assert m.tools == {3: {"length_mm": 12.5, "diameter_mm": 0.0}} and m.clock_hz == 50e6


@pytest.mark.parametrize("text,message", [
    ("[axis.x]\nsteps_per_inch = 3\n", "m.toml: unknown key axis.x.steps_per_inch"),
    ("[axis.w]\nsteps_per_mm = 3\n", "m.toml: unknown section [axis.w]"),
    ("[spindel]\nmax_s = 3\n", "m.toml: unknown section [spindel]"),
    ("[axis.x]\nsteps_per_mm = \"many\"\n", "m.toml: axis.x.steps_per_mm must be a number"),
    ("[axis.x]\nsteps_per_mm = 0\n", "m.toml: axis.x.steps_per_mm must be > 0"),
    ("[axis.y]\nmin_mm = 10\nmax_mm = 5\n", "axis.y.min_mm (10) must be below axis.y.max_mm"),
    ("[motion]\nprofile = \"cubic\"\n", "m.toml: motion.profile must be one of"),
    ("[home]\ng28 = [1, 2]\n", "m.toml: home.g28 must be a list of three numbers"),
    ("[controller]\nclock_hz = true\n", "m.toml: controller.clock_hz must be a number"),
    ("[controller]\nclock_hz = 1000\n", "axis.x.max_rate_mm_min (6000 mm/min = 10000 steps/s) is more than one step"),
    ("[output]\npulse_ns = 2e6\n", "output.pulse_ns is more than 65535 clock cycles"),
    ("[tool.a]\nlength_mm = 1\n", "m.toml: unknown section [tool.a]"),
    ("[output]\ninvert = [\"step_w\"]\n", "m.toml: output.invert: 'step_w' is not one of step_x, step_y"),
    ("[input]\ninvert = \"probe\"\n", "m.toml: input.invert must be a list of names of estop, limit_x"),
    ("[input]\ninvert = [\"probe\", \"probe\"]\n", "m.toml: input.invert: a name given twice"),
    ("axis = 3\n", "m.toml: unknown key"),
    ("[axis.x\n", "m.toml: not valid TOML"),
])
def test_bad_machine_files(tmp_path, text, message):
    f = tmp_path / "m.toml"
    f.write_text(text)
    with pytest.raises(MachineError) as err:
        load_machine(str(f))
    assert message in str(err.value) and "\n" not in str(err.value)


def test_pin_settings():
    """input.invert and output.invert as the INPUT_INVERT and OUTPUT_INVERT bits (regs/controller.rdl),
    input.filter_us and input.unfiltered as INPUT_FILTER (a sample every filter_us / 4, the inputs
    filtered in bits 20:16), spindle.pwm_hz as SPINDLE_PERIOD clocks; the periods must fit 16 bits."""
    assert load_machine().pin_settings() == {"INPUT_INVERT": 0, "INPUT_FILTER": 0x1F << 16, "OUTPUT_INVERT": 0,
                                             "SPINDLE_PERIOD": 50000}
    m = load_machine(sets=['input.invert=["probe", "estop"]', 'output.invert=["dir_y", "enable", "dout3", "step_x"]',
                           "controller.clock_hz=15e6", "spindle.pwm_hz=20000", "input.filter_us=1000",
                           'input.unfiltered=["probe", "estop"]'])
    assert m.pin_settings() == {"INPUT_INVERT": 0b10001, "INPUT_FILTER": 0b01110 << 16 | 3750,
                                "OUTPUT_INVERT": 1 << 4 | 1 << 6 | 1 << 15 | 1, "SPINDLE_PERIOD": 750}
    assert load_machine(sets=["input.filter_us=0.01"]).pin_settings()["INPUT_FILTER"] == 0x1F << 16 | 1
    with pytest.raises(MachineError, match=r"spindle.pwm_hz \(500 Hz\) is a period of 100000 clocks .* 763 \.\. 2.5e\+07 Hz"):
        load_machine(sets=["spindle.pwm_hz=500"]).pin_settings()
    with pytest.raises(MachineError, match=r"input.filter_us \(6000 us\) is a sample period of 75000 clocks .* at most 5242.8 us"):
        load_machine(sets=["input.filter_us=6000"]).pin_settings()


def test_overrides():
    m = load_machine(sets=["axis.x.steps_per_mm=80", "controller.clock_hz=1e6", "motion.profile=scurve",
                           "home.g28=[1, 2, 3]", "tool.7.diameter_mm=6"], clock_hz=None)
    assert m.steps_per_mm[0] == 80 and m.clock_hz == 1e6 and m.values["motion"]["profile"] == "scurve"
    assert m.g28 == (1, 2, 3) and m.tools[7]["diameter_mm"] == 6
    assert load_machine(sets=["controller.clock_hz=1e6"], clock_hz=2e8).clock_hz == 2e8    # --clock-hz last
    for bad, message in (("axis.x.steps_per_inch=3", "unknown key axis.x.steps_per_inch"),
                         ("axis.x.steps_per_mm=abc", "axis.x.steps_per_mm must be a number"),
                         ("clock_hz=5", "want SECTION.KEY=VALUE"), ("axis.x.steps_per_mm", "want KEY=VALUE")):
        with pytest.raises(MachineError, match=message):
            load_machine(sets=[bad])
    with pytest.raises(MachineError, match="cannot read machine file"):
        load_machine("/nonexistent/m.toml")


# ---------------- lines, rounding, limits ----------------

def test_rounding_once_no_drift():
    moves, here = [], (0.0, 0.0, 0.0)
    for n in range(1, 101):                              # 100 x 0.003 mm relative = 0.3 mm = 30 steps
        end = (0.003 * n, -0.0071 * n, 0.0)
        moves.append(Line(here, end, 500, n))
        here = end
    out = compile_program(Program(moves), MACHINE)
    assert total(out.commands) == steps_of(here) == [30, -71, 0]
    assert out.end_steps == (30, -71, 0) and all(c.kind == LINE for c in out.commands)
    # each command moves from the previous rounded point to the next
    pos = [0, 0, 0]
    for c in out.commands:
        pos = [p + d for p, d in zip(pos, (c.x, c.y, c.z))]
        assert pos == steps_of(moves[c.source - 1].end)


def test_long_lines_split_exactly():
    spm = (LINE_MAX // 1000)
    m = load_machine(sets=[f"axis.x.steps_per_mm={spm}", "axis.x.max_rate_mm_min=1000", "controller.clock_hz=1e9"])
    c = Compiler(m)
    c.line_to([2 * LINE_MAX + 5, -3, LINE_MAX + 1], 7.0, 1)
    cmds = c.out.commands
    assert len(cmds) == 3 and total(cmds) == [2 * LINE_MAX + 5, -3, LINE_MAX + 1]
    assert all(max(abs(x.x), abs(x.y), abs(x.z)) <= LINE_MAX for x in cmds)
    out = compile_program(Program([Line((0, 0, 0), (-1000, 0, 0), None, 1),
                                   Line((-1000, 0, 0), (1000, 0, 0), None, 2)]), m)
    assert total(out.commands) == [1000 * spm, 0, 0] and len(out.commands) == 3


def test_soft_limits():
    m = load_machine(sets=["axis.x.min_mm=0", "axis.x.max_mm=300"])
    with pytest.raises(CompileError) as err:
        compile_program(Program([Line((0, 0, 0), (312.5, 0, 0), 100, 4)]), m)
    assert str(err.value) == "line 4: X 312.5 mm is beyond the X travel 0 .. 300 mm (machine file)"
    # an arc whose ends are inside but whose bulge is not
    arc = Arc((290, 0, 0), (290, 24, 0), (290, 12, 0), "XY", True, 1, 500, 7)
    with pytest.raises(CompileError, match=r"^line 7: the arc reaches X 302 mm, beyond the X travel 0 \.\. 300 mm"):
        compile_program(Program([Line((0, 0, 0), (290, 0, 0), None, 6), arc]), m)
    ok = Arc((290, 0, 0), (290, 24, 0), (290, 12, 0), "XY", False, 1, 500, 7)        # bulges to -X: fine
    compile_program(Program([Line((0, 0, 0), (290, 0, 0), None, 6), ok]), m)


# ---------------- arcs ----------------

def arc_commands(out):
    return [c for c in out.commands if c.kind in (ARC_CW, ARC_CCW)]


@pytest.mark.parametrize("plane", ["XY", "ZX", "YZ"])
def test_arc_in_each_plane(plane):
    iu, iv, iw = PLANES[plane]
    start, centre, end = [0.0] * 3, [0.0] * 3, [0.0] * 3
    start[iu], centre[iu], centre[iv], end[iu], end[iv] = 10, 0, 0, 0, 10   # quarter, CCW
    out = compile_program(Program([Line((0, 0, 0), tuple(start), None, 1),
                                   Arc(tuple(start), tuple(end), tuple(centre), plane, True, 1, 600, 2)]), MACHINE)
    (c,) = arc_commands(out)
    assert (c.kind, c.plane, c.x, c.y, c.i, c.j, c.z) == (ARC_CCW, ["XY", "ZX", "YZ"].index(plane),
                                                           -1000, 1000, -1000, 0, 0)
    assert out.end_steps == tuple(steps_of(end))


def linuxcnc_tolerance(r: float) -> float:
    """How far off the circle an arc's end may be for LinuxCNC (mm mode): 0.005 mm, or 0.1 % of
    the radius up to 0.5 mm."""
    return max(0.005, min(0.001 * r, 0.5))


def leading_travel(r: float, a0: float, sweep: float) -> float:
    """The travel of the leading axis along an arc of radius r from angle a0 through `sweep`
    (each step of the arc core moves its octant's leading axis by one)."""
    total, a, end, q = 0.0, a0, a0 + sweep, math.pi / 4
    up = sweep > 0
    while (a < end) if up else (a > end):
        nxt = (math.floor(a / q + 1e-12) + 1) * q if up else (math.ceil(a / q - 1e-12) - 1) * q
        nxt = min(nxt, end) if up else max(nxt, end)
        total += max(abs(math.cos(nxt) - math.cos(a)), abs(math.sin(nxt) - math.sin(a))) * r
        a = nxt
    return total


def test_arc_end_correction_random():
    rng, seed = seeded_random()
    corrected = 0
    for n in range(300):
        plane = rng.choice(list(PLANES))
        iu, iv, iw = PLANES[plane]
        r = rng.choice([rng.uniform(0.02, 2), rng.uniform(2, 300)])
        c = [rng.uniform(-300, 300) for _ in range(3)]
        a0, a1 = rng.uniform(0, 2 * math.pi), rng.uniform(0, 2 * math.pi)
        off = rng.uniform(-1, 1) * linuxcnc_tolerance(r)
        start, end = list(c), list(c)
        start[iu], start[iv] = c[iu] + r * math.cos(a0), c[iv] + r * math.sin(a0)
        end[iu], end[iv] = c[iu] + (r + off) * math.cos(a1), c[iv] + (r + off) * math.sin(a1)
        end[iw] += rng.choice([0, rng.uniform(-5, 5)])
        arc = Arc(tuple(start), tuple(end), tuple(c), plane, rng.random() < 0.5, rng.choice([1, 1, 2]), 800, 2)
        out = compile_program(Program([Line((0, 0, 0), tuple(start), None, 1), arc]), MACHINE)
        assert total(out.commands) == steps_of(end), (seed, n)
        # the arc commands go the programmed way round: their step counts add up to the source's
        part = (a1 - a0) % (2 * math.pi) if arc.ccw else (a0 - a1) % (2 * math.pi)
        sweep = part + 2 * math.pi * (arc.turns - 1)
        got = sum(cmd.k for cmd in arc_commands(out))
        want = leading_travel(r * 100, a0, sweep if arc.ccw else -sweep)
        assert abs(got - want) <= 6 + sweep + 200 * linuxcnc_tolerance(r), (seed, n, got, want)
        for cmd in arc_commands(out):
            assert arc_error(cmd.i, cmd.j, 0, 0, cmd.x, cmd.y, 32) is None, (seed, n, cmd)
            assert cmd.k >= 1
            if cmd.k < 3000:        # the arc core's step model ends where the command says, in k steps
                path = arc_steps(cmd.i, cmd.j, 0, 0, cmd.x, cmd.y, cmd.kind == ARC_CCW, (cmd.x, cmd.y) == (0, 0))
                assert (sum(p.dx for p in path), sum(p.dy for p in path)) == (cmd.x, cmd.y)
                assert cmd.k == len(path) == cmd.motion.events - max(0, abs(cmd.z) - len(path))
        corrected += out.corrected
    assert corrected > 10           # the test does exercise the correction


def test_corrected_arc_keeps_its_sweep():
    # 100 mm radius, end 0.1 mm outside the circle (LinuxCNC's 0.1 %): arc to the lattice point, then a line
    arc = Arc((100, 0, 0), (0, 100.1, 0), (0, 0, 0), "XY", True, 1, 1000, 2)
    out = compile_program(Program([Line((0, 0, 0), (100, 0, 0), None, 1), arc]), MACHINE)
    kinds = [c.kind for c in out.commands]
    assert kinds == [LINE, ARC_CCW, LINE] and out.corrected == 1
    a = out.commands[1]
    assert abs(a.x - -10000) <= 1 and abs(a.y - 10000) <= 1
    assert total(out.commands) == [0, 10010, 0]
    assert max(abs(v) for v in (out.commands[2].x, out.commands[2].y)) <= 12


def absolute_centre(start_steps, cmd) -> tuple[int, int]:
    """An arc command's centre in absolute steps (u, v), from the position it starts at."""
    iu, iv, _ = list(PLANES.values())[cmd.plane]
    return start_steps[iu] + cmd.i, start_steps[iv] + cmd.j


def positions(commands) -> list[list[int]]:
    """The position (steps) before each command and after the last."""
    out = [[0, 0, 0]]
    for n in range(len(commands)):
        out.append(total(commands[:n + 1]))
    return out


OFF_CIRCLE = Arc((100, 0, 0), (0, 100.1, 0), (0, 0, 0), "XY", True, 1, 1000, 2)   # end 0.1 mm out


def test_correction_taken_in_by_the_next_line():
    # the line after a corrected arc starts where the arc ended: no short line between them
    prog = [Line((0, 0, 0), (100, 0, 0), None, 1), OFF_CIRCLE, Line((0, 100.1, 0), (-50, 100.1, 0), 1000, 3)]
    out = compile_program(Program(prog), MACHINE)
    assert [c.kind for c in out.commands] == [LINE, ARC_CCW, LINE] and out.corrected == 1
    arc, line = out.commands[1], out.commands[2]
    assert (arc.x + line.x, arc.y + line.y) == (-15000, 10010)
    assert total(out.commands) == [-5000, 10010, 0] == list(out.end_steps)


@pytest.mark.parametrize("between", ["dwell", "event", "G61", "end"])
def test_correction_made_before_a_stop(between):
    # before a dwell, an event, an exact-stop move or the program's end the arc's correction
    # is a line of its own: the machine stops on the programmed point
    prog = [Line((0, 0, 0), (100, 0, 0), None, 1), OFF_CIRCLE]
    if between == "dwell":
        prog.append(Dwell(0.5, 3))
    elif between == "event":
        prog.append(Event("mist_on", 0, 3))
    if between != "end":
        prog.append(Line((0, 100.1, 0), (-50, 100.1, 0), 1000, 4,
                         path_control=("G61", None) if between == "G61" else ("G64", None)))
    out = compile_program(Program(prog), MACHINE)
    kinds = [c.kind for c in out.commands]
    assert kinds[:3] == [LINE, ARC_CCW, LINE] and out.corrected == 1
    assert total(out.commands[:3]) == [0, 10010, 0]
    assert max(abs(out.commands[2].x), abs(out.commands[2].y)) <= 12
    assert total(out.commands) == steps_of(prog[-1].end)


def quarter_arcs(radii) -> Program:
    """Quarter arcs CCW about the origin from (100, 0), the n-th ending at radius radii[n]."""
    prog, start = [Line((0, 0, 0), (100, 0, 0), None, 1)], (100, 0, 0)
    for n, r in enumerate(radii):
        a = math.pi / 2 * (n + 1)
        end = (round(r * math.cos(a), 9), round(r * math.sin(a), 9), 0)
        prog.append(Arc(start, end, (0, 0, 0), "XY", True, 1, 1000, n + 2))
        start = end
    return Program(prog)


def test_correction_taken_in_by_the_next_arc():
    # ends 0.012 mm out (1.2 steps): each arc after one starts where it ended, within
    # TAKE_IN_STEPS of its own circle, about the same centre in absolute steps; no short line
    out = compile_program(quarter_arcs([100.012, 100, 100.012, 100]), MACHINE)
    assert [c.kind for c in out.commands] == [LINE] + [ARC_CCW] * 4 and out.corrected == 2
    at = positions(out.commands)
    assert {absolute_centre(at[n], out.commands[n]) for n in range(1, 5)} == {(0, 0)}
    assert total(out.commands) == [10000, 0, 0]
    # 0.1 mm out: farther than TAKE_IN_STEPS from the next circle, a short line goes first
    out = compile_program(quarter_arcs([100.1, 100, 100.1, 100]), MACHINE)
    assert [c.kind for c in out.commands] == [LINE] + [ARC_CCW, LINE] * 4
    assert total(out.commands) == [10000, 0, 0]


def test_correction_in_another_plane_or_before_an_exact_stop():
    # the correction of OFF_CIRCLE (an XY arc) is along y: an arc whose normal is y (ZX) cannot
    # take it in, nor an arc in G61; an arc whose normal is x (YZ) takes it in
    start, end = (0, 100.1, 0), (0, 100.1, 20)
    cases = [(Arc(start, end, (0, 100.1, 10), "ZX", True, 1, 1000, 3), [LINE, ARC_CCW, LINE, ARC_CCW]),
             (Arc(start, end, (0, 100.1, 10), "YZ", True, 1, 1000, 3, path_control=("G61", None)),
              [LINE, ARC_CCW, LINE, ARC_CCW]),
             (Arc(start, end, (0, 100.1, 10), "YZ", True, 1, 1000, 3), [LINE, ARC_CCW, ARC_CCW])]
    for arc, kinds in cases:
        out = compile_program(Program([Line((0, 0, 0), (100, 0, 0), None, 1), OFF_CIRCLE, arc]), MACHINE)
        assert [c.kind for c in out.commands][:len(kinds)] == kinds, (arc.plane, arc.path_control)
        assert total(out.commands) == steps_of(end)


def test_take_in_keeps_the_arc_core_limit():
    # an arc whose radius is just inside the core's limit (2^29 steps), starting where a small
    # arc before it ended 1.8 steps inside that arc's circle: taken in, its points would reach
    # the limit; it runs as chords instead (found by review)
    machine = load_machine(sets=["axis.x.steps_per_mm=1e5", "axis.y.steps_per_mm=1e5", "axis.x.min_mm=-6000",
                                 "axis.x.max_mm=6000", "axis.y.min_mm=-6000", "axis.y.max_mm=6000"])
    r2 = (ARC_LIMIT - 2.01) / 1e5
    a, rho, d = 1.0292e-4, 0.5425, 1.8274e-5
    s2 = (r2 * math.cos(-a), r2 * math.sin(-a), 0.0)
    c1 = (s2[0] - rho * math.cos(-a), s2[1] - rho * math.sin(-a), 0.0)
    s1 = (c1[0] + (rho + d) * math.cos(-a - 0.5), c1[1] + (rho + d) * math.sin(-a - 0.5), 0.0)
    prog = [Line((0, 0, 0), s1, None, 1), Arc(s1, s2, c1, "XY", True, 1, 1000, 2),
            Arc(s2, (r2, 0.0, 0.0), (0.0, 0.0, 0.0), "XY", True, 1, 1000, 3)]
    out = compile_program(Program(prog), machine)
    for c in arc_commands(out):
        assert arc_error(c.i, c.j, 0, 0, c.x, c.y, 32) is None, c
    assert total(out.commands) == steps_of((r2, 0, 0), (1e5, 1e5, 100))


def test_huge_radius_runs_as_chords():
    # R 1e14 mm: beyond the core, a chord's angle underflowed to 0 (a division by zero)
    out = compile_program(Program([Arc((0, 0, 0), (1, 0, 0), (0.5, -1e14, 0), "XY", False, 1, 100, 1)]), MACHINE)
    assert out.chords == 1 and total(out.commands) == [100, 0, 0]


def test_command_limit(monkeypatch):
    # a program that would make more than MAX_COMMANDS commands stops with one line, before it
    # makes them (a chord arc's count is known in advance)
    import interp.gcode.compile as compiler
    monkeypatch.setattr(compiler, "MAX_COMMANDS", 50)
    prog = [Line((0, 0, 0), (k + 1, 0, 0), 1000, k + 1) for k in range(60)]
    with pytest.raises(CompileError, match="^line 51: the program makes more than 50 motion_top commands"):
        compile_program(Program(prog), MACHINE)
    uneven = load_machine(sets=["axis.y.steps_per_mm=80"])
    arc = Arc((10, 0, 0), (10, 0, 0), (0, 0, 0), "XY", True, 1, 1000, 7)
    with pytest.raises(CompileError, match="^line 7: the program makes more than 50"):
        compile_program(Program([arc]), uneven)


def test_corrections_in_random_chains():
    # chains of lines and arcs (ends off their circles within LinuxCNC's tolerance, some of them
    # sharing the centre before, some in another plane): every arc about its centre rounded
    # once (nothing drifts), every move starting near its programmed start, the end exact.
    # "Near": an arc that takes a correction in runs through the start it was given, up to
    # TAKE_IN_STEPS off its circle, so its end may be that far off as well as its own end's
    # offset from its circle (three arcs about one centre, each ending further out)
    rng, seed = seeded_random()
    taken_in = 0
    for n in range(150):
        here, moves, slack = [rng.uniform(-100, 100) for _ in range(3)], [], 0.0
        moves.append(Line((0, 0, 0), tuple(here), None, 1))
        centre = None
        for k in range(2, 8):
            if rng.random() < 0.3:
                end = [h + rng.uniform(-20, 20) for h in here]
                moves.append(Line(tuple(here), tuple(end), 1000, k))
                centre = None
            else:
                plane = rng.choice(list(PLANES)) if centre is None else moves[-1].plane
                iu, iv, iw = PLANES[plane]
                if centre is None:
                    centre = list(here)
                    centre[iu] += rng.uniform(-30, 30)
                    centre[iv] += rng.uniform(-30, 30)
                r = math.hypot(here[iu] - centre[iu], here[iv] - centre[iv])
                off = rng.uniform(-1, 1) * linuxcnc_tolerance(r)
                slack = max(slack, abs(off))
                a1 = rng.uniform(0, 2 * math.pi)
                end = list(here)
                end[iu], end[iv] = centre[iu] + (r + off) * math.cos(a1), centre[iv] + (r + off) * math.sin(a1)
                moves.append(Arc(tuple(here), tuple(end), tuple(centre), plane, rng.random() < 0.5, 1, 1000, k))
                if rng.random() < 0.5:
                    centre = None
            here = end
        out = compile_program(Program(moves), MACHINE)
        assert total(out.commands) == steps_of(here) == list(out.end_steps), (seed, n)
        at, first = positions(out.commands), {}
        for c, start in zip(out.commands, at):
            first.setdefault(c.source, start)
            if c.kind in (ARC_CW, ARC_CCW):
                m = moves[c.source - 1]
                iu, iv, _ = PLANES[m.plane]
                want = steps_of(m.centre)
                assert all(abs(a - b) <= 1 for a, b in zip(absolute_centre(start, c), (want[iu], want[iv]))), \
                    (seed, n, c.source)
                assert arc_error(c.i, c.j, 0, 0, c.x, c.y, 32) is None, (seed, n, c)
                r = math.hypot(m.start[iu] - m.centre[iu], m.start[iv] - m.centre[iv])
                assert abs(math.hypot(c.i, c.j) - 100 * r) <= TAKE_IN_STEPS, (seed, n, c.source)
        for line, start in first.items():
            gap = max(abs(a - b) for a, b in zip(start, steps_of(moves[line - 1].start)))
            assert gap <= 100 * slack + TAKE_IN_STEPS + 3, (seed, n, line, gap)
            taken_in += gap > 0
    assert taken_in > 20            # the test does exercise moves that take a correction in


def test_corrections_do_not_add_up_along_a_spiral():
    # half circles about one centre, each ending 0.004 mm further out (within the centre
    # form's tolerance): an arc takes the correction before it in only while it starts within
    # TAKE_IN_STEPS of its own circle, so the path never drifts from the programmed spiral
    prog, start, r = [Line((0, 0, 0), (50, 0, 0), None, 1)], (50, 0, 0), 50.0
    for k in range(40):
        r += 0.004
        end = (r if k % 2 else -r, 0, 0)
        prog.append(Arc(start, end, (0, 0, 0), "XY", True, 1, 1000, k + 2))
        start = end
    out = compile_program(Program(prog), MACHINE)
    at = positions(out.commands)
    for c, here in zip(out.commands, at):
        if c.kind == ARC_CCW:
            m = prog[c.source - 1]
            assert abs(math.hypot(c.i, c.j) - 100 * math.hypot(*m.start[:2])) <= TAKE_IN_STEPS, c.source
            assert max(abs(v) for v in absolute_centre(here, c)) <= 1
    assert total(out.commands) == steps_of(start)
    assert 0 < out.corrected


def test_tiny_arcs_never_become_full_circles():
    # rounded start = rounded end, the source arc a tiny one: nothing (or a line), no full circle
    for ccw, a in ((True, 1e-4), (False, -1e-4), (True, 4e-4), (False, -4e-4)):
        arc = Arc((10, 0, 0), (10 * math.cos(a), 10 * math.sin(a), 0), (0, 0, 0), "XY", ccw, 1, 500, 2)
        out = compile_program(Program([Line((0, 0, 0), (10, 0, 0), None, 1), arc]), MACHINE)
        assert all(c.kind == LINE for c in out.commands)
        assert total(out.commands) == steps_of(arc.end)
    # ...but an almost-full circle whose ends round together is a full circle
    arc = Arc((10, 0, 0), (10 * math.cos(-1e-4), 10 * math.sin(-1e-4), 0), (0, 0, 0), "XY", True, 1, 500, 2)
    out = compile_program(Program([Line((0, 0, 0), (10, 0, 0), None, 1), arc]), MACHINE)
    (c,) = arc_commands(out)
    assert (c.x, c.y) == (0, 0)


def test_full_circles_and_turns_and_helix():
    arc = Arc((10, 0, 0), (10, 0, -3), (0, 0, 0), "XY", False, 3, 500, 2)        # P3, 3 mm down
    out = compile_program(Program([Line((0, 0, 0), (10, 0, 0), None, 1), arc]), MACHINE)
    cmds = arc_commands(out)
    assert len(cmds) == 3 and all((c.kind, c.x, c.y, c.i, c.j) == (ARC_CW, 0, 0, -1000, 0) for c in cmds)
    assert [c.z for c in cmds] == [-100, -100, -100] and out.end_steps == (1000, 0, -300)
    for c in cmds:
        assert c.k == len(arc_steps(c.i, c.j, 0, 0, 0, 0, False, True)) == c.motion.events


def test_helix_counts_exact_for_small_arcs():
    rng = random.Random(5)
    for _ in range(30):
        r = rng.uniform(0.05, 0.35)
        a1 = rng.uniform(0.3, 6)
        arc = Arc((r, 0, 0), (r * math.cos(a1), r * math.sin(a1), 1), (0, 0, 0), "XY", True, 1, 500, 2)
        out = compile_program(Program([Line((0, 0, 0), (r, 0, 0), None, 1), arc]), MACHINE)
        cmds = arc_commands(out)
        if not cmds:
            continue
        c = cmds[0]
        exact = len(arc_steps(c.i, c.j, 0, 0, c.x, c.y, True, (c.x, c.y) == (0, 0)))
        assert c.k == exact and c.z == min(100, c.k) and out.end_steps[2] == 100


@st.composite
def arcs(draw, radius=400):
    """(ci, cj, x, y, ccw): an arc command the core accepts (start 0, centre (ci, cj), end (x, y))."""
    r = draw(st.floats(0.5, radius))
    a0, sweep = draw(st.floats(0, 2 * math.pi)), draw(st.sampled_from([0.0, 0.01, 0.3, 1.0, 3.0, 6.2, 2 * math.pi]))
    ci, cj = round(-r * math.cos(a0)), round(-r * math.sin(a0))
    if (ci, cj) == (0, 0):
        ci = 1
    r2, turn = ci * ci + cj * cj, draw(st.sampled_from([1, -1]))
    a1 = math.atan2(-cj, -ci) + turn * (sweep + draw(st.floats(0, 0.2)))
    rs = math.sqrt(r2)
    x, y = round(ci + rs * math.cos(a1)), round(cj + rs * math.sin(a1))
    if not within_half_step(r2, (x - ci) ** 2 + (y - cj) ** 2):
        x, y = 0, 0                                         # a full circle
    return ci, cj, x, y, turn > 0


@settings(max_examples=300, deadline=None)
@given(arcs())
def test_arc_count_is_the_models(arc):
    """The exact step count and diagonal step count (octant interiors in closed form) equal
    the arc model's steps."""
    ci, cj, x, y, ccw = arc
    steps = arc_steps(ci, cj, 0, 0, x, y, ccw, (x, y) == (0, 0))
    assert arc_count(ci, cj, x, y, ccw) == len(steps)
    assert arc_events(ci, cj, x, y, ccw) == (len(steps), sum(1 for s in steps if s.dx and s.dy))


@settings(max_examples=200, deadline=None)
@given(arcs(60), st.integers(-300, 300), st.integers(-5, 400))
def test_helix_count_is_the_models(arc, travel, count):
    """Events of a helix (arc steps, w travel spread over `count` ticks, the rest after the arc)
    equal the models' step list, for exact and inexact counts."""
    ci, cj, x, y, ccw = arc
    n = arc_count(ci, cj, x, y, ccw)
    for k in (count, n):
        steps, error = command_steps(Command(ARC_CCW if ccw else ARC_CW, 1, x, y, travel, ci, cj, k), 32)
        assert not error and len(steps) == helix_count(n, travel, k)


def test_arc_count_of_huge_circles():
    """A full circle of 2^28 steps' radius (1.5e9 steps, counted without stepping through them):
    eight octants of R / sqrt(2) steps on the leading axis each."""
    r = 1 << 28
    assert abs(arc_count(-r, 0, 0, 0, True) - 8 * r / math.sqrt(2)) <= 8
    # its diagonal steps: the minor coordinates' travel, R (1 - 1 / sqrt 2) per octant
    assert abs(arc_events(-r, 0, 0, 0, True)[1] - 8 * r * (1 - 1 / math.sqrt(2))) <= 8


def test_chords_for_unequal_steps_and_huge_radius():
    m = load_machine(sets=["axis.y.steps_per_mm=80"])
    arc = Arc((10, 0, 0), (0, 10, 0), (0, 0, 0), "XY", True, 1, 500, 9)
    out = compile_program(Program([Line((0, 0, 0), (10, 0, 0), None, 1), arc]), m)
    assert not arc_commands(out) and out.chords == 1 and len(out.commands) > 5
    assert any("line 9: arc run as" in w and "different steps_per_mm" in w for w in out.warnings)
    assert out.end_steps == (0, 800, 0)
    # every chord vertex within a quarter step (+ rounding) of the circle, in steps
    pos = [1000, 0]
    for c in out.commands[1:]:
        pos = [pos[0] + c.x, pos[1] + c.y]
        assert abs(math.hypot(pos[0] / 100, pos[1] / 80) - 10) * 100 < 1.0
    # a radius beyond the core's limit (2^29 steps): chords
    spm = 2 * ARC_LIMIT / 1000
    m = load_machine(sets=[f"axis.x.steps_per_mm={spm}", f"axis.y.steps_per_mm={spm}",
                           "controller.clock_hz=1e10", "axis.x.max_mm=1000", "axis.y.max_mm=1000"])
    arc = Arc((600, 0, 0), (0, 600, 0), (0, 0, 0), "XY", True, 1, 500, 3)
    out = compile_program(Program([Line((0, 0, 0), (600, 0, 0), None, 1), arc]), m)
    assert not arc_commands(out) and any("radius is beyond the arc core" in w for w in out.warnings)
    assert total(out.commands) == steps_of((0, 600, 0), (spm, spm, 100))


# ---------------- feeds ----------------

def word(mm_s: float, spm: float, clock: float) -> float:
    """A path speed in path units (2^-FRAC steps) per clock."""
    return mm_s * spm * (1 << FRAC) / clock


@pytest.mark.parametrize("clock", [1e6, 50e6, 200e6])
@pytest.mark.parametrize("feed", [1, 10, 100, 1000, 6000])
def test_cruise_word_accuracy(clock, feed):
    m = load_machine(clock_hz=clock)
    out = compile_program(Program([Line((0, 0, 0), (500, 0, 0), feed, 1)]), m)
    assert out.commands[0].feed == round(word(feed / 60, 100, clock))
    # whole quanta of 0.12 mm/min at 1 MHz: F1 runs at 0.96 mm/min (a warning), F10 at 9.96
    assert bool(out.warnings) == (clock == 1e6 and feed == 1), out.warnings


def test_feed_caps_rapids_and_errors():
    m = load_machine(sets=["axis.z.max_rate_mm_min=600"])
    out = compile_program(Program([Line((0, 0, 0), (0, 0, -100), 2000, 5)]), m)
    assert out.commands[0].feed == round(word(10, 100, 50e6))
    assert out.commands[0].limit == out.commands[0].feed       # no faster axis rate along z
    assert any(w.startswith("line 5: F2000 mm/min is above") for w in out.warnings)
    # a rapid: the slowest axis involved limits it (z at 600 mm/min over 10 of a 10.05 mm path)
    out = compile_program(Program([Line((0, 0, 0), (1, 0, -10), None, 6)]), m)
    path = math.hypot(1, 10)
    assert out.commands[0].feed == round(word(10 * path / 10, 100, 50e6))
    # a feed below the axes' ceiling: limit = the ceiling (feed override up to 200 %)
    out = compile_program(Program([Line((0, 0, 0), (100, 0, 0), 3000, 7)]), MACHINE)
    c = out.commands[0]
    assert c.feed == round(word(50, 100, 50e6)) and c.limit == math.floor(word(100, 100, 50e6))
    with pytest.raises(CompileError, match="line 7: feed 1e-08 mm/min is too slow"):
        compile_program(Program([Line((0, 0, 0), (1, 0, 0), 1e-8, 7)]), m)


def test_a_step_rate_above_the_output_stage_is_warned_of():
    """A move whose cruise steps an axis faster than clock / (pulse + 1) (output.pulse_ns) is
    warned of with its line; at the default machine's rates nothing is."""
    fast = load_machine(sets=["output.pulse_ns=200000", "controller.clock_hz=1e6"])  # 200 + 1 clocks: 4 975 steps/s
    out = compile_program(Program([Line((0, 0, 0), (0, 30, 0), 3000, 4), Line((0, 30, 0), (30, 30, 0), 1000, 5)]), fast)
    rate = [w for w in out.warnings if "output.pulse_ns allows" in w]
    assert len(rate) == 1 and rate[0].startswith("line 4: 5000 steps/s on Y is above the 4975 ")  # 50 mm/s x 100
    fine = compile_program(Program([Line((0, 0, 0), (0, 30, 0), 3000, 4)]), MACHINE)
    assert not [w for w in fine.warnings if "output.pulse_ns" in w]


def test_feed_with_unequal_steps_per_mm():
    # 3-4-5 in mm with x 100, y 50 steps/mm: (300, 200) steps, sqrt(300^2 + 200^2) = 360.6 steps
    # along 5 mm: 72.1 steps/mm along the path; every one of the 300 step events costs 360.6 / 300
    m = load_machine(sets=["axis.y.steps_per_mm=50"])
    out = compile_program(Program([Line((0, 0, 0), (300, 400, 0), 600, 1)]), m)
    c = out.commands[0]
    spm = math.hypot(30000, 20000) / 500
    assert c.feed == round(word(10, spm, 50e6))
    assert c.cost == round(math.hypot(30000, 20000) * (1 << FRAC) / 30000) and c.length == 30000 * c.cost


@pytest.mark.parametrize("moves", [
    [Line((0, 0, 0), (10, 5, 0), 600, 1), Line((10, 5, 0), (10.07, 4.97, 0.02), 600, 2)],
    [Line((0, 0, 0), (3, 0, 0), 600, 1), Arc((3, 0, 0), (0, -3, 1), (0, 0, 0), "XY", True, 1, 600, 2)],
    [Line((0, 0, 0), (0, 3, 0), 600, 1), Arc((0, 3, 0), (0, 0, 3), (0, 0, 0), "YZ", False, 1, 600, 2)]])
def test_costs_true_even_and_lecture(moves):
    """costs="even": cost = round(true length x 2^FRAC / N), length = N x cost; "lecture": cost 0
    and length = the lecture's sqrt(axes) costs over the models' steps (as the RTL rounds them);
    "true" (the default): lines and helices as "even" (a helix paced by its plane's local speed),
    flat arcs as "lecture" with their speed words scaled by the stepped length over the true one
    (F along the true arc on average)."""
    true = compile_program(Program(moves), MACHINE)
    even = compile_program(Program(moves), MACHINE, costs="even")
    lecture = compile_program(Program(moves), MACHINE, costs="lecture")
    table = interval_costs(FRAC)
    for t, e, c in zip(true.commands, even.commands, lecture.commands):
        steps, error = command_steps(c, 32)
        assert not error and len(steps) == t.motion.events == c.motion.events == e.motion.events
        assert e.length == e.motion.events * e.cost
        assert abs(e.cost * e.motion.events - e.motion.steps * (1 << FRAC)) <= e.motion.events
        assert c.cost == 0 and c.length == sum(table[sum(map(abs, s))] for s in steps)
        assert c.length >= e.length - e.motion.events        # the lecture's path is never shorter
        if t.kind == LINE:
            assert (t.cost, t.length, t.motion.pacing) == (e.cost, e.length, 1.0)
        elif t.z != 0:
            # a helix: charged evenly; its plane's local speed up to sqrt 2 x N / its length in steps
            p, q = t.motion.plane_axes
            plane = math.hypot(t.motion.start_unit[p], t.motion.start_unit[q]) * t.motion.length_mm * 100
            assert (t.cost, t.length, t.motion.even_costs) == (e.cost, e.length, True)
            assert t.motion.pacing == pytest.approx(math.sqrt(2) * t.motion.events / plane)
        else:
            ratio = c.length / (t.motion.steps * (1 << FRAC))
            assert (t.cost, t.length) == (0, c.length) and t.motion.pacing == pytest.approx(max(1.0, ratio))
            # the same time along the true arc at the plan's cruise: length / feed = true / v
            spm_word = t.motion.spm * (1 << FRAC) / MACHINE.clock_hz
            assert t.feed == round(true.plans[-1].cruise_mm_s * spm_word * ratio)


def test_arcs_keep_their_local_speed_near_f():
    """Along a quarter arc the default costs keep the local path speed (32-event windows)
    within -4 % .. +6 % of the mean, and never above the command's pacing; events charged
    evenly run the diagonals over 25 % fast."""
    from interp.benchmarks.feed_accuracy import MOVES, local_range

    for name in ("arc r 20, quarter",):
        moves = MOVES[name]
        low, high = local_range(moves, "true")
        pacing = compile_program(Program(moves), MACHINE).commands[-1].motion.pacing
        assert 0.96 <= low and high <= min(1.06, pacing + 1e-9), (name, low, high, pacing)
        assert local_range(moves, "even")[1] > 1.25


def test_tangent_arc_joins_keep_the_cruise():
    """Four tangent G3 quarters at F3000 run at their cruise word through the joins (the
    profile's cycle model): their ends' local paces agree, so the join is no junction and the
    exit takes the arcs' scaled words (in true units it would brake to 1 / pacing of the
    cruise, 0.948).  At a corner the junction binds each side's local speed."""
    from interp.gcode.compile import FEED_W, LEN_W, NW, ZW
    from interp.models.speed_ramp import Segment, run_profile

    r, feed = 10, 3000
    points = [(0, 0), (-r, r), (-2 * r, 0), (-r, -r), (0, 0)]
    moves = [Arc((*s, 0), (*e, 0), (-r, 0, 0), "XY", True, 1, feed, n) for n, (s, e) in
             enumerate(zip(points, points[1:]), 1)]
    for costs, floor in (("true", 1.0), ("even", 1.0)):
        out = compile_program(Program(moves), load_machine(clock_hz=20e3), costs=costs)
        cmds = [c for c in out.commands if c.motion is not None]
        q = out.settings["speed_quantum"]
        cruise = cmds[0].feed
        assert all(c.feed == cruise for c in cmds) and [c.exit for c in cmds] == [cruise // q] * 3 + [0]
        samples = run_profile([Segment(c.feed, c.limit, c.exit, c.rate, c.length, c.budget) for c in cmds],
                              widths=dict(feed_w=FEED_W, nw=NW, pf=PF, len_w=LEN_W, zw=ZW), quantum=q,
                              block_shift=out.settings["block_shift"], max_cycles=10**6)
        speed = [s["speed"] for s in samples]
        at_cruise = [k for k, v in enumerate(speed) if v >= cruise - q]
        assert min(speed[at_cruise[0]:at_cruise[-1]]) >= floor * cruise - q, costs
    # a right-angle corner between two arcs: the junction binds, and the local speed at the
    # exit word on each side (the scaled word, along the stepped path) is Grbl's corner speed
    corner = [Arc((0, 0, 0), (-r, r, 0), (-r, 0, 0), "XY", True, 1, feed, 1),
              Arc((-r, r, 0), (-2 * r, 0, 0), (-2 * r, r, 0), "XY", False, 1, feed, 2)]
    out = compile_program(Program(corner), load_machine(clock_hz=20e3))
    first, second = (c.motion for c in out.commands)
    allowed = junction_speed(first.end_unit, second.start_unit, (500.0,) * 3, 0.01)
    q = out.settings["speed_quantum"]
    for motion, local in ((first, first.end_local), (second, second.start_local)):
        speed = out.commands[0].exit * q * 20e3 / (1 << FRAC) / motion.spm * math.hypot(*local)
        assert allowed - q * 20e3 / (1 << FRAC) / motion.spm * 1.1 < speed <= allowed


def test_a_steep_helix_runs_as_its_steps_with_the_plane_stop_a_corner():
    """A helix whose w travel is beyond its arc's steps: the hardware steps w on every event
    and then w alone.  The compiler emits that as a helix whose events all step w and a line
    along w (the same steps as one command), so the planner sees the plane stop as the
    corner it is: at F600 neither side runs above Grbl's corner speed there."""
    machine = load_machine(clock_hz=200e3)
    program = Program([Line((0, 0, 0), (1.0, 0, 0), None, 1),
                       Arc((1.0, 0, 0), (-1.0, 0, -20.0), (0, 0, 0), "XY", True, 1, 600, 2)])
    out = compile_program(program, machine)
    _, helix, line = out.commands
    assert helix.kind == ARC_CCW and line.kind == LINE and helix.z == -helix.k and line.z == -2000 - helix.z
    assert (line.x, line.y) == (0, 0) and out.end_steps == (-100, 0, -2000)
    whole = Command(ARC_CCW, helix.feed, helix.x, helix.y, -2000, helix.i, helix.j, helix.k, plane=helix.plane)
    assert command_steps(helix, 32)[0] + command_steps(line, 32)[0] == command_steps(whole, 32)[0]
    assert all(z for _, _, z in command_steps(helix, 32)[0])
    before, after = helix.motion.end_local, line.motion.start_unit         # the velocities there
    sides = out.plans[1].exit_mm_s * max(math.hypot(*before), math.hypot(*after))
    directions = [[u / math.hypot(*v) for u in v] for v in (before, after)]
    assert sides <= junction_speed(*directions, (500.0,) * 3, 0.01) * (1 + 1e-9)
    assert out.plans[1].exit_mm_s < 0.85 * out.plans[1].cruise_mm_s
    # the line along w is cut into pieces of at most 2^31 - 1 steps, as every line
    fine = load_machine(sets=["axis.z.steps_per_mm=2e6", "axis.z.max_rate_mm_min=60"])
    out = compile_program(Program([Line((0, 0, 0), (1, 0, -1000), None, 1),
                                   Arc((1, 0, -1000), (1, 0, 1000), (0, 0, -1000), "XY", True, 1, 60, 2)]), fine)
    assert [c.kind for c in out.commands] == [LINE, ARC_CCW, LINE, LINE] and out.end_steps == (100, 0, 2 * 10**9)
    assert all(abs(c.z) <= LINE_MAX for c in out.commands)


def test_local_pace_is_the_step_models():
    """The local velocity the compiler gives an arc's two ends (over the charged speed) is
    what its step events make: over its first and last 64 events, their displacement over
    their charge (a flat arc: the lecture's 1 and sqrt 2 a step; a helix: its true length / N
    an event; a steep one runs as a helix and a line along w), within what the window can
    resolve: a step per axis over its charge, and half its turn."""
    rng, seed = seeded_random()
    machine = load_machine(clock_hz=200e3)
    for n in range(40):
        r = rng.uniform(50, 120)
        a0, sweep = rng.uniform(0, 2 * math.pi), rng.uniform(0.5, 5.5)
        dz = rng.choice([0.0, rng.uniform(-8, 8), rng.choice([-1, 1]) * min(900.0, rng.uniform(1.5, 3) * r * sweep)])
        start = (r * math.cos(a0), r * math.sin(a0), 0.0)
        end = (r * math.cos(a0 + sweep), r * math.sin(a0 + sweep), dz)
        out = compile_program(Program([Arc(start, end, (0.0, 0.0, 0.0), "XY", True, 1, 600, 1)]), machine)
        cmd = out.commands[0]
        m = cmd.motion
        steps, _ = command_steps(cmd, 32)
        assert len(steps) == m.events
        for local, events in ((m.start_local, steps[:64]), (m.end_local, steps[-64:])):
            if m.even_costs:
                charge = len(events) * m.length_mm / m.events
            else:
                charge = sum(math.sqrt(abs(x) + abs(y)) for x, y, _ in events) / m.spm
            moved = [sum(e[axis] for e in events) for axis in range(3)]
            measured = [d / 100 / charge for d in moved]
            assert local is not None and (local[0] != 0 or local[1] != 0), (seed, n)
            # what 64 events can tell: their end points lie within half a step of the
            # curve, so each moving axis's displacement is within a step of the chord's,
            # and the chord turns from the end's tangent by half the window's angle
            quantum = math.sqrt(sum(d != 0 for d in moved)) / (charge * 100)
            turn = math.hypot(moved[0], moved[1]) / 100 / r / 2 * math.hypot(local[0], local[1])
            assert math.dist(measured, local) < quantum + turn, (seed, n, measured, local, quantum, turn)


def test_a_helix_into_a_tangent_line_keeps_the_junction():
    """A helix ending on a diagonal runs its plane 27 % above its mean there (charged evenly),
    a tangent line at its mean: the speed word at the join is lowered until the velocity
    change is within the junction deviation's allowance, never above sqrt(8 a delta) (Grbl's
    bound for every angle; before: 8.56 mm/s against 7.52 at F3000)."""
    from interp.gcode.compile import junction_velocities

    r, feed = 5.0, 3000
    a0, a1 = -math.pi / 4 - math.pi, math.pi / 4
    start, end = (r * math.cos(a0), r * math.sin(a0), 0.0), (r * math.cos(a1), r * math.sin(a1), -1.0)
    rise = -1.0 / (r * (a1 - a0))
    beyond = (end[0] - 10 * math.sin(a1), end[1] + 10 * math.cos(a1), end[2] + 10 * rise)
    program = Program([Line((start[0] + 1, start[1] - 1, 0), start, feed, 1),
                       Arc(start, end, (0.0, 0.0, 0.0), "XY", True, 1, feed, 2), Line(end, beyond, feed, 3)])
    clock = 200e3
    out = compile_program(program, load_machine(clock_hz=clock))
    moves = [c for c in out.commands if c.motion is not None]
    helix, line = next((c, d) for c, d in zip(moves, moves[1:]) if c.kind == ARC_CCW)
    assert helix.motion.even_costs and helix.motion.pacing > 1.25
    word = helix.exit * out.settings["speed_quantum"] * clock / (1 << FRAC)       # charged steps / s
    before = [word / helix.motion.spm * u for u in helix.motion.end_local]
    after = [word / line.motion.spm * u for u in line.motion.start_unit]
    change = [b - a for a, b in zip(before, after)]
    jump = math.hypot(*change)
    a_j = min(500.0 / abs(c) * jump for c in change if abs(c) > 1e-9)
    assert 0.9 * math.sqrt(8 * a_j * 0.01) < jump <= math.sqrt(8 * a_j * 0.01)
    v = word / helix.motion.spm
    assert [v * u for u in junction_velocities(helix.motion, line.motion)[0]] == pytest.approx(before)


# ---------------- dwells, events, time ----------------

def test_dwells_split():
    m = load_machine(clock_hz=200e6)
    out = compile_program(Program([Dwell(60.0, 1), Dwell(0, 2)]), m)
    cycles = [c.x for c in out.commands]
    assert all(c.kind == DWELL for c in out.commands) and sum(cycles) == 12_000_000_000
    assert max(cycles) <= DWELL_MAX and len(cycles) == 4 and cycles[-1] == 0
    assert out.commands[0].fields()[3] == -1            # 2^32 - 1 as the port's signed bits
    assert abs(out.machine_time_s - 60) < 1e-9
    with pytest.raises(CompileError, match="line 3: a dwell of -1 s is out of range"):
        compile_program(Program([Dwell(-1, 3)]), m)
    # a day at most (a longer one would be millions of DWELL commands), a pause too
    assert len(compile_program(Program([Dwell(86_400, 1)]), m).commands) == 4024
    with pytest.raises(CompileError, match=r"line 2: a dwell of 86401 s is out of range \(0 \.\. 86400 s"):
        compile_program(Program([Dwell(86_401, 2)]), m)
    with pytest.raises(CompileError, match="a pause of 1e\\+300 s is out of range"):
        compile_program(Program([Event("pause", 0, 1)]), m, pause_seconds=1e300)


def test_events_and_pauses():
    prog = Program([Event("spindle_cw", 12000, 1), Event("spindle_speed", 30000, 2), Event("output_on", 3, 3),
                    Event("pause", 1, 4), Event("tool_change", 5, 5), Event("program_end", 30, 6)])
    out = compile_program(prog, MACHINE, pause_seconds=2)
    got = [(c.kind, c.x, c.y, c.source) for c in out.commands]
    assert got == [(EVENT, EVENT_CODES["spindle_cw"], PWM_FULL // 2 + 1, 1),
                   (EVENT, EVENT_CODES["spindle_speed"], PWM_FULL, 2), (EVENT, EVENT_CODES["output_on"], 3, 3),
                   (EVENT, EVENT_CODES["pause"], 1, 4), (DWELL, 100_000_000, 0, 4),
                   (EVENT, EVENT_CODES["tool_change"], 5, 5), (EVENT, EVENT_CODES["program_end"], 30, 6)]
    assert any("line 2: S30000 is above" in w for w in out.warnings)
    assert [e[0] for e in out.events] == ["spindle_cw", "spindle_speed", "output_on", "pause", "tool_change",
                                          "program_end"]
    assert out.machine_time_s == 2


def test_machine_time_and_counts():
    prog = Program([Line((0, 0, 0), (60, 0, 0), 600, 1),                     # 6 s
                    Arc((60, 0, 0), (60, 0, 0), (50, 0, 0), "XY", True, 1, 600, 2),   # 2 pi 10 mm at 10 mm/s
                    Dwell(1.5, 3)])
    out = compile_program(prog, MACHINE)
    # (the cruise the hardware holds is whole quanta: 250 000 of them at 600 mm/min here)
    assert out.machine_time_s == pytest.approx(sum(p.time_s for p in out.plans) + 1.5, rel=1e-5)
    assert 6 + 2 * math.pi + 1.5 < out.machine_time_s < 6 + 2 * math.pi + 1.5 + 0.1   # + the ramps
    assert out.command_time[-1] == out.machine_time_s and out.command_time == sorted(out.command_time)
    assert (out.moves, out.arcs) == (2, 1)
    # the S-curve's filter adds its window to each run between stops (here one run)
    s = compile_program(prog, MACHINE, profile="scurve")
    window = (1 << (s.settings["block_shift"] + s.settings["jerk_shift"])) / 50e6
    # (its blocks are 2^10 clocks: quanta 256 times coarser, about 1000 in 600 mm/min)
    assert s.machine_time_s == pytest.approx(sum(p.time_s for p in s.plans) + 1.5 + window, rel=1e-3)
    # (and its junctions are planned a W / 2 slower, docs/planner.md: never faster)
    assert s.machine_time_s >= out.machine_time_s + window


# ---------------- the speed profile ----------------

def check_profile(out) -> None:
    """Every move command's profile fields as the hardware design defines them."""
    a, bs = out.settings["speed_quantum"], out.settings["block_shift"]
    cmds = out.commands
    for n, c in enumerate(cmds):
        if c.motion is None:
            assert (c.limit, c.exit, c.rate, c.cost, c.length, c.budget) == (0,) * 6
            continue
        assert 1 <= c.rate <= 1 << PF and c.feed >= 1 and c.limit >= c.feed
        assert c.length > 0 and c.budget == 2 * c.rate * c.length // (a << bs)
        assert c.exit * a <= c.feed
        following = cmds[n + 1] if n + 1 < len(cmds) else None
        if following is None or following.motion is None or following.motion.stop_before:
            assert c.exit == 0
        elif c.exit:        # the next command, entered at the exit, can brake to its own exit
            assert (c.exit + EXIT_MARGIN) ** 2 <= (following.budget >> PF) + following.exit ** 2


def test_profile_fields_and_settings():
    prog = Program([Line((0, 0, 0), (10, 0, 0), 3000, 1), Line((10, 0, 0), (20, 0.01, 0), 3000, 2),
                    Line((20, 0.01, 0), (20, 10, 0), 3000, 3), Dwell(0.1, 4), Line((20, 10, 0), (0, 0, 0), None, 5)])
    out = compile_program(prog, MACHINE)
    check_profile(out)
    a = out.settings["speed_quantum"]
    assert out.settings == {"speed_quantum": a, "block_shift": BLOCK_SHIFT_MIN, "jerk_shift": 0, "override": 100}
    # A = the largest path acceleration in path units / clock^2 (the diagonal rapid's, above
    # 500) over a block of 2^BLOCK_SHIFT_MIN clocks
    block = 1 << BLOCK_SHIFT_MIN
    largest = max(word(p.accel_mm_s2, 100, 50e6) for p in out.plans)
    assert a == math.ceil(block * largest / 50e6)
    assert largest > word(500, 100, 50e6)
    stops = [c.motion.stop_before for c in out.commands if c.motion]
    assert stops == [True, False, False, True]               # the start, after the dwell
    assert out.commands[0].exit > 0                          # straight on: no stop between 1 and 2
    # a short straight continuation the plan brakes in exactly: its entry comes down a few quanta
    tight = compile_program(Program([Line((0, 0, 0), (1, 0, 0), 1200, 1), Line((1, 0, 0), (1.2, 0, 0), 1200, 2)]),
                            load_machine(clock_hz=50e3))
    first, second = tight.commands
    planned = math.floor(tight.plans[0].exit_mm_s * first.motion.spm * (1 << FRAC) / 50e3
                         / tight.settings["speed_quantum"])
    assert 0 < planned - EXIT_MARGIN - 1 <= first.exit < planned
    check_profile(tight)
    # the planner's accel in path units / clock^2: rate = floor(a_seg 2^bs / A 2^PF)
    p = out.plans[0]
    assert out.commands[0].rate == math.floor(word(p.accel_mm_s2, 100, 50e6) * block / 50e6 / a * (1 << PF))


def test_block_grows_until_the_words_hold_the_program():
    """A fast machine (3200 steps/mm, 20 m/min at 200 MHz): at blocks of 4 clocks the rapid would
    be above 2^NW quanta, so the compiler takes the least block that holds it, and every field
    fits its word."""
    sets = [f"axis.{a}.{k}={v}" for a in "xyz" for k, v in (("steps_per_mm", 3200), ("max_rate_mm_min", 20000))]
    machine = load_machine(sets=sets, clock_hz=200e6)
    prog = Program([Line((0, 0, 0), (300, 0, 0), None, 1), Line((300, 0, 0), (0, 0, 0), 1000, 2)])
    out = compile_program(prog, machine)
    check_profile(out)
    a, bs = out.settings["speed_quantum"], out.settings["block_shift"]
    assert bs > BLOCK_SHIFT_MIN
    fastest = max(c.limit for c in out.commands)
    assert fastest // a <= NW_MAX and max(c.budget for c in out.commands) <= ZW_MAX
    # the least such block: one block less leaves the rapid above 2^NW quanta
    a_less = math.ceil(a / 2)
    assert fastest // a_less > NW_MAX or a_less == a
    assert Compiler.least_block_shift(0.1, 1e3, 1e3) == BLOCK_SHIFT_MIN
    assert Compiler.least_block_shift(1e-3, 1e3, 1e3) == 6          # 2^6 x 1e-3 >= 1/16 path unit a block
    assert Compiler.least_block_shift(1e-9, 1e3, 1e3) == BLOCK_SHIFT_MAX
    assert Compiler.least_block_shift(0.1, 1e30, 1e3) == BLOCK_SHIFT_MAX + 1      # nothing holds it


def test_small_accelerations_keep_their_rate():
    """1 step/mm and 1 mm/s^2 at 200 MHz: a block of 4 clocks holds 2^-23 path unit of
    acceleration, so the quantum would round up to 1 and the rate to 1 of 2^PF (35 times too
    steep); the compiler takes a block long enough for the rate to keep its precision."""
    sets = [f"axis.{a}.{k}={v}" for a in "xyz" for k, v in (("steps_per_mm", 1), ("accel_mm_s2", 1))]
    out = compile_program(Program([Line((0, 0, 0), (50, 0, 0), 600, 1)]), load_machine(sets=sets, clock_hz=200e6))
    check_profile(out)
    a, bs = out.settings["speed_quantum"], out.settings["block_shift"]
    rate = out.commands[0].rate
    accel = rate / (1 << PF) * a / (1 << bs) / (1 << FRAC) * 200e6 ** 2          # steps (mm) / s^2
    assert bs > BLOCK_SHIFT_MIN and rate > 100 and 0.99 <= accel <= 1.0, (bs, rate, accel)
    assert not out.warnings


def test_path_modes_give_stops_and_tolerances():
    from interp.gcode.compile import Compiler

    modes = [("G64", None), ("G61", None), ("G64", 0.05), ("G64", None)]
    prog = Program([Line((k, 0, 0), (k + 1, 0, 0), 600, 2 * k + 1, path_control=mode)
                    for k, mode in enumerate(modes)])
    out = Compiler(MACHINE).run(prog)
    motions = [c.motion for c in out.commands]
    assert [m.stop_before for m in motions] == [True, True, False, False]
    assert [m.tolerance_mm for m in motions] == [None, None, 0.05, None]


def test_scurve_shifts():
    # window >= 2 accel / jerk: 2 x 500 / 20000 s = 2.5e6 cycles at 50 MHz -> 2^22 = 2^12 blocks of 2^10
    out = compile_program(Program([Line((0, 0, 0), (10, 0, 0), 600, 1)]), MACHINE, profile="scurve")
    assert (out.settings["jerk_shift"], out.settings["block_shift"]) == (12, 10) and out.profile == "scurve"
    check_profile(out)
    slow = load_machine(clock_hz=50e3)          # 2500 cycles: 2^12, blocks of the least 2^2 clocks
    out = compile_program(Program([Line((0, 0, 0), (10, 0, 0), 600, 1)]), slow, profile="scurve")
    assert (out.settings["jerk_shift"], out.settings["block_shift"]) == (10, BLOCK_SHIFT_MIN)
    for jerk in ("0.001", "1e-301"):            # (2 accel / jerk overflows to inf: the same error)
        with pytest.raises(CompileError, match="S-curve's window"):
            compile_program(Program([Line((0, 0, 0), (10, 0, 0), 600, 1)]),
                            load_machine(sets=[f"motion.jerk_mm_s3={jerk}"]), profile="scurve")


# ---------------- the commands through the step-level model of motion_top ----------------

def test_commands_through_the_step_model():
    """Random small programs (lines, arcs and helices in every plane, dwells, events): the
    step-level model of motion_top's cores (interp.models.motion.queue_steps at W = 32) ends
    exactly at the compiled end point, with no error."""
    from interp.models import motion

    if not hasattr(motion, "helix_steps"):
        pytest.skip("interp.models.motion has no plane/helix step model yet")
    rng, seed = seeded_random()
    for _ in range(20):
        here, moves = (0.0, 0.0, 0.0), []
        for n in range(1, 8):
            kind = rng.choice(["line", "arc", "dwell", "event"])
            if kind == "line":
                end = tuple(h + rng.uniform(-3, 3) for h in here)
                moves.append(Line(here, end, rng.choice([None, 300.0]), n))
                here = end
            elif kind == "arc":
                plane = rng.choice(list(PLANES))
                iu, iv, iw = PLANES[plane]
                r, a0, a1 = rng.uniform(0.05, 2), rng.uniform(0, 6.3), rng.uniform(0, 6.3)
                c = list(here)
                c[iu] -= r * math.cos(a0)
                c[iv] -= r * math.sin(a0)
                end = list(c)
                off = rng.uniform(-1, 1) * linuxcnc_tolerance(r)
                end[iu] += (r + off) * math.cos(a1)
                end[iv] += (r + off) * math.sin(a1)
                end[iw] = here[iw] + rng.choice([0, rng.uniform(-2, 2)])
                moves.append(Arc(here, tuple(end), tuple(c), plane, rng.random() < 0.5, rng.choice([1, 2]), 500, n))
                here = tuple(end)
            elif kind == "dwell":
                moves.append(Dwell(0.001, n))
            else:
                moves.append(Event("spindle_cw", 1000, n))
        out = compile_program(Program(moves), MACHINE)
        steps, errors = motion.queue_steps(out.commands, 32)
        assert errors == [], seed
        check_profile(out)
        for c in out.commands:          # N of every move command is its step count in the models
            if c.motion is not None:
                assert c.motion.events == len(command_steps(c, 32)[0]), (seed, c)
        assert len(steps) == out.step_events, seed
        assert [sum(s[k] for s in steps) for k in range(3)] == list(out.end_steps) == steps_of(here), seed
        assert all(max(abs(v) for v in s) <= 1 for s in steps), seed


def test_outputs_are_the_controllers():
    out = compile_program(Program([Event("output_on", 3, 1), Event("output_off", 0, 2)]), MACHINE)
    assert [(c.x, c.y) for c in out.commands] == [(EVENT_CODES["output_on"], 3), (EVENT_CODES["output_off"], 0)]
    with pytest.raises(CompileError, match=r"^line 2: output 4: the controller has digital outputs 0 \.\. 3"):
        compile_program(Program([Event("output_on", 3, 1), Event("output_off", 4, 2)]), MACHINE)


def test_speeds_are_whole_quanta():
    # speed_ramp holds the cruise at whole quanta (at least one): at 200 kHz and 20000 mm/s^2 a
    # quantum is 24 mm/min, so F30 runs at 24 (the RTL: 0.2 mm in 100 054 clocks, 0.50027 s);
    # the warning says so and the machine time counts it
    slow = load_machine(clock_hz=200e3, sets=["axis.x.accel_mm_s2=20000"])
    out = compile_program(Program([Line((0, 0, 0), (0.2, 0, 0), 30, 1)]), slow)
    assert abs(out.machine_time_s - 0.5) < 1e-3
    assert out.warnings == ["line 1: feed 30 mm/min runs at 24 mm/min: the speed generator holds whole quanta "
                            "of 24 mm/min (2^block_shift x the largest acceleration per clock at 200000 Hz): "
                            "raise the clock or lower the accelerations"]
    out = compile_program(Program([Line((0, 0, 0), (0.2, 0, 0), 1e-3, 1)]), slow)     # below one quantum
    assert abs(out.machine_time_s - 0.2 / 24 * 60) < 1e-3 and "runs at 24 mm/min" in out.warnings[0]
    out = compile_program(Program([Line((0, 0, 0), (0.2, 0, 0), 2400, 1)]), slow)     # 100 quanta: exact
    assert out.warnings == []


def test_exact_stop_before_each_programmed_move_only():
    # G61 stops before every programmed move, not inside one: not between an arc's turns or
    # chords, nor before the correction that finishes an arc (the reviewer's double stop)
    def g61(moves):
        return Program([replace(m, path_control=("G61", None)) for m in moves])
    prog = [Line((0, 0, 0), (100, 0, 0), None, 1), OFF_CIRCLE, Line((0, 100.1, 0), (0, 50, 0), 1000, 3)]
    out = compile_program(g61(prog), MACHINE)
    assert [(c.kind, c.motion.stop_before) for c in out.commands] == \
        [(LINE, True), (ARC_CCW, True), (LINE, False), (LINE, True)]
    turns = Arc((100, 0, 0), (100, 0, 0), (0, 0, 0), "XY", True, 3, 1000, 2)
    out = compile_program(g61([prog[0], turns]), MACHINE)
    assert [c.motion.stop_before for c in arc_commands(out)] == [True, False, False]
    chords = compile_program(g61([prog[0], turns]), load_machine(sets=["axis.y.steps_per_mm=80"]))
    stops = [c.motion.stop_before for c in chords.commands[1:]]
    assert len(stops) > 100 and stops == [True] + [False] * (len(stops) - 1)


def test_a_program_compiled_from_the_machines_position():
    """compile_text(start_steps=...): the program starts where the machine is (interp send reads
    it from the controller).  G90 targets are machine coordinates, so the commands differ from a
    start at 0 by the start; G91 moves and arcs about their start are the same; the end and
    the travel limits are absolute."""
    from interp.commands.gcode import compile_text

    machine = load_machine(None, ["axis.x.max_mm=20"])
    start = (801, -400, 3)                                  # steps: 8.01, -4, 0.03 mm
    absolute = "G21 G90\nG1 X10 Y0 Z0 F600\nG2 X10 Y0 I5 J0\nG1 Y1\n"
    relative = "G21 G91\nG1 X2 F600\nG3 X0 Y0 I-1 J0\nG1 Y1\n"

    def geometry(commands):
        return [c.fields()[:2] + c.fields()[3:10] for c in commands]

    _, home = compile_text(absolute, machine)
    _, there = compile_text(absolute, machine, start_steps=start)
    assert home.end_steps == (1000, 100, 0) == there.end_steps
    assert (there.commands[0].x, there.commands[0].y, there.commands[0].z) == (1000 - 801, 400, -3)
    assert geometry(there.commands[1:]) == geometry(home.commands[1:])
    _, home = compile_text(relative, machine)
    _, there = compile_text(relative, machine, start_steps=start)
    assert geometry(there.commands) == geometry(home.commands)
    assert there.end_steps == tuple(s + e for s, e in zip(start, home.end_steps))
    compile_text("G21 G91\nG1 X12.5 F600\n", machine)                   # within the 20 mm from 0 ...
    with pytest.raises(CompileError, match="X 20.51 mm is beyond the X travel"):
        compile_text("G21 G91\nG1 X12.5 F600\n", machine, start_steps=start)  # ... not from 8.01


LASER = """G21 G90
M3 S500
G0 X1
G1 X2 F600 S250
G1 X3 S1000
G0 X5
G1 X6
M4 S100
G1 X7
M5
G0 X8
"""


def test_laser_mode():
    """spindle.laser (Grbl's $32): laser mode on first and off last; an S along the path is an
    inline spindle_speed (plane 1: no stop, the next move plans through it); the beam is off
    during a G0 (power 0 inline before it, the power back before the next feed move); M3 / M4 /
    M5 stay barriers (M4: the controller scales the power with the speed).  Without laser mode
    every S is a barrier and the steps are the same."""
    from interp.commands.gcode import compile_text

    code = {v: k for k, v in EVENT_CODES.items()}
    _, laser = compile_text(LASER, load_machine(sets=["spindle.laser=true", "spindle.max_s=1000"]))
    events = [(code[c.x], c.y, c.plane) for c in laser.commands if c.kind == EVENT]
    duty = lambda s: round(s / 1000 * 65535)
    assert events == [("laser_mode", 1, 1), ("spindle_cw", duty(500), 0),
                      ("spindle_speed", 0, 1),                                  # G0 X1: dark
                      ("spindle_speed", duty(250), 1),                          # S250 before G1 X2 (still dark)...
                      ("spindle_speed", duty(1000), 1),                         # S1000
                      ("spindle_speed", 0, 1), ("spindle_speed", duty(1000), 1),  # G0 X5, then G1 X6
                      ("spindle_ccw", duty(100), 0), ("spindle_off", 0, 0), ("laser_mode", 0, 1)]
    moves = [c for c in laser.commands if c.motion is not None]
    assert [c.motion.stop_before for c in moves] == [True, False, False, False, False, True, True]
    assert [e[0] for e in laser.events] == [e[0] for e in events]
    assert laser.warnings == []
    _, spindle = compile_text(LASER, load_machine(sets=["spindle.max_s=1000"]))
    assert all(c.plane == 0 for c in spindle.commands if c.kind == EVENT)
    assert [c.motion.stop_before for c in spindle.commands if c.motion is not None] == [True, True, True, False,
                                                                                          False, True, True]
    assert laser.end_steps == spindle.end_steps and laser.machine_time_s < spindle.machine_time_s


def test_laser_mode_dark_rapids_and_the_end():
    """Laser mode: an S given during a G0 run waits for the next feed move whatever the power
    before (no beam at rest through a dwell); a program that ends with the beam on gets a
    spindle off before laser mode ends (the beam is not left on at rest)."""
    from interp.commands.gcode import compile_text

    code = {v: k for k, v in EVENT_CODES.items()}
    machine = load_machine(sets=["spindle.laser=true", "spindle.max_s=1000"])
    _, out = compile_text("G21 G90\nM3 S0\nG1 X1 F600\nG0 X2\nS1000\nG4 P0.1\nG1 X3\n", machine)
    kinds = [(code[c.x], c.y, c.plane) if c.kind == EVENT else ("dwell" if c.kind == DWELL else "move")
             for c in out.commands]
    assert kinds == [("laser_mode", 1, 1), ("spindle_cw", 0, 0), "move", "move", "dwell",
                     ("spindle_speed", 65535, 1), "move", ("spindle_off", 0, 0), ("laser_mode", 0, 1)]
