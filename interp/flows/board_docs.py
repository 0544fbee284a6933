# SPDX-License-Identifier: Apache-2.0
"""The generated tables of docs/boards.md: each board's pins (from its pin file),
the resources (from docs/boards.csv, a copy of `make bitstream`'s
out/bitstream/boards.csv) and the area per module (from docs/board_area.csv, a
copy of out/bitstream/board_area.csv: see board_area.py).

    python -m interp.flows.board_docs            rewrite the tables in docs/boards.md
    python -m interp.flows.board_docs --check    exit 1 if a table is stale

A pin file line names one port of boards/<board>/top.v, its FPGA site, and a
comment `<board net> | <header> | <what it is>` (tests/test_boards.py checks
that every port of the top has exactly one line).
"""
from __future__ import annotations

import csv
import re
import sys
from dataclasses import dataclass
from pathlib import Path

from ..simulation.runner import ROOT
from . import board_area
from .synth import BOARD_CSV_HEADER, BOARDS, BOARDS_DIR

DOC = ROOT / "docs" / "boards.md"
CSV = ROOT / "docs" / "boards.csv"
_PCF = re.compile(r"^set_io\s+(?:-\w+\s+\w+\s+)*(\S+)\s+(\S+)\s*#\s*(.*)$")
_LPF = re.compile(r'^LOCATE\s+COMP\s+"([^"]+)"\s+SITE\s+"([^"]+)"\s*;\s*#\s*(.*)$')


@dataclass(frozen=True)
class Pin:
    port: str       # top port bit, e.g. step[0]
    site: str       # FPGA ball
    net: str        # the board's name for it
    header: str     # connector (or "-")
    what: str
    pullup: bool = False


def pins(board: str) -> list[Pin]:
    """The pin file's assignments, in file order."""
    b = BOARDS[board]
    text = (BOARDS_DIR / board / b.pins).read_text()
    out = []
    pulled = set(re.findall(r'IOBUF\s+PORT\s+"([^"]+)"\s+PULLMODE=UP', text))
    for line in text.splitlines():
        m = (_PCF if b.pin_option == "--pcf" else _LPF).match(line.strip())
        if not m:
            continue
        port, site, comment = m.groups()
        fields = [f.strip() for f in comment.split("|")]
        if len(fields) != 3:
            raise ValueError(f"{b.pins}: comment of {port} is not 'net | header | what': {comment!r}")
        pullup = ("-pullup yes" in line) if b.pin_option == "--pcf" else (port in pulled)
        out.append(Pin(port, site, *fields, pullup))
    return out


def top_ports(board: str) -> dict[str, str]:
    """Every bit of boards/<board>/top.v's ports: name[i] (or name) -> input | output."""
    text = re.sub(r"//[^\n]*|/\*.*?\*/", " ", BOARDS[board].top.read_text(), flags=re.S)
    header = text[text.index("module"):text.index(");", text.index(") ("))]
    out = {}
    for direction, rng, name in re.findall(r"\b(input|output)\s+wire\s*(\[\s*\d+\s*:\s*\d+\s*\])?\s*(\w+)",
                                           header):
        if rng:
            hi, lo = map(int, re.findall(r"\d+", rng))
            for i in range(min(hi, lo), max(hi, lo) + 1):
                out[f"{name}[{i}]"] = direction
        else:
            out[name] = direction
    return out


def pin_table(board: str) -> str:
    ports = top_ports(board)
    rows = ["| port | direction | FPGA pin | board net | header | function |",
            "|---|---|---|---|---|---|"]
    for p in pins(board):
        direction = ports.get(p.port, "?") + (", pull-up" if p.pullup else "")
        rows.append(f"| `{p.port}` | {direction} | {p.site} | {p.net} | {p.header} | {p.what} |")
    return "\n".join(rows)


def read_rows(path: Path = CSV) -> list[dict]:
    return board_area.read_rows(path)


def resources_table(rows: list[dict]) -> str:
    out = ["| board | family | device | clock MHz | Fmax MHz | LUTs / capacity | FFs | BRAMs | note |",
           "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        luts = r["luts"] + (f" / {r['lut_capacity']}" if r.get("lut_capacity") else "")
        if r.get("lut_capacity") and r.get("luts"):
            luts += f" ({100 * int(r['luts']) / int(r['lut_capacity']):.0f} %)"
        out.append(f"| {r['board']} | {r['family']} | {r['device']} | {r['clock_mhz']} | "
                   f"{r['fmax_mhz'] or '-'} | {luts} | {r['ffs']} | {r['brams'] or '-'} | {r.get('note') or ''} |")
    return "\n".join(out)


def section(name: str) -> tuple[str, str]:
    return f"<!-- {name}:begin -->", f"<!-- {name}:end -->"


def render(text: str) -> str:
    """docs/boards.md with every generated table filled in."""
    blocks = {f"pins-{b}": pin_table(b) for b in BOARDS}
    blocks["resources"] = resources_table(read_rows()) if CSV.exists() else \
        "_No figures yet: run `make bitstream` and copy out/bitstream/boards.csv to docs/boards.csv._"
    blocks["area"] = board_area.table(board_area.read_rows()) if board_area.CSV.exists() else \
        "_No figures yet: run `make bitstream` and copy out/bitstream/board_area.csv to docs/._"
    for name, table in blocks.items():
        begin, end = section(name)
        if begin not in text or end not in text:
            raise ValueError(f"docs/boards.md: no {begin} ... {end} block")
        text = text[:text.index(begin) + len(begin)] + "\n" + table + "\n" + text[text.index(end):]
    return text


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    text = DOC.read_text()
    try:
        new = render(text)
    except (ValueError, KeyError, OSError) as exc:     # a missing block, a bad CSV or pin file
        print(f"board_docs: {exc}", file=sys.stderr)
        return 1
    if CSV.exists():
        header = next(csv.reader(open(CSV, newline="")))
        if header != BOARD_CSV_HEADER:
            print(f"board_docs: docs/boards.csv header is {','.join(header)}, "
                  f"expected {','.join(BOARD_CSV_HEADER)}", file=sys.stderr)
            return 1
    if "--check" in argv:
        if new != text:
            print("board_docs: docs/boards.md tables are stale: python -m interp.flows.board_docs",
                  file=sys.stderr)
            return 1
        return 0
    DOC.write_text(new)
    return 0


if __name__ == "__main__":
    sys.exit(main())
