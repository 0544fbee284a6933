"""FPGA figures: Fmax, LUTs, FFs per core at width 32 (iCE40 HX8K, ECP5-25F), with
cycles per step, so the step rate each core reaches on each device reads off one row.

Fmax and area come from the synthesis flow (interp/synth.py, `make synth`):
`interp bench` re-runs it only where sources changed, and shows the cached
results when the YoWASP tools are not installed (`make bench` does not
install them).  Cycles per step: one of the core's `interp demo` moves
through its cycle model (equal to the RTL cycle by cycle), `tick` high,
start to `done`.
"""
from __future__ import annotations

import argparse

from .. import synth

# Goals of issue 7 (MHz at width 32): production cores.
GOALS = {"su1571551": (150, 250), "circ-arc": (120, 200)}
# A move for the cycles/step column where the demo's first example does not fit.
MOVES = {"su1571551": ["--x", "-40", "--y", "23", "--mode", "exact"],
         "su1571551/faithful": ["--x", "-40", "--y", "23", "--mode", "faithful"]}


def cycles_per_step(name: str):
    from ..cores import load_all
    from ..models.base import drive, steps_of

    cores = load_all()
    core = cores.get(name.split("/")[0])
    if core is None or not (MOVES.get(name) or core.examples):
        return None
    parser = argparse.ArgumentParser()
    core.add_arguments(parser)
    args = parser.parse_args(MOVES.get(name) or core.examples[0])
    args.max_cycles = 10_000_000
    samples = drive(core.model(args), core.stimulus(args))
    steps = len(steps_of(samples, core.axes))
    return round((len(samples) - 1) / steps, 2) if steps else None


def tables(quick: bool):
    if synth.have_tools() and not quick:
        rows, notes = synth.table(log=lambda m: None)
    else:
        rows, notes = synth.cached_rows(), ["cached results (run make synth to refresh)"]
    if not rows:
        return [("FPGA: Fmax and area", ["note"], [["no synthesis results: run make synth"]])]
    by_core: dict[str, dict] = {}
    for r in rows:
        by_core.setdefault(r["core"], {})[r["family"]] = r
    out = []
    for name, fams in by_core.items():
        try:
            cps = cycles_per_step(name)
        except Exception:                  # a core in progress must not stop the table
            cps = None
        line, notes_of = [name, cps if cps is not None else "-"], []
        for fam in ("ice40", "ecp5"):
            r = fams.get(fam)
            fmax = r["fmax_mhz"] if r and r["fmax_mhz"] is not None else "does not fit"
            if r and r.get("note"):
                notes_of.append(f"{fam}: {r['note']}")
            line += ([fmax, f"{r['luts']}/{r['ffs']}",
                      round(fmax / cps, 1) if cps and r["fmax_mhz"] else "-"]
                     if r else ["-", "-", "-"])
        goal = GOALS.get(name)
        if goal and "ice40" in fams and "ecp5" in fams:
            met = [(fams[f]["fmax_mhz"] or 0) >= g for f, g in zip(("ice40", "ecp5"), goal)]
            line.append(f"{goal[0]}/{goal[1]}: " + "/".join("met" if m else "not met" for m in met))
        else:
            line.append("")
        out.append(line + ["; ".join(notes_of)])
    header = ["core", "cycles/step", "iCE40 HX8K Fmax (MHz)", "iCE40 LUT/FF", "iCE40 Msteps/s",
              "ECP5-25F Fmax (MHz)", "ECP5 LUT/FF", "ECP5 Msteps/s", "goal iCE40/ECP5", "notes"]
    title = "FPGA at width 32: Yosys 0.70 + nextpnr (YoWASP), seed 1, register to register"
    if notes:
        title += " — " + "; ".join(notes[:3]) + (" ..." if len(notes) > 3 else "")
    return [(title, header, out)]
