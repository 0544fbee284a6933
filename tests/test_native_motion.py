# SPDX-License-Identifier: Apache-2.0
"""The native Verilator harness of motion_top (interp.simulation.native) against cocotb on Icarus.

Both run the same command file at the CLI build (32-bit fields, FRAC = 32) and
must write byte-identical steps CSVs and the same results (cycles, position,
errors, events); the harness's quiet-stretch skipping must not change anything
(compared with --exact).  Also: the max_cycles stop, a malformed command
file, an empty one.  The Verilator build (about a minute) is made once per
machine and source and shared by every test.
"""
import math
import os
import random
import shutil

import pytest

from interp.testing.seeds import seeded_random
from interp.cores import UsageError
from interp.models.motion import Command
from interp.models.profile import profile_for
from interp.models.speed_ramp import BLOCK_SHIFT_MIN
from interp.simulation.native import CLI_PARAMETERS, command_row, executable, run_cocotb_job, run_native, write_commands
from interp.simulation.native.build import ports
from interp.simulation.runner import RTL

pytestmark = pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus Verilog")

FEATURES = ports(RTL)
PARAMS = CLI_PARAMETERS
ONE = 1 << PARAMS["FRAC"]                       # feed of 1 step per clock
TIMING = (3, 2, 4)                              # pulse width, dir setup, dir hold (cycles)
QUANTUM = ONE >> 12                             # A: 2^-12 steps per clock
ACCEL = QUANTUM / 4                             # path units per clock^2
SETTINGS = {"speed_quantum": QUANTUM, "block_shift": BLOCK_SHIFT_MIN, "jerk_shift": 0, "override": 100}


def profiled(rows, accel=ACCEL, quantum=QUANTUM, lecture=True):  # noqa: D103
    """Rows of 10 fields (kind plane feed x y z i j k l) -> 16 with bench profiles."""
    cmds = [Command(r[0], r[2], *r[3:10], plane=r[1]) for r in rows]
    cmds = profile_for(cmds, quantum=quantum, accel=accel, frac=PARAMS["FRAC"], pf=PARAMS["PF"],
                       width=PARAMS["W"], lecture=lecture, feed_w=PARAMS["FEED_W"],
                       feed_max=(1 << PARAMS["FEED_W"]) - 1)
    return [command_row(c) for c in cmds]


@pytest.fixture(scope="session")
def native():
    return executable(PARAMS)


def random_job(rng: random.Random, n: int) -> list[tuple[int, ...]]:
    """Lines, arcs (quarter, half, three-quarter, full; planes and helices when the RTL has
    them), dwells, events, a few bad commands; mostly fast feeds, some slow."""
    jobs = []
    for _ in range(n):
        feed = rng.randrange(ONE // 8, ONE) if rng.random() < 0.95 else ONE // rng.randrange(20, 200)
        r = rng.random()
        if r < 0.45:
            jobs.append((0, 0, feed, *(rng.randint(-25, 25) for _ in range(3)), 0, 0, 0, 0))
        elif r < 0.8:
            i, j = rng.randint(-12, 12), rng.randint(-12, 12)
            if i == j == 0:
                i = 5
            turn = rng.randrange(4)
            end = [(i + j, j - i), (2 * i, 2 * j), (i - j, j + i), (0, 0)][turn]
            ccw = rng.random() < 0.5
            if ccw and turn in (0, 2):              # the quarter / three-quarter ends swap for CCW
                end = [(i - j, j + i), None, (i + j, j - i)][turn]
            plane = rng.randrange(3) if "plane" in FEATURES else 0
            helix = rng.randint(-10, 10) if "plane" in FEATURES and rng.random() < 0.3 else 0
            count = max(1, round(2 * math.hypot(i, j) * (turn + 1)))
            jobs.append((2 if ccw else 1, plane, feed, *end, helix, i, j, count if helix else 0, 0))
        elif r < 0.88:
            jobs.append((4, 0, 0, rng.randint(0, 40), 0, 0, 0, 0, 0, 0))
        elif r < 0.96 and "events" in FEATURES:
            jobs.append((5, 0, 0, rng.randrange(256), rng.randint(-(1 << 31), (1 << 31) - 1), 0, 0, 0, 0, 0))
        else:
            jobs.append(bad_command(rng, feed))
    for _ in range(2):                               # every job has refused commands
        jobs.insert(rng.randrange(len(jobs) + 1), bad_command(rng, ONE // 2))
    return jobs


def bad_command(rng: random.Random, feed: int) -> tuple[int, ...]:
    """A command the RTL refuses: kind 6, a move of feed 0 (and an arc in plane 3)."""
    return rng.choice([(6, 0, feed, 1, 1, 0, 0, 0, 0, 0), (0, 0, 0, 3, 4, 0, 0, 0, 0, 0)]
                      + ([(1, 3, feed, 0, 0, 0, 4, 0, 0, 0)] if "plane" in FEATURES else []))


def refused(rows) -> int:
    """How many commands of a job the RTL refuses (bad_command's kinds)."""
    return sum(kind == 6 or kind in (0, 1, 2) and feed == 0 or kind in (1, 2) and plane not in AXES
               for kind, plane, feed, *_ in rows)


AXES = {0: (0, 1, 2), 1: (2, 0, 1), 2: (1, 2, 0)}    # plane -> the axes of (u, v, w)


def end_point(rows) -> list[int]:
    """Where the accepted moves of a job end."""
    pos = [0, 0, 0]
    for kind, plane, feed, x, y, z, *_ in rows:
        if kind == 0 and feed:
            pos = [p + d for p, d in zip(pos, (x, y, z))]
        elif kind in (1, 2) and feed and plane in AXES:
            for axis, d in zip(AXES[plane], (x, y, z)):
                pos[axis] += d
    return pos


def both(tmp_path, rows, max_cycles=2_000_000, name="job", timing=TIMING, settings=SETTINGS, controls=(),
         push_interval=1):
    """The result of one job (rows of 10 fields get bench profiles), natively, natively
    without skipping (--exact) and on Icarus: the same steps CSV and the same results."""
    commands = tmp_path / f"{name}.txt"
    write_commands(commands, profiled(rows) if rows and len(rows[0]) == 10 else rows)
    extra = {"settings": settings, "controls": controls, "push_interval": push_interval}
    got = run_native(commands, steps_path=tmp_path / f"{name}_native.csv", timing=timing,
                     max_cycles=max_cycles, parameters=PARAMS, **extra)
    exact = run_native(commands, steps_path=tmp_path / f"{name}_exact.csv", timing=timing,
                       max_cycles=max_cycles, parameters=PARAMS, exact=True, **extra)
    want = run_cocotb_job(commands, "icarus", timing, tmp_path / f"{name}_icarus.csv", max_cycles,
                          parameters=PARAMS, **extra)
    texts = [(tmp_path / f"{name}_{k}.csv").read_bytes() for k in ("native", "exact", "icarus")]
    assert texts[0] == texts[1], "quiet-stretch skipping changed the steps"
    assert texts[0] == texts[2], "native and Icarus steps differ"
    for r in (got, exact, want):
        r.pop("skipped")
    assert got == exact == want
    return got


def test_random_jobs_native_equals_icarus(native, tmp_path):
    rng, seed = seeded_random()
    size = 300 if os.environ.get("INTERP_TEST_ALL") else 80      # make test-all: the long job
    rows = random_job(rng, size)
    got = both(tmp_path, rows)
    print(f"{got['cycles']} cycles, {got['steps']} steps, {len(got['errors'])} errors, {len(got['events'])} events")
    assert not got["stopped"] and got["pushed"] == got["dispatched"] == got["commands"] == len(rows)
    assert got["steps"] > 3 * size
    assert len(got["errors"]) == refused(rows) >= 2, "every bad command is refused, and only those"
    assert got["position"] == end_point(rows)
    if "events" in FEATURES:
        assert len(got["events"]) == sum(r[0] == 5 for r in rows)


def test_paced_pushes_native_equals_icarus(native, tmp_path):
    """push_interval 85 (the controller's record unpacker at the default build): natively,
    without skipping and on Icarus the same steps and results; the moves end where they do
    unpaced; a burst of events is pushed, and so run, exactly 85 cycles apart."""
    rng, _ = seeded_random()
    rows = random_job(rng, 40)
    paced, free = both(tmp_path, rows, name="paced", push_interval=85), both(tmp_path, rows, name="free")
    assert paced["position"] == free["position"] == end_point(rows)
    assert paced["steps"] == free["steps"] and paced["cycles"] >= free["cycles"]
    if "events" in FEATURES:
        burst = [(5, 0, 0, 200 + k, 0, 0, 0, 0, 0, 0) for k in range(4)]
        cycles = [e[0] for e in both(tmp_path, burst, name="burst", push_interval=85)["events"]]
        assert [b - a for a, b in zip(cycles, cycles[1:])] == [85] * 3, cycles
    with pytest.raises(UsageError, match="push-interval"):
        run_native(tmp_path / "paced.txt", steps_path=tmp_path / "s.csv", timing=TIMING, max_cycles=100,
                   parameters=PARAMS, push_interval=0)


def slow(feed):
    """Settings and profile arguments for a slow job: the quantum an eighth of the feed, the
    rate 2^20 (a quantum every 64 clocks: the ramp's DDA phase comes back every 2^4 blocks,
    which the skipping of dwells needs)."""
    quantum = max(1, feed // 8)
    return {**SETTINGS, "speed_quantum": quantum}, {"quantum": quantum, "accel": quantum / 64}


def test_slow_job_with_dwell(native, tmp_path):
    """A few steps at 1 step per 3000 cycles and a long dwell: the dwell is skipped, the slow
    moves are not (only rest is skipped); the same as every cycle simulated."""
    feed = ONE // 3000
    settings, args = slow(feed)
    # (a dwell of 4 * 10^6 cycles: at rest the state repeats every 2^MW blocks of 4 clocks)
    rows = [(0, 0, feed, 7, -3, 2, 0, 0, 0, 0), (2, 0, feed, 0, 0, 0, 3, 0, 0, 0), (4, 0, 0, 4 * 10**6, 0, 0, 0, 0, 0, 0),
            (0, 0, feed, -1, 0, 0, 0, 0, 0, 0)]
    commands = tmp_path / "slow.txt"
    write_commands(commands, profiled(rows, **args))
    got = run_native(commands, steps_path=tmp_path / "a.csv", timing=TIMING, max_cycles=10**7, parameters=PARAMS,
                     settings=settings)
    exact = run_native(commands, steps_path=tmp_path / "b.csv", timing=TIMING, max_cycles=10**7,
                       parameters=PARAMS, exact=True, settings=settings)
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()
    assert 0.9 * 4 * 10**6 < got["skipped"] < 4 * 10**6 and exact.pop("skipped") == 0
    got.pop("skipped")
    assert got == exact and got["position"] == [6, -3, 2] and not got["stopped"]


def test_dwell_and_event_drain_skip(native, tmp_path, monkeypatch):
    """At rest (a dwell after the speed reached 0) the state other than the counters repeats
    every few cycles: those stretches are skipped, exactly (the same as Icarus and as every
    cycle simulated).  No steps file asked for: none written."""
    rows = [(0, 0, ONE // 7, 5, 2, 0, 0, 0, 0, 0), (4, 0, 0, 20_000, 0, 0, 0, 0, 0, 0),
            (5, 0, 0, 3, 9, 0, 0, 0, 0, 0), (4, 0, 0, 1000, 0, 0, 0, 0, 0, 0), (0, 0, ONE // 5, -5, 1, 0, 0, 0, 0, 0)]
    got = both(tmp_path, rows, max_cycles=10**6, name="dwell")
    assert got["position"] == [0, 3, 0] and got["events"] and not got["stopped"]
    write_commands(tmp_path / "long.txt", profiled([(4, 0, 0, 10**9, 0, 0, 0, 0, 0, 0)]))
    monkeypatch.chdir(tmp_path)
    long = run_native(tmp_path / "long.txt", steps_path=None, timing=TIMING, max_cycles=2 * 10**9, parameters=PARAMS)
    assert long["cycles"] > 10**9 and long["skipped"] > 0.999 * 10**9
    assert not (tmp_path / "None").exists()


@pytest.mark.parametrize("timing", [(40, 30, 120), (1, 0, 0), (200, 0, 300)])
def test_slow_reversals_with_long_timing(native, tmp_path, timing):
    """Quiet stretches in every state of the output stage (pulse, dir hold and setup waits)
    and in a dwell: skipping must stop exactly where a counter acts (Icarus and --exact agree)."""
    feed = ONE // 450
    rows = [(0, 0, feed, 3 - 6 * (k % 2), 2 - 4 * (k % 2), 1 - 2 * (k % 2), 0, 0, 0, 0) for k in range(4)]
    rows += [(1, 0, feed, 0, 0, 0, 2, 1, 0, 0), (4, 0, 0, 3000, 0, 0, 0, 0, 0, 0),
             (0, 0, ONE // 3, -4, 0, 0, 0, 0, 0, 0), (0, 0, ONE // 3, 4, 1, 0, 0, 0, 0, 0)]
    got = both(tmp_path, rows, timing=timing)
    assert got["position"] == end_point(rows) and not got["errors"]


def test_max_cycles_stop(native, tmp_path):
    rows = [(0, 0, ONE // 4, 20, 10, 0, 0, 0, 0, 0)] * 8
    got = both(tmp_path, rows, max_cycles=150)
    assert got["stopped"] and got["cycles"] == 150 and got["errors"] == []
    assert 0 < got["dispatched"] < len(rows) and got["pushed"] <= len(rows)


def test_empty_command_file(native, tmp_path):
    got = both(tmp_path, [])
    assert got == {"cycles": 1, "position": [0, 0, 0], "errors": [], "events": [], "steps": 0,
                   "stopped": False, "pushed": 0, "dispatched": 0, "commands": 0, "hold_stops": []}
    assert (tmp_path / "job_native.csv").read_text() == "cycle,dx,dy,dz\n"


TAIL = " 100 0 4096 0 65536 7"     # limit exit rate cost length budget


@pytest.mark.parametrize("text, where", [
    (f"0 0 100 1 2 3 0 0 0 0{TAIL}\n0 0 5 1 2\n", "line 2: want 16 integers"),
    ("0 0 100 1 2 3 0 0 0 0\n", "line 1: want 16 integers"),
    (f"0 0 100 1 2 3 0 0 0 x{TAIL}\n", "line 1: want 16 integers"),
    (f"\n9 0 100 1 2 3 0 0 0 0{TAIL}\n", "line 2: kind 9 is out of range"),
    (f"0 0 -5 1 2 3 0 0 0 0{TAIL}\n", "line 1: feed -5 is out of range"),
    (f"0 0 1 {1 << 40} 0 0 0 0 0 0{TAIL}\n", f"line 1: x {1 << 40} is out of range"),
    (f"0 0 1 1 0 0 0 0 0 0 1 0 1 0 {1 << 66} 1\n", f"line 1: length {1 << 66} is out of range"),
    ("0 0 1 1 0 0 0 0 0 0 1 0 1 0 1 -1\n", "line 1: budget -1 is out of range"),
])
def test_bad_command_file(native, tmp_path, text, where):
    commands = tmp_path / "bad.txt"
    commands.write_text(text)
    with pytest.raises(UsageError) as err:
        run_native(commands, steps_path=tmp_path / "s.csv", timing=TIMING, max_cycles=100, parameters=PARAMS)
    message = str(err.value)
    assert "\n" not in message and message.startswith(f"{commands} {where}"), message


def test_progress_callback(native, tmp_path):
    """A 12-step line at 1 step per 10^6 cycles: progress every 2^22 cycles while it runs."""
    commands = tmp_path / "long.txt"
    settings, args = slow(ONE // 1_000_000)
    write_commands(commands, profiled([(0, 0, ONE // 1_000_000, 12, 5, 0, 0, 0, 0, 0)], **args))
    calls = []
    got = run_native(commands, steps_path=tmp_path / "s.csv", timing=TIMING, max_cycles=10**9,
                     parameters=PARAMS, progress=lambda *a: calls.append(a), settings=settings)
    assert got["steps"] == 12 and got["cycles"] > 11_000_000
    assert len(calls) >= 2 and all(c[0] >= 1 << 22 and c[2] == 1 for c in calls)
    assert [c[0] for c in calls] == sorted({c[0] for c in calls}) and calls[-1][0] < got["cycles"]
    assert [c[1] for c in calls] == sorted(c[1] for c in calls) and 0 < calls[-1][1] <= 12


def test_holds_and_override_native_equals_icarus(native, tmp_path):
    """Feed holds, resumes and override changes from a controls schedule: the same steps CSV
    and the same hold_stops natively, without skipping and on Icarus; every step out once."""
    rng, seed = seeded_random()
    rows = [r for r in random_job(rng, 40) if r[0] != 6 and r[2] != 0 or r[0] in (4, 5)]
    controls, cycle = [], 0
    for _ in range(6):
        cycle += rng.randint(200, 3000)
        controls.append((cycle, "hold", 0))
        cycle += rng.randint(1, 4000)
        controls.append((cycle, "resume", 0))
        cycle += rng.randint(1, 500)
        controls.append((cycle, "override", rng.choice([30, 100, 150, 200])))
    got = both(tmp_path, rows, name="holds", controls=controls)
    assert not got["stopped"] and got["position"] == end_point(rows)
    holds = got["hold_stops"]
    assert [h[0] for h in holds] == [c[0] for c in controls if c[1] == "hold" and c[0] < got["cycles"]]
    assert holds, "no hold came while the job ran"
    for hold, stopped, steps in holds:
        assert stopped is None or (stopped > hold and steps >= 0)
