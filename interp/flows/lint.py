# SPDX-License-Identifier: Apache-2.0
"""Verilator lint (`make lint`, `python -m interp.flows.lint`): every rtl/ module, -Wall.

Each module is linted on its portable file list (rtl/*.v) and, for each FPGA
family with forms in rtl/<family>/, on that family's list (the family's form of
every module it uses; see interp/flows/synth.py `sources`); each board's top
(boards/<board>/top.v) on its family's list.  A family form (or a top) may
instance the family's primitive cells (SB_CARRY, CCU2C, ...): for those the lint
reads port-and-parameter stubs made from Yosys's cell library, whose own
warnings are switched off.  One line per failure; exit status 1 if any.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

from ..simulation.runner import ROOT, RTL, verilator_bin

BUILD = ROOT / "build" / "lint"
FAMILIES = ("ice40", "ecp5")
_MODULE = re.compile(r"^module\s+([A-Za-z_]\w*)\s*(#\s*\(.*?\)\s*)?\((.*?)\);(.*?)^endmodule", re.S | re.M)


def _cell_library(family: str) -> dict[str, str]:
    """Primitive name -> stub text (ports and parameters) from Yosys's simulation models."""
    from .synth import yosys_share

    out = {}
    for path in sorted((yosys_share() / family).glob("*")):
        if path.suffix not in (".v", ".vh") or path.stem.endswith("_map"):
            continue
        text = re.sub(r"//[^\n]*|/\*.*?\*/|\(\*.*?\*\)", " ", path.read_text(), flags=re.S)
        text = re.sub(r"`\w+", " ", text)                 # macros (default assignments, ifdefs)
        for m in _MODULE.finditer(text):
            name, header_params, ports, body = m.groups()
            params = re.findall(r"^\s*(?:parameter|localparam)\b[^;]*;", body, re.M)
            params = [p for p in params if not p.strip().startswith("localparam")]
            decls = re.findall(r"^\s*(?:input|output|inout)\b[^;]*;", body, re.M) if \
                not re.search(r"\b(input|output|inout)\b", ports) else []
            out.setdefault(name, f"module {name} {header_params or ''}({ports});\n"
                           + "".join(p.strip() + "\n" for p in params + decls) + "endmodule\n")
    return out


def cell_stubs(family: str, files: list[Path]) -> list[Path]:
    """Stub file and Verilator config for the primitives `files` instance ([] if none)."""
    from .synth import _tokens

    used = set().union(*(_tokens(f) for f in files))
    library = _cell_library(family)
    names = sorted(n for n in used if n in library)
    if not names:
        return []
    stubs = _write(BUILD / f"{family}_cells_{'_'.join(names)}.v", "".join(library[n] for n in names))
    config = _write(BUILD / "cells.vlt", f'`verilator_config\nlint_off -file "{BUILD}/*_cells_*.v"\n')
    return [config, stubs]


def _write(path: Path, text: str) -> Path:
    """Write atomically (parallel lints read the same files)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text() != text:
        tmp = path.with_name(f".{path.name}.{os.getpid()}")
        tmp.write_text(text)
        os.replace(tmp, path)
    return path


def lint(toplevel: str, files: list[Path], family: str | None = None,
         parameters: dict | None = None) -> str | None:
    """Verilator -Wall on `files` (top first): None if clean, else its first message (one line)."""
    extra = cell_stubs(family, files) if family else []
    cmd = [str(verilator_bin() / "verilator"), "--lint-only", "-Wall", "--quiet",
           "--top-module", toplevel, f"-I{RTL}", *[f"-G{k}={v}" for k, v in (parameters or {}).items()],
           *[str(f) for f in extra + list(files)]]
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode == 0:
        return None
    lines = [ln.strip() for ln in run.stderr.splitlines() if ln.startswith("%")]
    first = lines[0] if lines else (run.stderr.strip().splitlines() or [f"exit status {run.returncode}"])[0]
    return first.replace(str(ROOT) + "/", "")


def main(argv: list[str] | None = None) -> int:
    from .synth import sources

    modules = sorted(p.stem for p in RTL.glob("*.v"))
    families = [f for f in FAMILIES if any((RTL / f).glob("*.v"))]
    failed = checked = 0
    for family in [None, *families]:
        for module in modules:
            files = sources(module, family)
            if family and not any(f.parent.name == family for f in files):
                continue                    # the same file list as the portable one
            checked += 1
            message = lint(module, files, family)
            if message:
                failed += 1
                print(f"lint: {module}{' on ' + family if family else ''}: {message}")
    # The boards' tops (boards/<board>/top.v, vendor cells allowed) on their family's list.
    from .synth import BOARDS, FlowError, board_lint
    for name, board in BOARDS.items():
        checked += 1
        try:
            message = board_lint(board)
        except FlowError as exc:
            message = str(exc)
        if message:
            failed += 1
            print(f"lint: boards/{name}/top.v on {board.family}: {message}")
    forms = sum(len(list((RTL / f).glob("*.v"))) for f in families)
    print(f"lint: {len(modules)} modules, {forms} family forms and {len(BOARDS)} board tops, {checked} file lists: "
          + (f"{failed} FAILED" if failed else "clean") + " (verilator --lint-only -Wall)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
