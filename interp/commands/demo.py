"""`interp demo`: every core's built-in examples through the RTL, with waves and plots."""
from __future__ import annotations

from ..cores import REGISTRY
from ..simulation.output import ensure_dir
from ..simulation.runner import SIMULATORS


def add_parser(sub) -> None:
    p = sub.add_parser("demo", help="simulate the built-in examples: VCD, steps/trace CSV, PNG plots")
    p.add_argument("--out", default="out/demo", help="output folder (default out/demo)")
    p.add_argument("--sim", choices=SIMULATORS, default="icarus")
    p.add_argument("--core", action="append", help="only this core (repeatable)")
    p.set_defaults(func=run)


def run(args) -> int:
    from ..cli import build_parser

    out = ensure_dir(args.out)
    parser = build_parser()
    names = args.core or sorted(REGISTRY)
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
    extra = [f for f in (getattr(m, "demo", None) for m in _demo_hooks()) if f]
    for hook in extra:
        hook(out, args.sim)
    return 0


def _demo_hooks():
    """Other commands may add demo output by defining `demo(out, sim)`."""
    import importlib
    import pkgutil

    from .. import commands

    for info in pkgutil.iter_modules(commands.__path__):
        if info.name != "demo":
            yield importlib.import_module(f"{commands.__name__}.{info.name}")


