# SPDX-License-Identifier: Apache-2.0
"""The `interp` command line.

  interp run CORE [core options] [--sim icarus|verilator] [--steps FILE] [--trace FILE] [--vcd FILE] [--plot FILE]
  interp model CORE ...          the same files from the golden model
  interp demo [--out DIR]        built-in examples through the RTL: waves, CSVs, plots
  interp wave CORE               a core's example to out/CORE.vcd, opened in GTKWave (make wave CORE=...)
  interp bench                   benchmark tables

More subcommands come from the modules of interp.commands (each has `add_parser`).
"""
from __future__ import annotations

import argparse
import importlib
import json
import pkgutil
import sys
import tempfile
from pathlib import Path

from . import commands
from .cores import REGISTRY, UsageError, load_all
from .models.base import Run, drive, steps_of
from .simulation.output import check_outputs, summary, write_run
from .simulation.runner import SIMULATORS


class Parser(argparse.ArgumentParser):
    """argparse that reports a bad argument as one line, exit status 2."""

    def error(self, message):
        raise UsageError(f"{self.prog}: {message}")


def add_run_options(parser: argparse.ArgumentParser, rtl: bool) -> None:
    if rtl:
        parser.add_argument("--sim", choices=SIMULATORS, default="icarus", help="simulator (default icarus)")
    parser.add_argument("--steps", metavar="FILE", help="CSV of steps: cycle,dx,dy")
    parser.add_argument("--trace", metavar="FILE", help="CSV of the patent core's registers at each step")
    parser.add_argument("--vcd", metavar="FILE", help="waveform file")
    parser.add_argument("--plot", metavar="FILE", help="PNG of the stepped path over the ideal one")
    parser.add_argument("--max-cycles", type=int, default=10_000_000, help=argparse.SUPPRESS)


def simulate(core, args, sim: str = "icarus", vcd: str | None = None) -> Run:
    """Run the core's stimulus through the RTL; return its samples."""
    from .simulation.jobs import job_env
    from .simulation.runner import run_cocotb

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "samples.json"
        job = {"core": core.name, "args": {k: v for k, v in vars(args).items() if _plain(v)},
               "out": str(out)}
        run_cocotb(toplevel=core.toplevel, test_module="interp.simulation.rtl_driver", sim=sim,
                   parameters=core.parameters(args), env=job_env("INTERP_JOB", job, tmp),
                   waves=vcd, name=f"cli_{core.toplevel}", test_dir=Path(tmp), quiet=True)
        samples = json.loads(out.read_text())
    return Run(steps=steps_of(samples, core.axes), trace=core.trace(samples), samples=samples)


def model_run(core, args) -> Run:
    samples = drive(core.model(args), core.stimulus(args))
    return Run(steps=steps_of(samples, core.axes), trace=core.trace(samples), samples=samples)


def _plain(value) -> bool:
    return isinstance(value, (int, float, str, bool, list, type(None)))


def cmd_run_or_model(args) -> int:
    core = REGISTRY[args.core]
    core.check(args)
    if args.trace and core.trace_header is None:
        raise UsageError(f"core {core.name} has no --trace (only the patent cores have one)")
    check_outputs(args.steps, args.trace, args.vcd, args.plot)
    if args.command == "run":
        run = simulate(core, args, args.sim, args.vcd)
    else:
        run = model_run(core, args)
    write_run(core, args, run, model_vcd=args.command == "model")
    print(summary(core, args, run))
    return 0


def build_parser() -> Parser:
    parser = Parser(prog="interp", description="Evaluation-function interpolators: RTL, models, tools")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    for command, rtl, text in (("run", True, "simulate a core's RTL"),
                               ("model", False, "run a core's golden model")):
        p = sub.add_parser(command, help=text)
        cores = p.add_subparsers(dest="core", required=True, metavar="CORE", parser_class=Parser)
        for name, core in sorted(REGISTRY.items()):
            cp = cores.add_parser(name, help=core.help)
            core.add_arguments(cp)
            add_run_options(cp, rtl)
            cp.set_defaults(func=cmd_run_or_model)
    for info in pkgutil.iter_modules(commands.__path__):
        importlib.import_module(f"{commands.__name__}.{info.name}").add_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    load_all()
    try:
        parser = build_parser()
        args, rest = parser.parse_known_args(argv)
        if rest and hasattr(args, "move") and not any(word.startswith("-") for word in rest):
            args.move += rest               # interp jog X1 --feed 600 Y2: words after an option
        elif rest:
            parser.error(f"unrecognized arguments: {' '.join(rest)}")
        return args.func(args) or 0
    except UsageError as err:
        for message in getattr(err, "messages", ()):      # what the program said before its (ABORT, ...)
            print(f"interp: message: {message}", file=sys.stderr)
        print(f"interp: error: {err}", file=sys.stderr)
        return 2
    except (RuntimeError, OSError) as err:
        first = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
        print(f"interp: failed: {first}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
