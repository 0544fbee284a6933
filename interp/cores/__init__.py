# SPDX-License-Identifier: Apache-2.0
"""Registry of the cores the command line knows.

Each module in this package defines a `Core` subclass and registers it with
`@register`.  A core says how to turn command-line options into HDL
parameters, a cycle model and a stimulus, and (patent cores) how to turn the
per-cycle samples into the trace CSV.  `interp run` and `interp model` use the
same stimulus, so their outputs are comparable line by line.
"""
from __future__ import annotations

import argparse
import importlib
import pkgutil

from ..models.base import CycleModel, Stimulus, move

REGISTRY: dict[str, "Core"] = {}


class UsageError(Exception):
    """Bad command-line input: reported as one line, exit status 2."""


def register(cls):
    REGISTRY[cls.name] = cls()
    return cls


def signed_range(value: int, width: int, what: str) -> int:
    lo, hi = -(1 << (width - 1)), (1 << (width - 1)) - 1
    if not lo <= value <= hi:
        raise UsageError(f"{what} = {value} does not fit {width} signed bits ({lo} .. {hi})")
    return value


class Core:
    name: str = ""              # CLI name
    toplevel: str = ""          # Verilog module
    help: str = ""
    axes: str = "xy"            # axes in the steps CSV
    trace_header: list[str] | None = None
    examples: list[list[str]] = []   # core options for `interp demo`

    def add_arguments(self, parser: argparse.ArgumentParser) -> None:
        parser.add_argument("--width", type=int, default=32, help="coordinate width in bits (default 32)")

    def check(self, args) -> None:
        """Raise UsageError for options the core cannot take."""
        if args.width < 2 or args.width > 62:
            raise UsageError(f"--width {args.width} is outside 2 .. 62")

    def parameters(self, args) -> dict:
        return {"WIDTH": args.width}

    def model(self, args) -> CycleModel:
        raise NotImplementedError

    def load(self, args) -> dict:
        """The command inputs applied with `start`."""
        raise NotImplementedError

    def stimulus(self, args) -> Stimulus:
        return move(self.load(args), max_cycles=args.max_cycles)

    def trace(self, samples: list[dict]) -> list[dict]:
        return []

    def ideal(self, args):
        """Points (x, y) of the programmed path, for plots; None if not drawn."""
        return None

    def plot_options(self, args) -> dict:
        """Extra plot_path arguments: the start point in the user's coordinates (the
        steps are drawn from it; default the origin), the deviation band."""
        return {}


def load_all() -> dict[str, Core]:
    for info in pkgutil.iter_modules(__path__):
        importlib.import_module(f"{__name__}.{info.name}")
    return REGISTRY
