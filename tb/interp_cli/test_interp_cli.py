# SPDX-License-Identifier: Apache-2.0
"""The `interp` command line contract: files, formats, RTL == model, bad arguments."""
import subprocess
import sys

import pytest

SPEC_TRACE = """step,kind,f,ctr1,ctr2
1,axial,-2.5,3,3
2,diagonal,0.5,3,2
3,axial,-1.5,2,2
4,diagonal,0.5,2,1
5,axial,-0.5,1,1
6,diagonal,0.5,1,0
7,axial,0.5,0,0
"""


def interp(*args):
    return subprocess.run([sys.executable, "-m", "interp.cli", *map(str, args)],
                          capture_output=True, text=True)


def test_model_trace_is_the_patent_table(tmp_path):
    done = interp("model", "su1571551", "--x", 7, "--y", 3, "--mode", "faithful",
                  "--steps", tmp_path / "s.csv", "--trace", tmp_path / "t.csv", "--vcd", tmp_path / "m.vcd")
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "t.csv").read_text() == SPEC_TRACE
    assert (tmp_path / "s.csv").read_text().splitlines() == [
        "cycle,dx,dy", "3,1,0", "4,1,1", "5,1,0", "6,1,1", "7,1,0", "8,1,1", "9,1,0"]
    assert "$var" in (tmp_path / "m.vcd").read_text()


@pytest.mark.parametrize("mode", ["faithful", "exact"])
def test_run_equals_model(sim, mode, tmp_path):
    files = {}
    for command in ("run", "model"):
        extra = ["--sim", sim] if command == "run" else []
        done = interp(command, "su1571551", "--x", -23, "--y", 9, "--mode", mode, *extra,
                      "--steps", tmp_path / f"{command}_s.csv", "--trace", tmp_path / f"{command}_t.csv",
                      "--vcd", tmp_path / f"{command}.vcd", "--plot", tmp_path / f"{command}.png")
        assert done.returncode == 0, done.stderr
        files[command] = [(tmp_path / f"{command}_{k}.csv").read_text() for k in "st"]
        assert (tmp_path / f"{command}.vcd").stat().st_size > 0
        assert (tmp_path / f"{command}.png").read_bytes()[:4] == b"\x89PNG"
    assert files["run"] == files["model"]
    steps = files["run"][0].splitlines()[1:]
    assert len(steps) == 23 and sum(int(r.split(",")[2]) for r in steps) == 9


@pytest.mark.parametrize("args, message", [
    (["--x", 128, "--y", 0, "--width", 8], "does not fit 8 signed bits"),
    (["--x", 1], "required: --y"),
    (["--x", "a", "--y", 1], "invalid int value"),
    (["--x", 1, "--y", 1, "--mode", "fast"], "invalid choice"),
    (["--x", 1, "--y", 1, "--width", 1], "outside 2 .. 62"),
])
def test_bad_arguments(args, message, tmp_path):
    done = interp("model", "su1571551", *args, "--steps", tmp_path / "s.csv")
    assert done.returncode == 2
    assert message in done.stderr and len(done.stderr.strip().splitlines()) == 1, done.stderr
    assert "Traceback" not in done.stderr


def test_unknown_core(tmp_path):
    done = interp("run", "nosuchcore", "--steps", tmp_path / "s.csv")
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1


def test_summary_line(sim):
    """`interp run` (no files asked for) prints one line: steps, end point, cycles, deviation."""
    done = interp("run", "circ-arc", "--cx", 0, "--cy", 0, "--x0", 30, "--y0", 0, "--x1", 0, "--y1", 30,
                  "--sim", sim)
    assert done.returncode == 0, done.stderr
    line, = done.stdout.strip().splitlines()
    assert line.startswith("circ-arc: 42 steps, end (0, 30), ") and "clock cycles" in line, line
    assert float(line.split("max deviation ")[1].split()[0]) <= 0.5


@pytest.mark.parametrize("option", ["--steps", "--plot", "--vcd", "--trace"])
def test_unwritable_output_refused_before_running(option, tmp_path):
    done = interp("model", "su1571551", "--x", 7, "--y", 3, option, tmp_path / "missing" / "out")
    assert done.returncode == 2 and "no directory" in done.stderr, done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and not done.stdout
