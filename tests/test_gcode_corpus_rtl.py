# SPDX-License-Identifier: Apache-2.0
"""A selection of the public G-code corpus end to end on the RTL (native Verilator harness).

Each program runs through `interp gcode FILE --steps S.csv --events E.csv` at a 200 kHz
controller clock (the default machine's 50 MHz would only multiply the cycles of these
10..55 s programs; steps and events do not depend on the clock, the speed profile only
through its quantum).  The motion monitor's verdict must be ok (speeds, accelerations).  The steps in the CSV must
add up to the end in steps that --check reports, which must be the tests' own reading of the
program (interp.testing.gcode_reference) in machine mm times the machine's steps/mm, and the
events CSV must hold the events the program asks for, in order, at non-decreasing cycles.
Skipped while the native simulation module or the corpus (INTERP_GCODE_CORPUS) is absent.
"""
import csv
import importlib.util
import json

import pytest

from interp.benchmarks.gcode_corpus import (CORPUS, MACHINE, interp_gcode, machine_file,
                                            reference, steps_match)

CLOCK_HZ = "200000"
SELECTION = {
    "lcnc_3dtest.ngc": "LinuxCNC sample: inch, full circles in G17, G18 and G19",
    "ugs_spiral.gcode": "helix: full circles and helical full circles (G3 ... Z20 I20)",
    "lcnc_hole-circle.ngc": "G81 drilling cycle repeated by L6 with a polar ^60 increment, inch",
    "ugs_arc_rword_test.gcode": "one-step commands (arcs' closing lines) at 200 kHz: each must still "
                                "outlast the look-ahead's set-up (the compiler slows them)",
}



def missing() -> str | None:
    if not CORPUS.is_dir():
        return f"no G-code corpus at {CORPUS} (set INTERP_GCODE_CORPUS)"
    if importlib.util.find_spec("interp.simulation.native") is None:
        return "the native simulation (interp.simulation.native) is not here yet"
    if importlib.util.find_spec("interp.gcode.interpreter") is None or not MACHINE.is_file():
        return "the G-code front end (interp.gcode.interpreter, default machine file) is not here"
    return None


@pytest.mark.parametrize("name", sorted(SELECTION))
def test_corpus_program_on_rtl(name, tmp_path):
    reason = missing()
    if reason:
        pytest.skip(reason)
    path = CORPUS / name
    status, out, err = interp_gcode([str(path), "--check", "--json", "--clock-hz", CLOCK_HZ])
    assert status == 0, err
    end_steps = json.loads(out)["end_steps"]
    machine = machine_file()
    expected = reference(path, machine)
    exact = [mm * spm for mm, spm in zip(expected.machine, machine["steps_per_mm"])]
    assert all(steps_match(s, e) for s, e in zip(end_steps, exact)), (end_steps, exact)

    steps_csv, events_csv = tmp_path / "steps.csv", tmp_path / "events.csv"
    status, out, err = interp_gcode([str(path), "--clock-hz", CLOCK_HZ, "--steps", str(steps_csv),
                                   "--events", str(events_csv)])
    assert status == 0, err
    with open(steps_csv, newline="") as f:
        rows = list(csv.DictReader(f))
    assert [sum(int(r[k]) for r in rows) for k in ("dx", "dy", "dz")] == end_steps
    assert all(int(r[k]) in (-1, 0, 1) for r in rows for k in ("dx", "dy", "dz"))
    with open(events_csv, newline="") as f:
        events = list(csv.DictReader(f))
    assert [(e["event"], float(e["value"])) for e in events] == \
        [(n, pytest.approx(float(v))) for n, v in expected.events]
    cycles = [int(e["cycle"]) for e in events]
    assert cycles == sorted(cycles)
    verdict = next(line for line in out.splitlines() if line.startswith("monitor: "))
    assert verdict.startswith("monitor: ok"), verdict
