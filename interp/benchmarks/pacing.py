# SPDX-License-Identifier: Apache-2.0
"""The S-curve filter and the step pacer at the G-code build's widths (FEED_W 34,
FRAC 32, MW 12): area and Fmax on iCE40 HX8K and ECP5-25F next to feed_rate's
(the constant-feed speed block they replace), and the stall the pacer's phase
absorbs.

Area and Fmax come from the project's synthesis flow (interp/flows/synth.py,
`implement`, cached per source hash); without the YoWASP tools (`make
fpga-deps`) or with `quick`, only cached results are shown.  The stall table is
arithmetic on the widths: the phase (max(FEED_W, FRAC + 1) + MW + GUARD bits)
keeps growing while a step is due and none can leave; it saturates (`overrun`)
after (2^PHASE_W - 1 - cost << J) / F clocks.
"""
from __future__ import annotations

import json

from ..flows import synth
from ..gcode.compile import FEED_W, FRAC, MW

CLI = {"FEED_W": FEED_W, "FRAC": FRAC, "MW": MW}
BLOCKS = [t for t in synth.CORES if t.toplevel in ("jerk_filter", "step_pacer")] + [
    synth.Target("feed_rate", "feed_rate", {"FEED_W": FEED_W, "FRAC": FRAC}, width=None),
]


def _row(target: synth.Target, family: synth.Family, run: bool) -> dict | None:
    if run:
        try:
            return synth.implement(target, family, log=lambda m: None)
        except Exception as exc:           # a tool failure must not stop the other rows
            return {"error": str(exc).splitlines()[0]}
    cached = synth.run_dir(target, family) / "result.json"
    return json.loads(cached.read_text()) if cached.exists() else None


def area_rows(run: bool) -> list[list]:
    rows = []
    for target in BLOCKS:
        for name, family in synth.FAMILIES.items():
            r = _row(target, family, run)
            if not r:
                rows.append([target.toplevel, name, "-", "-", "-", "-", "not synthesized yet: make fpga-deps, then interp bench"])
            elif "error" in r:
                rows.append([target.toplevel, name, "-", "-", "-", "-", r["error"]])
            else:
                rows.append([target.toplevel, name, r["fmax_mhz"] if r["fmax_mhz"] is not None else "-",
                             r["luts"], r["ffs"], r.get("brams", "-"), r.get("note", "")])
    return rows


def stall_rows() -> list[list]:
    frac, feed_w, mw, guard = CLI["FRAC"], CLI["FEED_W"], CLI["MW"], 8
    phase_w = max(feed_w, frac + 1) + mw + guard
    top = (1 << phase_w) - 1
    rows = []
    for speed in (1.0, 0.1, 0.01, 0.001):             # axial steps per clock
        for shift in (0, mw):
            f = int(speed * (1 << frac)) << shift
            cost = (1 << frac) << shift
            rows.append([speed, shift, phase_w, f"{(top - cost) // f:,}"])
    return rows


def tables(quick: bool):
    run = synth.have_tools() and not quick
    return [
        (f"S-curve filter and step pacer vs feed_rate, FEED_W {FEED_W}, FRAC {FRAC}, MW {MW} "
         f"({'Yosys + nextpnr, seed 1' if run else 'cached results'})",
         ["block", "family", "Fmax (MHz)", "LUTs", "FFs", "BRAMs", "note"], area_rows(run)),
        ("step_pacer: the longest stall its phase absorbs (GUARD 8), clocks",
         ["speed (steps/clock)", "jerk_shift", "phase bits", "clocks before overrun"], stall_rows()),
    ]
