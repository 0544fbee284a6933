# SPDX-License-Identifier: Apache-2.0
"""Tangent-method curve interpolator: RTL vs cycle model (every cycle) vs the paper's points 1-9."""
import cocotb
import pytest
from cocotb.triggers import FallingEdge

from interp.models.base import move
from interp.models.curve import (CURVES, END_COUNT, END_X, END_Y, PAPER_CURVES, PAPER_SCALES,
                                 CurveTangent, Program, anchored_e, program, steps)
from interp.simulation.runner import run_cocotb
from interp.testing.tbkit import TB, scoreboard, seeded_rng

IDLE = dict(vars(Program(0, 0, 0, 0, 0, 0, 0, 0, 0)), start=0, tick=0)


class CurveTB(TB):
    def __init__(self, dut):
        super().__init__(dut)
        self.width, self.pw, self.cw = int(dut.WIDTH.value), int(dut.PW.value), int(dut.CW.value)

    async def reset(self, idle=IDLE, cycles=2):
        await super().reset(idle, cycles)
        self.ref = CurveTangent(self.width, self.pw, self.cw)   # follows the DUT across moves

    async def check_move(self, prog: Program, tick=lambda c: 1, context=""):
        """Scoreboard one move; its steps must be the step-level model's, its end the same."""
        samples = await scoreboard(self, self.ref, move(prog.inputs(), tick, max_cycles=200_000),
                                   context=context or str(prog))
        want = steps(prog.as_ports(self.width, self.pw, self.cw), self.width, self.pw)
        got = [s for s in samples if s["step_x"] or s["step_y"]]
        assert len(got) == len(want.steps), f"{context}: {len(got)} steps, model {len(want.steps)}"
        for n, (s, w) in enumerate(zip(got, want.steps)):
            dx = (-1 if s["dir_x"] else 1) * s["step_x"]
            dy = (-1 if s["dir_y"] else 1) * s["step_y"]
            assert (dx, dy, s["x_q"], s["y_q"], s["e_q"]) == (w.dx, w.dy, w.x, w.y, w.e), \
                f"{context} step {n + 1}: rtl {s}, points 1-9 {w}"
        ends = [s for s in samples if s["done"]]
        assert len(ends) == 1 and ends[0]["error"] == int(want.error is not None), \
            f"{context}: done/error {ends}, model stop {want.error}"
        return samples, want


async def setup(dut):
    tb = CurveTB(dut)
    await tb.reset()
    return tb


@cocotb.test()
async def paper_curves(dut):
    """The paper's four curves at its four scalings, both modes (first 250 steps of each)."""
    tb = await setup(dut)
    for name in PAPER_CURVES:
        for a, b in PAPER_SCALES:
            for improved in (0, 1):
                prog = program(CURVES[name], a, b, improved=bool(improved))
                prog.count, prog.end_sel = min(prog.count, 250), END_X
                await tb.check_move(prog, context=f"{name} A={a} B={b} improved={improved}")


@cocotb.test()
async def conics_and_lines(dut):
    """Ellipse, circle, parabola, line, both directions and modes, to their end coordinate."""
    tb = await setup(dut)
    for name, a, b in [("ellipse", 40, 25), ("circle", 50, 50), ("parabola", 30, 20), ("line", 17, 40),
                       ("line", -23, 9)]:
        spec = CURVES[name]
        for improved in (0, 1):
            for reverse in (0, 1):
                prog = program(spec, a, b, improved=bool(improved), reverse=bool(reverse))
                if reverse:      # the other way round: end on the mirrored coordinate
                    prog.end_coord = -prog.end_coord
                prog.count = min(prog.count, 400)
                _, want = await tb.check_move(prog, context=f"{name} {a} {b} imp={improved} rev={reverse}")
                assert want.error is None or tb.pw < 24, "a small build may overflow"
        # every step of the improved mode stays near the true curve
        prog = program(spec, a, b, improved=True)
        for s in steps(prog).steps:
            from interp.models.curve import distance
            assert distance(spec, a, b, s.x, s.y) < 1.0, f"{name}: ({s.x}, {s.y}) off the curve"


@cocotb.test()
async def random_coefficients(dut):
    """Random projections and coefficients within the width, random tick, all end modes."""
    tb = await setup(dut)
    rng = seeded_rng(dut, "random_coefficients")
    half_p, half_x = 1 << (tb.pw - 1), 1 << (tb.width - 1)
    for n in range(120):
        big = rng.random() < 0.3            # full-width values: overflows are defined stops
        lim = half_p - 1 if big else 1000
        cl = half_p - 1 if big else 8
        prog = Program(
            x0=rng.randint(-half_x, half_x - 1) if big else rng.randint(-50, 50),
            y0=rng.randint(-half_x, half_x - 1) if big else rng.randint(-50, 50),
            p0=rng.randint(-lim - 1, lim), q0=rng.randint(-lim - 1, lim),
            dp_dx=rng.randint(-cl - 1, cl), dp_dy=rng.randint(-cl - 1, cl),
            dq_dx=rng.randint(-cl - 1, cl), dq_dy=rng.randint(-cl - 1, cl),
            count=rng.randint(0, 60), end_sel=rng.choice([END_COUNT, END_X, END_Y]),
            end_coord=rng.randint(-50, 50), reverse=rng.randint(0, 1), improved=rng.randint(0, 1),
            e_load=int(rng.random() < 0.2), e_init=rng.randint(-lim, lim))
        await tb.check_move(prog, tick=lambda c: rng.random() < 0.7, context=f"random #{n} {prog}")


@cocotb.test()
async def bad_input(dut):
    """Each bad input ends the move with done + error and no step beyond it."""
    tb = await setup(dut)
    hi_x, hi_p = (1 << (tb.width - 1)) - 1, (1 << (tb.pw - 1)) - 1
    cases = {
        "end_sel 3": Program(0, 0, 5, 3, 0, 0, 0, 0, 10, end_sel=3),
        "no tangent (both projections zero)": Program(0, 0, 0, 0, 1, 1, 1, 1, 10),
        "leaves the coordinate range": Program(hi_x - 3, 0, 7, 0, 0, 0, 0, 0, 10),
        "leaves it downwards": Program(-hi_x - 1 + 2, 5, -7, 1, 0, 0, 0, 0, 10),
        "projection overflows": Program(0, 0, hi_p - 2, 1, 1, 0, 0, 0, 10),
        "E overflows": Program(0, 0, 5, 0, 3, 0, 0, 0, 10, e_load=1, e_init=(1 << (tb.pw + 3)) - 2),
    }
    for what, prog in cases.items():
        samples, want = await tb.check_move(prog, context=what)
        assert want.error is not None and samples[-3]["done"] and samples[-3]["error"], what
        assert len(want.steps) < prog.count
    # an off-curve start is not an error: the core follows the neighbouring curve of the
    # tangent field (exponent family: y = y0·e^((x-x0)/B)); the CLI rejects it (tested there).
    prog = program(CURVES["exponent"], 100, 10, x0=0, y0=130, end=(END_X, 10))
    _, want = await tb.check_move(prog, context="off-curve start")
    assert want.error is None
    # count 0: done at once, no step (a documented no-op)
    samples, _ = await tb.check_move(Program(0, 0, 5, 3, 0, 0, 0, 0, 0), context="count 0")
    assert not any(s["step_x"] or s["step_y"] or s["error"] for s in samples)


@cocotb.test()
async def reanchor(dut):
    """Segments restarted with E from the true curve (e_load) follow the curve as one move."""
    tb = await setup(dut)
    spec, a, b = CURVES["hyperbola"], 100, 10
    x, y = spec.start(a, b)
    while x < 40:
        prog = program(spec, a, b, x0=x, y0=y, count=8, improved=True)
        prog.e_load, prog.e_init = 1, anchored_e(spec, a, b, x, y)
        _, want = await tb.check_move(prog, context=f"segment at ({x}, {y})")
        x, y = want.steps[-1].x, want.steps[-1].y


@cocotb.test()
async def start_while_busy_is_ignored(dut):
    tb = await setup(dut)
    prog = program(CURVES["circle"], 20, 20, improved=True)
    other = program(CURVES["line"], 5, 7)

    def stim():
        sample = yield {**prog.inputs(), "start": 1, "tick": 1}
        cycle = 1
        while not sample["done"]:
            sample = yield {**other.inputs(), "start": int(cycle % 3 == 0), "tick": 1}
            cycle += 1
        yield {**other.inputs(), "start": 0, "tick": 1}

    samples = await scoreboard(tb, tb.ref, stim(), context="start while busy")
    got = [s for s in samples if s["step_x"] or s["step_y"]]
    assert len(got) == len(steps(prog).steps) and samples[-2]["y_q"] == 20


@cocotb.test()
async def reset_at_any_cycle(dut):
    """rst in any cycle of a move returns to idle; no step after it."""
    tb = await setup(dut)
    prog = program(CURVES["parabola"], 6, 4)
    for k in range(0, 14):
        await tb.reset()
        try:
            await scoreboard(tb, tb.ref, move(prog.inputs(), max_cycles=k), context=f"reset at {k}")
        except RuntimeError:
            pass
        tb.drive({"rst": 1, "start": 0})
        await FallingEdge(dut.clk)
        tb.drive({"rst": 0, "tick": 1})
        for _ in range(12):
            await FallingEdge(dut.clk)
            s = tb.sample(CurveTangent.watch)
            assert not (s["step_x"] or s["step_y"] or s["busy"] or s["done"] or s["error"]), f"reset at {k}: {s}"


@pytest.mark.parametrize("width,pw", [(16, 24), (8, 10)])
def test_curve_tangent(sim, width, pw):
    run_cocotb(toplevel="curve_tangent", test_module="test_curve_tangent", sim=sim,
               parameters={"WIDTH": width, "PW": pw, "CW": 24}, name=f"curve_tangent_w{width}_p{pw}")
