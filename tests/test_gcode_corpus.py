# SPDX-License-Identifier: Apache-2.0
"""The public G-code corpus through `interp gcode FILE --check --json`.

Every program of the corpus directory (INTERP_GCODE_CORPUS, by default the `shared/gcode`
folder next to this repository's root) runs through the front end with the default machine
file, and its end is compared with the tests' own independent reading of the program
(interp.testing.gcode_reference): `end` (work coordinates, program units) within 1e-6, and
`end_steps` with the reference's machine millimetres times the machine's steps/mm, rounded
(either neighbour when the product lies on a half step), and the numbers of arcs and events.  A program
the front end refuses must be listed in REFUSED below with the line it is refused at, and the
refusal must be one line naming the line and the column, with exit status 2.
"""
import contextlib
import importlib.util
import io
import json
import math
import os
import re
import tomllib
from pathlib import Path

import pytest

from interp.testing.gcode_reference import Refused, run

ROOT = Path(__file__).resolve().parents[1]
CORPUS = Path(os.environ.get("INTERP_GCODE_CORPUS", ROOT.parent / "shared" / "gcode"))
MACHINE = ROOT / "interp" / "gcode" / "default_machine.toml"
PROGRAM_SUFFIXES = {".gcode", ".nc", ".ngc", ".tap"}

# Programs the front end refuses, with the line of the refusal and why that is right.
REFUSED = {
    # A 3D printer's Marlin program: extruder axis E, M104/M140 heaters, and two lines of
    # plain text that a hand edit broke out of a ';' comment (line 58 is the first).
    "cura_own_gcode.gcode": 58,
    # G41/G42 cutter radius compensation (the sample exists to show it); not supported.
    "lcnc_comp.ngc": 12,
    # Its feed rate is a LinuxCNC HAL pin, #<_hal[plasmac.cut-feed-rate]>, which has no
    # value outside a LinuxCNC plasma configuration (so the feed rate is not positive).
    "lcnc_metric_wrench.ngc": 9,
    # A pen plotter's M300 S30/S50 servo commands (and M17/M18 motor power): not RS274NGC.
    "ur5_drawing.gcode": 7,
}
# The front end's documented departures from LinuxCNC that these programs need (Fusion 360
# and textbook Fanuc habits: "G0 ... G80" in one block, axis words after G80); the reference
# models them with fanuc_g80=True, and LinuxCNC itself would refuse these two programs.
FANUC_HABITS = {"helman_simple_mill.gcode", "tap_HeatSunk_drill.tap"}

REFUSAL = re.compile(r"interp: (error: )?line (\d+), column (\d+): \S.*")


def corpus_files() -> list[Path]:
    if not CORPUS.is_dir():
        return []
    return sorted(p for p in CORPUS.iterdir() if p.suffix.lower() in PROGRAM_SUFFIXES)


def front_end_missing() -> str | None:
    if importlib.util.find_spec("interp.gcode.interpreter") is None or not MACHINE.is_file():
        return "the G-code front end (interp.gcode.interpreter, the default machine file) is not here"
    return None


def machine_file() -> dict:
    values = tomllib.loads(MACHINE.read_text())
    tools = {int(n): dict(v) for n, v in values.get("tool", {}).items()}
    home = values.get("home", {})
    return {"steps_per_mm": [float(values["axis"][a]["steps_per_mm"]) for a in "xyz"],
            "g28": tuple(home.get("g28", (0, 0, 0))), "g30": tuple(home.get("g30", (0, 0, 0))),
            "tools": tools}


def check(path: Path) -> tuple[int, str, str]:
    """interp gcode PATH --check --json, in this process: (status, stdout, stderr)."""
    from interp.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(["gcode", str(path), "--check", "--json"])
    return status, out.getvalue(), err.getvalue()


def reference(path: Path, machine: dict):
    text = path.read_text(encoding="utf-8", errors="surrogateescape")
    return run(text, g28=machine["g28"], g30=machine["g30"], tools=machine["tools"],
               fanuc_g80=path.name in FANUC_HABITS)


def steps_match(steps: int, exact: float) -> bool:
    if abs(abs(exact - math.floor(exact)) - 0.5) < 1e-6:        # on a half step: either side
        return steps in (math.floor(exact), math.ceil(exact))
    return steps == round(exact)


FILES = corpus_files()


@pytest.mark.skipif(not FILES, reason=f"no G-code corpus at {CORPUS} (set INTERP_GCODE_CORPUS)")
def test_refusal_list_names_corpus_programs():
    names = {p.name for p in FILES}
    assert set(REFUSED) <= names and FANUC_HABITS <= names


@pytest.mark.skipif(not FILES, reason=f"no G-code corpus at {CORPUS} (set INTERP_GCODE_CORPUS)")
@pytest.mark.parametrize("path", FILES or [None], ids=lambda p: p.name if p else "none")
def test_corpus_program(path):
    missing = front_end_missing()
    if missing:
        pytest.skip(missing)
    status, out, err = check(path)
    if path.name in REFUSED:
        lines = err.strip().splitlines()
        assert status == 2 and out == "", (status, out)
        assert len(lines) == 1 and REFUSAL.fullmatch(lines[0]), err
        assert int(REFUSAL.fullmatch(lines[0]).group(2)) == REFUSED[path.name], lines[0]
        return
    assert status == 0, f"refused: {err.strip()}"
    summary = json.loads(out)
    machine = machine_file()
    try:
        expected = reference(path, machine)
    except Refused as error:                    # the front end runs what LinuxCNC refuses
        pytest.fail(f"the front end runs it, the reference refuses it: {error}")
    assert summary["end"] == pytest.approx(list(expected.work), abs=1e-6), "end"
    exact = [mm * spm for mm, spm in zip(expected.machine, machine["steps_per_mm"])]
    assert all(steps_match(s, e) for s, e in zip(summary["end_steps"], exact)), \
        (summary["end_steps"], exact)
    assert summary["arcs"] == expected.arcs
    assert summary["events"] == len(expected.events)
