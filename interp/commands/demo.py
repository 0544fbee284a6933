# SPDX-License-Identifier: Apache-2.0
"""`interp demo`: every core's built-in examples through the RTL, with waves and plots.

Besides one VCD, steps CSV and PNG per example, it draws OUT/overview.png: a
line, an arc, a curve and the G-code demo program side by side, each over its
deviation from the programmed path.  The README's picture docs/demo.png is
this file: `make docs-demo`, i.e.
`interp demo --overview-only --overview docs/demo.png`.
"""
from __future__ import annotations

import csv
from pathlib import Path

from ..cores import REGISTRY, UsageError
from ..simulation.output import ensure_dir
from ..simulation.runner import SIMULATORS

# The overview's panels: (label, core, options); the first linear core that exists is used.
OVERVIEW = (("line", "lin-exact", ["--x", "-40", "--y", "23"]),
            ("line", "su1571551", ["--x", "-40", "--y", "23", "--mode", "exact"]),
            ("arc", "circ-arc", ["--cx", "0", "--cy", "0", "--x0", "30", "--y0", "0", "--x1", "30", "--y1", "0",
                                 "--full"]),
            ("curve", "curve", ["--curve", "ellipse", "--a", "40", "--b", "25", "--mode", "improved"]))


def add_parser(sub) -> None:
    p = sub.add_parser("demo", help="simulate the built-in examples: VCD, steps/trace CSV, PNG plots")
    p.add_argument("--out", default="out/demo", help="output folder (default out/demo)")
    p.add_argument("--sim", choices=SIMULATORS, default="icarus")
    p.add_argument("--core", action="append", help="only this core (repeatable)")
    p.add_argument("--overview", metavar="FILE", help="the overview picture (default OUT/overview.png)")
    p.add_argument("--overview-only", action="store_true", help="only the overview picture's runs")
    p.set_defaults(func=run)


def run(args) -> int:
    from ..cli import build_parser

    out = ensure_dir(args.out)
    parser = build_parser()
    names = [] if args.overview_only else args.core or sorted(REGISTRY)
    for name in names:
        if name not in REGISTRY:
            raise UsageError(f"demo: unknown core {name!r}; choose from {', '.join(sorted(REGISTRY))}")
    for name in names:
        core = REGISTRY[name]
        for n, options in enumerate(core.examples, 1):
            stem = out / f"{name}_{n}"
            argv = ["run", name, *options, "--sim", args.sim, "--steps", f"{stem}_steps.csv",
                    "--vcd", f"{stem}.vcd", "--plot", f"{stem}.png"]
            if core.trace_header:
                argv += ["--trace", f"{stem}_trace.csv"]
            job = parser.parse_args(argv)
            job.func(job)
            print(f"{name} {' '.join(options)}: {stem}.vcd {stem}.png {stem}_steps.csv")
    if not args.overview_only:
        for hook in [f for f in (getattr(m, "demo", None) for m in _demo_hooks()) if f]:
            hook(out, args.sim)
    overview = Path(args.overview) if args.overview else out / "overview.png"
    write_overview(overview, out / "overview", args.sim)
    print(f"overview: {overview}")
    return 0


def read_steps(path) -> list[tuple[int, ...]]:
    with open(path, newline="") as f:
        rows = csv.reader(f)
        next(rows)
        return [tuple(int(v) for v in row) for row in rows]


def write_overview(path, work, sim: str = "icarus") -> None:
    """A line, an arc, a curve and the G-code demo through the RTL, in one small PNG."""
    from ..cli import build_parser
    from ..plots.paths import plot_overview
    from ..gcode.machine import load_machine
    from .gcode import DEMO, DEMO_OPTIONS, ideal_xy, interpret_program

    work = ensure_dir(work)
    parser = build_parser()
    panels, lines = [], 0
    for label, name, options in OVERVIEW:
        if name not in REGISTRY or (label == "line" and lines):
            continue
        lines += label == "line"
        core = REGISTRY[name]
        job = parser.parse_args(["run", name, *options, "--sim", sim, "--steps", str(work / f"{name}_steps.csv")])
        job.func(job)
        panels.append({"steps": read_steps(job.steps), "ideal": core.ideal(job),
                       "title": f"{label}, {core.toplevel}: {' '.join(options)}", **core.plot_options(job)})
    src = work / "gcode_demo.nc"
    src.write_text(DEMO)
    job = parser.parse_args(["gcode", str(src), *DEMO_OPTIONS, "--sim", sim, "--steps", str(work / "gcode_steps.csv")])
    if job.func(job):
        raise RuntimeError("the G-code demo failed")
    machine = load_machine()
    scale = machine.steps_per_mm[0]
    panels.append({"steps": read_steps(job.steps), "ideal": ideal_xy(interpret_program(DEMO, machine), machine),
                   "unit": "mm", "scale": scale,
                   "title": f"G-code, motion_top: the demo program ({scale:g} steps/mm)"})
    ensure_dir(Path(path).parent)
    plot_overview(path, panels)


def _demo_hooks():
    """Other commands may add demo output by defining `demo(out, sim)`."""
    import importlib
    import pkgutil

    from .. import commands

    for info in pkgutil.iter_modules(commands.__path__):
        if info.name != "demo":
            yield importlib.import_module(f"{commands.__name__}.{info.name}")
