# SPDX-License-Identifier: Apache-2.0
"""The public G-code corpus through `interp gcode FILE --check --json`.

Every program of the corpus directory (INTERP_GCODE_CORPUS; the default is CORPUS in
interp.benchmarks.gcode_corpus) runs through the front end with the default machine file,
and its end is compared with the tests' own independent reading of the program
(interp.testing.gcode_reference): `end` (work coordinates, program units) within 1e-6,
`end_steps` with the reference's machine millimetres times the machine's steps/mm, rounded
(either neighbour when the product lies on a half step), and the numbers of arcs and events.
A program the front end refuses must be listed in REFUSED below with the line it is refused
at, and the refusal must be one line naming the line and the column, with exit status 2.
"""
import importlib.util
import json
import re

import pytest

from interp.benchmarks.gcode_corpus import (CORPUS, FANUC_HABITS, MACHINE, corpus_files,
                                            interp_gcode, machine_file, reference, steps_match)
from interp.testing.gcode_reference import Refused

# Programs the front end refuses, with the line of the refusal and why that is right.
REFUSED = {
    # A 3D printer's Marlin program: extruder axis E, M104/M140 heaters, and two lines of
    # plain text that a hand edit broke out of a ';' comment (line 58 is the first).
    "cura_own_gcode.gcode": 58,
    # G42 D1: cutter radius compensation with tool 1 of LinuxCNC's sim tool table, which the
    # corpus machine file has not got (tests/test_gcode_cutter.py runs it with that tool).
    "lcnc_comp.ngc": 12,
    # Its feed rate is a LinuxCNC HAL pin, #<_hal[plasmac.cut-feed-rate]>, which has no
    # value outside a LinuxCNC plasma configuration (so the feed rate is not positive).
    "lcnc_metric_wrench.ngc": 9,
    # A pen plotter's M300 S30/S50 servo commands (and M17/M18 motor power): not RS274NGC.
    "ur5_drawing.gcode": 7,
}
# FANUC_HABITS (helman_simple_mill, tap_HeatSunk_drill) need the front end's documented
# departures from LinuxCNC ("G0 ... G80" in one block, axis words after G80), which LinuxCNC
# refuses; the reference models them there (fanuc_g80=True).

REFUSAL = re.compile(r"interp: (error: )?line (\d+), column (\d+): \S.*")


def front_end_missing() -> str | None:
    if importlib.util.find_spec("interp.gcode.interpreter") is None or not MACHINE.is_file():
        return "the G-code front end (interp.gcode.interpreter, default machine file) is not here"
    return None


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
    status, out, err = interp_gcode([str(path), "--check", "--json"])
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
