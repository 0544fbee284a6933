# SPDX-License-Identifier: Apache-2.0
"""FPGA figures: Fmax, LUTs, FFs per core at width 32 (iCE40 HX8K, ECP5-25F), with
cycles per step, so the step rate each core reaches on each device reads off one row.

Fmax and area come from the synthesis flow (interp/flows/synth.py, `make synth`):
`interp bench` re-runs it only where sources changed, and shows the cached
results when the YoWASP tools are not installed (`make bench` does not
install them).  Cycles per step: one of the core's `interp demo` moves
through its cycle model (equal to the RTL cycle by cycle), `tick` high,
start to `done`.  Simulation speed: a harness generated from the core
registry (interp/simulation/harness.py: the table's parameters, the cycles/step move,
`tick` high, `start` pulsed whenever the core is idle) runs a fixed number of
cycles natively on Icarus and on Verilator (`--binary -O3`), no cocotb;
cycles per CPU second of the run (user + system: other load on the
machine barely changes it), compile time excluded.
"""
from __future__ import annotations

import argparse
from concurrent.futures import ThreadPoolExecutor

from ..simulation import harness, speed
from ..flows import synth

# Fmax goals (MHz at width 32, iCE40 / ECP5) of the production cores.
GOALS = {"lin-exact": (150, 250), "circ-arc": (120, 200)}
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


# Cycles each simulator runs: about 1 s on Icarus, 0.5 s on Verilator for su1571551.
SIM_CYCLES = {"icarus": 20_000, "verilator": 2_000_000}


def sim_speeds(names: list[str], quick: bool) -> dict[tuple[str, str], str]:
    """(row, simulator) -> cycles/s for the rows with a stimulus (CLI cores, motion_top).

    Builds two at a time, then runs one at a time; a core that does not build or
    run (one in progress) gets no figure."""
    jobs = []
    for name in names:
        try:
            made = harness.for_row(name, MOVES.get(name))
        except Exception:
            made = None
        jobs += [(name, sim, made) for sim in speed.SIMULATORS if made]

    def build(job):
        name, sim, (module, src) = job
        try:
            return speed.build_harness(module, sim, src=src)
        except Exception:
            return None

    with ThreadPoolExecutor(2) as pool:
        built = list(pool.map(build, jobs))
    out = {}
    for (name, sim, _), cmd in zip(jobs, built):
        n = SIM_CYCLES[sim] // (10 if quick else 1)
        try:
            got, seconds = speed.run_built(cmd, [f"+cycles={n}"], cpu=True) if cmd else ({}, 0)
        except Exception:
            continue
        if got.get("cycles") == n and seconds > 0:
            out[name, sim] = f"{float(f'{n / seconds:.3g}'):,.0f}"     # three significant figures
    return out


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
    speeds = sim_speeds(list(by_core), quick)
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
        line += [speeds.get((name, sim), "-") for sim in ("icarus", "verilator")]
        out.append(line + ["; ".join(notes_of)])
    header = ["core", "cycles/step", "iCE40 HX8K Fmax (MHz)", "iCE40 LUT/FF", "iCE40 Msteps/s",
              "ECP5-25F Fmax (MHz)", "ECP5 LUT/FF", "ECP5 Msteps/s", "goal iCE40/ECP5",
              "Icarus cycles/s", "Verilator cycles/s", "notes"]
    title = "FPGA at width 32: Yosys 0.70 + nextpnr (YoWASP), seed 1, register to register"
    if notes:
        title += " — " + "; ".join(notes[:3]) + (" ..." if len(notes) > 3 else "")
    return [(title, header, out)]
