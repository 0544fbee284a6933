# SPDX-License-Identifier: Apache-2.0
"""Area per module of the board builds: docs/board_area.csv and the table of docs/boards.md.

`make bitstream` keeps Yosys's statistics of each board's design synthesized
module by module (-noflatten, so every module keeps its cells) in
build/synth/board_<board>/modules.json.  This module turns them into one row per
module instance of the hierarchy, with its LUTs and flip-flops including
everything below it:

    python -m interp.flows.board_area [CSV]   build/synth/board_*/modules.json -> CSV
                                              (default docs/board_area.csv)

LUTs count as `interp synth` counts them: iCE40 SB_LUT4, ECP5 LUT4 plus 2 per
CCU2C carry cell.  The bitstream is built from the flat netlist, which Yosys
optimizes across module boundaries, so the placed count in docs/boards.csv is
smaller than the top's row here.  Instances of one module under one
parent (several parameterizations included) are one row, `name x N`.
"""
from __future__ import annotations

import csv
import json
import sys
from collections import Counter
from pathlib import Path

from ..simulation.runner import ROOT
from .synth import BOARD_TOP, BOARDS, BUILD, area

CSV = ROOT / "docs" / "board_area.csv"
HEADER = ["board", "family", "module", "depth", "instances", "luts", "ffs"]
SHARE = 0.015                   # the table shows instances with at least this share of the top's LUTs


def base_name(key: str) -> str:
    """Yosys's module key ($paramod$<hash>\\name, $paramod\\name\\P=..., \\name) -> name."""
    parts = [p for p in key.split("\\") if p]
    if key.startswith("$paramod"):
        return parts[1]
    return parts[0]


def rows(stat: dict, board: str, family: str) -> list[dict]:
    """Depth-first rows of the hierarchy under the board's top."""
    modules = stat["modules"]
    inclusive: dict[str, tuple[int, int]] = {}

    def module(name: str) -> str | None:
        """The modules' key of a cell type that is a module (keys may carry a leading backslash)."""
        return name if name in modules else ("\\" + name if "\\" + name in modules else None)

    def cells(key: str) -> dict[str, int]:
        return {k: int(v) for k, v in modules[key].get("num_cells_by_type", {}).items()}

    def own(key: str) -> dict[str, int]:
        return {k.lstrip("\\"): v for k, v in cells(key).items() if module(k) is None}

    def children(key: str) -> list[tuple[str, int]]:
        return [(module(k), v) for k, v in cells(key).items() if module(k) is not None]

    def total(key: str) -> tuple[int, int]:
        if key not in inclusive:
            luts, ffs = area(own(key), family)
            for child, count in children(key):
                cl, cf = total(child)
                luts, ffs = luts + count * cl, ffs + count * cf
            inclusive[key] = (luts, ffs)
        return inclusive[key]

    out: list[dict] = []

    def walk(group: Counter, path: str, depth: int) -> None:
        """`group`: module key -> instances (one module name under one parent)."""
        luts = sum(total(k)[0] * n for k, n in group.items())
        ffs = sum(total(k)[1] * n for k, n in group.items())
        out.append({"board": board, "family": family, "module": path, "depth": depth,
                    "instances": sum(group.values()), "luts": luts, "ffs": ffs})
        below: dict[str, Counter] = {}
        for key, n in group.items():
            for child, m in children(key):
                below.setdefault(base_name(child), Counter())[child] += n * m
        for name in sorted(below, key=lambda c: -sum(total(k)[0] * m for k, m in below[c].items())):
            walk(below[name], f"{path}/{name}", depth + 1)

    walk(Counter({f"\\{BOARD_TOP}": 1}), BOARD_TOP, 0)
    return out


def collect() -> list[dict]:
    """Rows of every board whose build has a modules.json."""
    out = []
    for name, board in BOARDS.items():
        stat = BUILD / f"board_{name}" / "modules.json"
        if stat.exists():
            out += rows(json.loads(stat.read_text()), name, board.family)
    return out


def read_rows(path: Path = CSV) -> list[dict]:
    """The rows of a CSV file (this module's or docs/boards.csv) as dicts of strings."""
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def table(rows: list[dict]) -> str:
    """Markdown: one line per module instance (depth-first, indented), a LUTs / FFs column
    pair per board; instances below SHARE of the top's LUTs in every board are left out."""
    boards = list(dict.fromkeys(r["board"] for r in rows))
    by = {(r["board"], r["module"]): r for r in rows}
    tops = {b: int(by[(b, BOARD_TOP)]["luts"]) for b in boards}
    order: list[str] = []           # each board's depth-first order, merged
    for b in boards:
        previous = None
        for r in rows:
            if r["board"] != b:
                continue
            if r["module"] not in order:
                order.insert(order.index(previous) + 1 if previous else len(order), r["module"])
            previous = r["module"]
    head = "| module | " + " | ".join(f"{b} LUTs | {b} FFs" for b in boards) + " |"
    out = [head, "|---|" + "---|---|" * len(boards)]
    for module in order:
        cells = [by.get((b, module)) for b in boards]
        if not any(c and int(c["luts"]) >= SHARE * tops[b] for b, c in zip(boards, cells)):
            continue
        first = next(c for c in cells if c)
        name = module.rsplit("/", 1)[-1]
        label = "· " * int(first["depth"]) + f"`{name}`" + (f" × {first['instances']}"
                                                           if int(first["instances"]) > 1 else "")
        out.append(f"| {label} | " + " | ".join(f"{c['luts']} | {c['ffs']}" if c else "— | —"
                                                 for c in cells) + " |")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    path = Path(argv[0]) if argv else CSV
    found = collect()
    if not found:
        print("board_area: no build/synth/board_*/modules.json: run `make bitstream` first", file=sys.stderr)
        return 1
    # a board not built here keeps its rows
    kept = [r for r in (read_rows(path) if path.exists() else [])
            if r["board"] not in {f["board"] for f in found}]
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, HEADER)
        w.writeheader()
        w.writerows(kept + found)
    print(f"board_area: {len(kept) + len(found)} rows -> {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
