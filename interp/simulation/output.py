# SPDX-License-Identifier: Apache-2.0
"""Files `interp run`/`interp model` write: steps CSV, trace CSV, model VCD, plot."""
from __future__ import annotations

import csv
import os
from pathlib import Path

from ..models.base import Run

PERIOD_NS = 10      # the benches' clock period, also used for model waveforms


def write_steps(path, steps, axes: str = "xy") -> None:
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["cycle"] + [f"d{a}" for a in axes])
        w.writerows(steps)


def write_trace(path, header, rows) -> None:
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=header)
        w.writeheader()
        for row in rows:
            w.writerow({k: ("" if row.get(k) is None else row[k]) for k in header})


def write_model_vcd(path, samples: list[dict], scope: str) -> None:
    """The model's per-cycle samples as a VCD (1-bit signals as wires)."""
    from vcd import VCDWriter

    names = list(samples[0]) if samples else []
    one_bit = {n for n in names if all(s[n] in (0, 1) for s in samples)}
    with open(path, "w") as f, VCDWriter(f, timescale="1 ns", date="today") as vcd:
        clk = vcd.register_var(scope, "clk", "wire", size=1)
        variables = {n: vcd.register_var(scope, n, "wire" if n in one_bit else "integer",
                                         size=1 if n in one_bit else 64) for n in names}
        for cycle, sample in enumerate(samples):
            t = cycle * PERIOD_NS
            vcd.change(clk, t, 1)
            vcd.change(clk, t + PERIOD_NS // 2, 0)
            for n, v in sample.items():
                vcd.change(variables[n], t + PERIOD_NS // 2, v)


def check_outputs(*paths, inputs=()) -> None:
    """Refuse, before anything runs, an output path that cannot be written, that names one of
    the `inputs` (the program, the machine file: it would be overwritten) or another output."""
    from ..cores import UsageError

    def same(a, b) -> bool:
        try:
            return Path(a).resolve() == Path(b).resolve() or (Path(a).exists() and Path(b).exists()
                                                              and os.path.samefile(a, b))
        except OSError:
            return False

    given = [path for path in paths if path is not None]
    for n, path in enumerate(given):
        for source in inputs:
            if source not in (None, "-") and same(path, source):
                raise UsageError(f"{path}: an output would overwrite the input {source}")
        for other in given[:n]:
            if same(path, other):
                raise UsageError(f"{path}: given for two outputs")
    for path in given:
        p = Path(path)
        folder = p.parent if str(p.parent) else Path(".")
        if p.is_dir():
            raise UsageError(f"{path} is a directory, not a file")
        if not folder.is_dir():
            raise UsageError(f"cannot write {path}: no directory {folder}")
        existed = p.exists()
        try:                            # a real probe: permission bits do not bind root
            with open(p, "a"):
                pass
        except OSError as err:
            raise UsageError(f"cannot write {path}: {err.strerror}") from None
        if not existed:
            p.unlink()


def summary(core, args, run: Run) -> str:
    """One line: steps, end point, clock cycles, largest deviation from the programmed path."""
    start = core.plot_options(args).get("start", (0, 0))
    end = list(start) + [0] * (len(core.axes) - len(start))
    for row in run.steps:
        end = [e + d for e, d in zip(end, row[1:])]
    cycles = len(run.samples)
    text = (f"{core.name}: {len(run.steps)} steps, end ({', '.join(map(str, end))}), "
            f"{cycles} clock cycles")
    ideal = core.ideal(args)
    if ideal is not None and len(core.axes) == 2:
        from ..plots.paths import deviations, positions

        worst = float(abs(deviations(positions(run.steps, start), ideal)).max())
        text += f", max deviation {worst:.3f} steps"
    return text


def write_run(core, args, run: Run, model_vcd: bool) -> None:
    if args.steps:
        write_steps(args.steps, run.steps, core.axes)
    if args.trace:
        write_trace(args.trace, core.trace_header, run.trace)
    if args.vcd and model_vcd:
        write_model_vcd(args.vcd, run.samples, core.toplevel)
    if args.plot:
        from ..plots.paths import plot_path

        plot_path(args.plot, run.steps, core.ideal(args),
                  title=f"interp {args.command} {core.name} ({core.toplevel}): {', '.join(describe(args))}",
                  **core.plot_options(args))


def describe(args) -> list[str]:
    skip = {"command", "core", "func", "steps", "trace", "vcd", "plot", "sim", "max_cycles"}
    return [f"{k}={v}" for k, v in vars(args).items() if k not in skip and v is not None]


def ensure_dir(path) -> Path:
    p = Path(path)
    p.mkdir(parents=True, exist_ok=True)
    return p
