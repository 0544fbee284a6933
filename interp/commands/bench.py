# SPDX-License-Identifier: Apache-2.0
"""`interp bench`: every benchmark table (modules of interp.benchmarks define `tables(quick)`)."""
from __future__ import annotations

import importlib
import pkgutil
from pathlib import Path

from .. import benchmarks


def add_parser(sub) -> None:
    p = sub.add_parser("bench", help="print the benchmark tables")
    p.add_argument("--quick", action="store_true", help="smaller ranges, for a fast look")
    p.add_argument("--only", action="append", help="only this benchmark module (repeatable)")
    p.add_argument("--md", metavar="FILE", help="also write the tables as Markdown to FILE")
    p.set_defaults(func=run)


def markdown(title: str, header: list[str], rows: list[list]) -> str:
    cells = [[_fmt(c) for c in row] for row in rows]
    lines = [f"### {title}", "", "| " + " | ".join(header) + " |",
             "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(row) + " |" for row in cells]
    return "\n".join(lines) + "\n"


def _fmt(value) -> str:
    if isinstance(value, float):
        return f"{value:.4g}" if abs(value) < 1e5 else f"{value:,.0f}"
    return str(value)


def run(args) -> int:
    out = []
    for info in pkgutil.iter_modules(benchmarks.__path__):
        if args.only and info.name not in args.only:
            continue
        module = importlib.import_module(f"{benchmarks.__name__}.{info.name}")
        for title, header, rows in module.tables(args.quick):
            text = markdown(title, header, rows)
            print(text, flush=True)
            out.append(text)
    if args.md:
        Path(args.md).parent.mkdir(parents=True, exist_ok=True)     # (out/ on a fresh clone)
        Path(args.md).write_text("\n".join(out))
    return 0
