# SPDX-License-Identifier: Apache-2.0
"""`interp run|model su1665343`: Table 2 as the trace CSV, RTL == model, bad input messages."""
import subprocess
import sys

import pytest

TABLE2_CSV = """step,kind,ct7,ct8,code,f
1,y,1,10,-3,7.75
2,y,2,9,-5,2.75
3,y,3,8,-7,-4.25
4,diagonal,4,6,13,8.75
5,y,5,5,-11,-2.25
6,diagonal,6,3,7,4.75
7,y,7,2,-15,-10.25
8,diagonal,8,0,1,-9.25
9,diagonal,9,-1,-3,-12.25
9a,correction,8,-1,17,4.75
9b,correction,7,-1,,4.75
10,diagonal,6,-3,-7,-2.25
11,x,5,-4,11,8.75
12,diagonal,4,-6,-13,-4.25
13,x,3,-7,7,2.75
14,diagonal,2,-9,-19,-16.25
15,x,1,-10,3,-13.25
16,x,0,-11,1,-12.25
17,x,-1,-12,,
"""


def interp(*args):
    return subprocess.run([sys.executable, "-m", "interp.cli", *map(str, args)],
                          capture_output=True, text=True)


def test_model_trace_is_table2(tmp_path):
    done = interp("model", "su1665343", "--r", 12, "--width", 5,
                  "--steps", tmp_path / "s.csv", "--trace", tmp_path / "t.csv")
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "t.csv").read_text().replace("\r", "") == TABLE2_CSV
    steps = (tmp_path / "s.csv").read_text().split()[1:]
    assert "".join({"0,1": "Y", "-1,0": "X", "-1,1": "D"}[s.split(",", 1)[1]] for s in steps) == \
        "YYYDYDYDDDXDXDXXX"


def test_run_equals_model(sim, tmp_path):
    """Case A arc from a start point above 45°, through the RTL and the model."""
    files = {}
    for command in ("run", "model"):
        extra = ["--sim", sim] if command == "run" else []
        done = interp(command, "su1665343", "--r", 11, "--x0", 8, "--y0", 8, *extra,
                      "--steps", tmp_path / f"{command}_s.csv", "--trace", tmp_path / f"{command}_t.csv")
        assert done.returncode == 0, done.stderr
        files[command] = [(tmp_path / f"{command}_{k}.csv").read_text() for k in "st"]
    assert files["run"] == files["model"]
    assert len(files["run"][0].splitlines()) > 5


@pytest.mark.parametrize("args, message", [
    (["--r", 0], "radius must be at least 1"),
    (["--r", 15, "--width", 5], "does not fit WIDTH = 5"),
    (["--r", 12, "--x0", 5, "--y0", 5], "farther than one step"),
    (["--r", 12, "--x0", 5], "both --x0 and --y0"),
    (["--r", 12, "--width", 3], "outside 4 .. 30"),
])
def test_bad_arguments(args, message, tmp_path):
    done = interp("model", "su1665343", *args, "--steps", tmp_path / "s.csv")
    assert done.returncode == 2
    assert message in done.stderr and len(done.stderr.strip().splitlines()) == 1, done.stderr
