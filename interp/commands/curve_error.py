# SPDX-License-Identifier: Apache-2.0
"""`interp curve-error [--csv FILE]`: the paper's error experiment, through the RTL.

The four curves at the paper's four scalings (A, B), each over a fixed range
(docs/algorithms.md, section 4), in three modes: literal (the paper's points 1-9),
improved, and improved with E re-anchored to the true curve every 8 steps.
"""
from __future__ import annotations

import csv
import json
import tempfile
from pathlib import Path

from ..models.curve import CURVES, PAPER_CURVES, PAPER_ERROR, PAPER_SCALES, paper_error

MODES = {"literal": ("literal", 0), "improved": ("improved", 0), "reanchor": ("improved", 8)}
REANCHOR = 8


def job(curve: str, a: int, b: int, mode: str, **extra) -> dict:
    m, n = MODES[mode]
    return dict(curve=curve, a=a, b=b, x0=None, y0=None, end_x=None, end_y=None, count=None,
                reverse=False, mode=m, reanchor=n, width=16, pw=24, max_cycles=10_000_000, **extra)


def rtl_points(jobs: list[dict], sim: str = "icarus") -> list[list[tuple[int, int]]]:
    """Run every job through rtl/curve_tangent.v in one simulation; the visited nodes."""
    from ..simulation.jobs import job_env
    from ..simulation.runner import run_cocotb

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "points.json"
        run_cocotb(toplevel="curve_tangent", test_module="interp.simulation.curve_driver", sim=sim,
                   parameters={"WIDTH": 16, "PW": 24, "CW": 24},
                   env={**job_env("INTERP_JOBS", jobs, tmp), "INTERP_OUT": str(out)},
                   name="cli_curve_error", test_dir=Path(tmp), quiet=True)
        return [[tuple(p) for p in pts] for pts in json.loads(out.read_text())]


def experiment(sim: str = "icarus", scales=PAPER_SCALES, modes=tuple(MODES)) -> list[dict]:
    """Rows: curve, a, b, paper_error and max_error per mode."""
    cells = [(c, i, a, b, m) for c in PAPER_CURVES for i, (a, b) in enumerate(scales) for m in modes]
    points = rtl_points([job(c, a, b, m) for c, _, a, b, m in cells], sim)
    rows: dict = {}
    for (c, i, a, b, m), pts in zip(cells, points):
        row = rows.setdefault((c, a, b), {"curve": c, "a": a, "b": b,
                                          "paper_error": PAPER_ERROR[c][PAPER_SCALES.index((a, b))]
                                          if (a, b) in PAPER_SCALES else None})
        row[m] = round(paper_error(CURVES[c], a, b, pts), 4)
        row[m + "_steps"] = len(pts) - 1
    return list(rows.values())


def add_parser(sub) -> None:
    p = sub.add_parser("curve-error", help="the tangent-method paper's error table, through the RTL")
    p.add_argument("--csv", metavar="FILE", help="write curve,a,b,max_error,paper_error")
    p.add_argument("--mode", choices=list(MODES), default="literal", help="the mode written to --csv")
    p.add_argument("--sim", choices=["icarus", "verilator"], default="icarus")
    p.set_defaults(func=run)


def run(args) -> int:
    rows = experiment(args.sim)
    print(f"{'curve':10} {'A':>5} {'B':>4} {'paper':>7} {'literal':>8} {'improved':>9} {'re-anchor':>9}")
    for r in rows:
        print(f"{r['curve']:10} {r['a']:5} {r['b']:4} {r['paper_error']:7.4f} {r['literal']:8.4f} "
              f"{r['improved']:9.4f} {r['reanchor']:9.4f}")
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["curve", "a", "b", "max_error", "paper_error"])
            for r in rows:
                w.writerow([r["curve"], r["a"], r["b"], r[args.mode], r["paper_error"]])
    return 0


def demo(out, sim: str) -> None:
    """One plot per curve (improved mode) for `interp demo`."""
    from ..cli import build_parser
    from ..cores import load_all

    load_all()
    parser = build_parser()
    examples = {"exponent": (100, 10), "logarithm": (100, 10), "hyperbola": (100, 10), "sqrt": (100, 10),
                "ellipse": (40, 25), "circle": (40, 40), "parabola": (30, 20), "line": (17, 40)}
    for name, (a, b) in examples.items():
        stem = Path(out) / f"curve_{name}"
        argv = ["run", "curve", "--curve", name, "--a", str(a), "--b", str(b), "--mode", "improved",
                "--sim", sim, "--steps", f"{stem}_steps.csv", "--plot", f"{stem}.png"]
        parsed = parser.parse_args(argv)
        parsed.func(parsed)
        print(f"curve {name}: {stem}.png {stem}_steps.csv")
