# SPDX-License-Identifier: Apache-2.0
"""SU 1665343 circular interpolator: RTL vs cycle model vs the patent's equations and Table 2.

cocotb scoreboards every cycle here (Table 2, the sector switches, start
points, bad input, reset, a random sample of R); `test_sweep` runs every R of
the range through a native harness (sim/sweep_su1665343.v) and compares the
step sequences with the step-level model.
"""
import math
import subprocess

import cocotb
import pytest
from cocotb.triggers import FallingEdge

from interp.models.base import move, steps_of
from interp.models.su1665343 import (Su1665343, expected_per_step, move_cycles, path_string,
                                     per_step, r_max, radial_error, setup_cycles, start_error, steps,
                                     trace)
from interp.testing.tbkit import TB, scoreboard, seeded_rng

# Patent Table 2 (R = 12): (step, kind, CT7, CT8, commutator code, F after).
TABLE2 = [
    ("1", "y", 1, 10, -3, 7.75), ("2", "y", 2, 9, -5, 2.75), ("3", "y", 3, 8, -7, -4.25),
    ("4", "diagonal", 4, 6, 13, 8.75), ("5", "y", 5, 5, -11, -2.25),
    ("6", "diagonal", 6, 3, 7, 4.75), ("7", "y", 7, 2, -15, -10.25),
    ("8", "diagonal", 8, 0, 1, -9.25), ("9", "diagonal", 9, -1, -3, -12.25),
    ("9a", "correction", 8, -1, 17, 4.75), ("9b", "correction", 7, -1, None, 4.75),
    ("10", "diagonal", 6, -3, -7, -2.25), ("11", "x", 5, -4, 11, 8.75),
    ("12", "diagonal", 4, -6, -13, -4.25), ("13", "x", 3, -7, 7, 2.75),
    ("14", "diagonal", 2, -9, -19, -16.25), ("15", "x", 1, -10, 3, -13.25),
    ("16", "x", 0, -11, 1, -12.25), ("17", "x", -1, -12, None, None),
]
TABLE2_PATH = "YYYDYDYDDDXDXDXXX"
# All three sector-switch cases of the patent: A after a Y step, A after a diagonal, B.
SWITCH_CASES = {4: ("A", "y"), 11: ("A", "y"), 134: ("A", "y"), 3: ("A", "diagonal"),
                6: ("A", "diagonal"), 10: ("A", "diagonal"), 1: ("B", "diagonal"),
                5: ("B", "diagonal"), 12: ("B", "diagonal")}
IDLE = {"start": 0, "tick": 0, "r": 0, "x0": 0, "y0": 0}


class CircTB(TB):
    def __init__(self, dut):
        super().__init__(dut)
        self.width = int(dut.WIDTH.value)
        self.rmax = r_max(self.width)
        self.worst_error = 0.0

    async def reset(self, idle=IDLE, cycles=2):
        await super().reset(idle, cycles)
        self.ref = Su1665343(self.width)     # follows the DUT across moves

    async def check_move(self, r, x0=None, y0=None, tick=lambda c: 1, on_path=True):
        """Scoreboard one move; check steps, F per step, end point and radial error."""
        x0, y0 = (r, 0) if x0 is None else (x0, y0)
        samples = await scoreboard(self, self.ref, move({"r": r, "x0": x0, "y0": y0}, tick),
                                   context=f"R={r} from ({x0}, {y0})")
        want = steps(r, x0, y0)
        rows = trace(samples, self.width)
        assert per_step(rows) == expected_per_step(want), f"R={r} ({x0}, {y0}): {rows}"
        x, y = x0, y0
        for _, dx, dy in steps_of(samples):
            x, y = x + dx, y + dy
        assert x == 0 and sum(s["done"] for s in samples) == 1, f"R={r}: ends at ({x}, {y})"
        if on_path:
            assert y == r, f"R={r} from ({x0}, {y0}): ends at ({x}, {y})"
            err = radial_error(r, want, x0, y0)
            assert err < 0.5, f"R={r}: radial error {err}"
            self.worst_error = max(self.worst_error, err)
        assert not any(s["error"] for s in samples)
        return samples, rows


async def setup(dut):
    tb = CircTB(dut)
    await tb.reset()
    return tb


@cocotb.test()
async def table2(dut):
    """R = 12 reproduces the patent's Table 2 row by row and its step path."""
    tb = await setup(dut)
    samples, rows = await tb.check_move(12)
    got = [(r["step"], r["kind"], r["ct7"], r["ct8"], r["code"], r["f"]) for r in rows]
    assert got == TABLE2, "\n".join(map(str, got))
    assert path_string(steps(12)) == TABLE2_PATH
    path = "".join("D" if s["step_x"] and s["step_y"] else "X" if s["step_x"] else "Y"
                   for s in samples if s["step_x"] or s["step_y"])
    assert path == TABLE2_PATH, path
    done = [i for i, s in enumerate(samples) if s["done"]]
    assert done == [move_cycles(steps(12), tb.width)], done
    pulses = [i for i, s in enumerate(samples) if s["step_x"] or s["step_y"]]
    assert pulses[0] == setup_cycles(tb.width) + 2, pulses[0]     # load, pulse, strobe
    dut._log.info("R=12: Table 2 matched, %d cycles for %d steps", done[0], len(TABLE2_PATH))


@cocotb.test()
async def sector_switch_cases(dut):
    """Each of the three sector-switch cases, against the step-level model."""
    tb = await setup(dut)
    for r, (case, kind) in SWITCH_CASES.items():
        if r > tb.rmax:
            continue
        switches = [(s.switch, s.kind) for s in steps(r) if s.switch]
        assert switches == [(case, kind)], f"R={r}: {switches}"
        await tb.check_move(r)


@cocotb.test()
async def every_small_r_and_random_sample(dut):
    """Every R up to 40 (the whole range at small widths), then a random sample, random tick."""
    tb = await setup(dut)
    rng = seeded_rng(dut, "every_small_r_and_random_sample")
    for r in range(1, min(40, tb.rmax) + 1):
        await tb.check_move(r)
    for _ in range(3):
        r = rng.randint(1, tb.rmax)
        await tb.check_move(r, tick=lambda c: rng.random() < 0.8)
    await tb.check_move(tb.rmax)
    dut._log.info("max radial error over these moves: %.4f", tb.worst_error)


@cocotb.test()
async def start_points(dut):
    """Starts inside the quadrant on either side of 45° (points of the R path), and
    starts off the path but within one step of the circle."""
    tb = await setup(dut)
    for r in [r for r in (12, 13, 40, 99) if r <= tb.rmax]:
        path = steps(r)
        points = [(p.x, p.y) for p in path[:-1]]
        below = [p for p in points if p[0] > p[1]]
        above = [p for p in points if p[1] >= p[0]]
        for x0, y0 in {below[0], below[len(below) // 2], below[-1], above[0], above[len(above) // 2],
                       above[-1]}:
            await tb.check_move(r, x0, y0)
        await tb.check_move(r, 0, r)                 # at the end point already: no step
        for x0, y0 in ((r + 1, 0), (r - 1, 0), (r - 1, 1), (1, r)):
            await tb.check_move(r, x0, y0, on_path=False)
    if tb.width == 5:           # every start point the core accepts, for every R
        for r in range(1, tb.rmax + 1):
            for x0 in range(r + 2):
                for y0 in range(r + 2):
                    if start_error(r, x0, y0, tb.width) is None:
                        await tb.check_move(r, x0, y0, on_path=(x0, y0) in on_path(r))


def on_path(r):
    """Points of the arc from (R, 0): starting there must end at (0, R) within 0.5."""
    return {(r, 0)} | {(p.x, p.y) for p in steps(r)}


@cocotb.test()
async def bad_input(dut):
    """R = 0, R too large, start point off the circle: `error` after the set-up (busy only
    during it), no step, no `done`; then a good move."""
    tb = await setup(dut)
    mask = (1 << tb.width) - 1
    bad = [(0, 0, 0), (0, 5, 0), (tb.rmax + 1, tb.rmax + 1, 0), (mask, mask, 0),
           (12, 10, 0), (12, 14, 0), (12, 0, 0), (12, 12, 12), (3, mask, 0), (3, 0, mask)]
    for r, x0, y0 in bad:
        samples = await scoreboard(tb, tb.ref, move({"r": r, "x0": x0, "y0": y0}, end="error",
                                                    idle_after=10), context=f"bad R={r} ({x0}, {y0})")
        set_up = setup_cycles(tb.width)
        assert [i for i, s in enumerate(samples) if s["error"]] == [set_up + 1]
        assert [i for i, s in enumerate(samples) if s["busy"]] == list(range(1, set_up + 1))
        assert not any(s["step_x"] or s["step_y"] or s["done"] for s in samples), \
            f"bad R={r} ({x0}, {y0}) moved"
    await tb.check_move(5)


@cocotb.test()
async def refused_starts(dut):
    """The load former's checks (E = R^2 - X^2 - Y^2 against 2R - 1 and -2R - 1) against
    start_error(): every point just outside the band (R-1)^2 .. (R+1)^2, R = 0 .. 2^WIDTH - 1
    at WIDTH 5 (a sample of R and X at WIDTH 12), and random inputs over the whole range."""
    tb = await setup(dut)
    rng = seeded_rng(dut, "refused_starts")
    mask = (1 << tb.width) - 1
    radii = range(mask + 1) if tb.width <= 5 else [0, 1, 2, 12, 1000, tb.rmax, tb.rmax + 1, mask]
    triples = []
    for r in radii:
        xs = range(0, min(r + 3, mask + 1))
        for x0 in xs if len(xs) <= 40 else sorted(rng.sample(xs, 12)) + [0, r, min(r + 1, mask)]:
            inner = (r - 1) ** 2 - x0 * x0          # y0^2 >= inner and <= outer are accepted
            outer = (r + 1) ** 2 - x0 * x0
            lo = math.isqrt(inner - 1) if inner > 0 else None
            hi = math.isqrt(outer) + 1 if outer >= 0 else 0
            triples += [(r, x0, y) for y in (lo, hi) if y is not None and y <= mask]
    triples += [(rng.randint(0, mask), rng.randint(0, mask), rng.randint(0, mask)) for _ in range(40)]
    refused = 0
    for r, x0, y0 in triples:
        if start_error(r, x0, y0, tb.width) is None:
            continue
        refused += 1
        samples = await scoreboard(tb, tb.ref, move({"r": r, "x0": x0, "y0": y0}, end="error",
                                                    idle_after=0), context=f"bad R={r} ({x0}, {y0})")
        assert samples[-1]["error"], f"R={r} ({x0}, {y0}) accepted"
    dut._log.info("%d refused starts checked", refused)


@cocotb.test()
async def start_while_busy_is_ignored(dut):
    """A second start (even a bad one) during a move changes nothing."""
    tb = await setup(dut)

    def stim():
        sample = yield {"r": 10, "x0": 10, "y0": 0, "start": 1, "tick": 1}
        cycle = 1
        while not sample["done"]:
            sample = yield {"r": 3 + cycle % 2 * 1000, "x0": 0, "y0": 3,
                            "start": int(cycle % 2 == 0), "tick": 1}
            cycle += 1
        yield {"r": 0, "x0": 0, "y0": 0, "start": 0, "tick": 1}

    samples = await scoreboard(tb, tb.ref, stim(), context="start while busy")
    assert sum(s["step_x"] for s in samples) == 10 and sum(s["step_y"] for s in samples) == 10
    assert not any(s["error"] for s in samples)


@cocotb.test()
async def reset_at_any_cycle(dut):
    """rst in any cycle of a move (both switch cases) returns to idle; no step after it."""
    tb = await setup(dut)
    for r in (4, 5):
        for k in range(move_cycles(steps(r), tb.width) + 2):
            await tb.reset()
            try:
                await scoreboard(tb, tb.ref, move({"r": r, "x0": r, "y0": 0}, max_cycles=k),
                                 context=f"R={r} reset at {k}")
            except RuntimeError:
                pass
            tb.drive({"rst": 1, "start": 0})
            await FallingEdge(dut.clk)
            tb.drive({"rst": 0, "tick": 1})
            for _ in range(12):
                await FallingEdge(dut.clk)
                s = tb.sample(Su1665343.watch)
                assert not (s["step_x"] or s["step_y"] or s["busy"] or s["done"] or s["error"]), \
                    f"R={r} reset at {k}: {s}"
                assert s["ct7"] == s["ct8"] == s["f"] == s["t16"] == 0
        await tb.reset()
        await tb.check_move(r)


@pytest.mark.parametrize("width", [5, 12])
def test_circ_su1665343(sim, width):
    from interp.simulation.runner import run_cocotb
    run_cocotb(toplevel="circ_su1665343", test_module="test_circ_su1665343", sim=sim,
               parameters={"WIDTH": width}, name=f"circ_su1665343_w{width}")


# Every R: 1 .. 2000 on Verilator, 1 .. 300 on Icarus (slower per cycle).
SWEEP = {"verilator": 2000, "icarus": 300}


def test_sweep(sim, tmp_path):
    """Native harness: each R's step sequence and cycle count against the step-level model."""
    from interp.simulation.speed import build_harness
    rhi = SWEEP[sim]
    out = tmp_path / "paths.txt"
    cmd = build_harness("sweep_su1665343", sim, {"SWEEP_WIDTH": 12})
    subprocess.run(cmd + ["+rlo=1", f"+rhi={rhi}", f"+out={out}"], check=True,
                   capture_output=True, text=True, timeout=240)
    lines = out.read_text().split("\n")[:-1]
    assert len(lines) == rhi, f"{len(lines)} results for {rhi} radii"
    worst = 0.0
    for line in lines:
        r, path, x, y, cycles = line.split(" ")
        r = int(r)
        want = steps(r)
        assert path == path_string(want), f"R={r}: RTL {path}\n model {path_string(want)}"
        assert (int(x), int(y)) == (0, r), f"R={r} ends at ({x}, {y})"
        assert int(cycles) == move_cycles(want, 12), f"R={r}: {cycles} cycles"
        worst = max(worst, radial_error(r, want))
    assert worst < 0.5
    print(f"R = 1 .. {rhi} on {sim}: every step sequence matches; max radial error {worst:.4f}")
