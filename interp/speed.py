"""Native (no cocotb) runs of the sim/ harnesses, to measure simulation speed.

`run_harness` compiles a self-running testbench with Icarus (iverilog/vvp) or
Verilator (`--binary`), runs it, and returns its printed `key=value` pairs
and the run's wall time (compile time excluded).
"""
from __future__ import annotations

import re
import subprocess
import time

from .sim import RTL, ROOT, SIMULATORS, verilator_bin


def build_harness(harness: str, sim: str, defines: dict | None = None) -> list[str]:
    """Compile sim/<harness>.v; return the command that runs it."""
    if sim not in SIMULATORS:
        raise ValueError(f"unknown simulator {sim!r}")
    src = ROOT / "sim" / f"{harness}.v"
    tag = "_".join(f"{k}{v}" for k, v in sorted((defines or {}).items()))
    out = ROOT / "sim_build" / "native" / sim / f"{harness}_{tag}"
    out.mkdir(parents=True, exist_ok=True)
    dflags = [f"-D{k}={v}" for k, v in (defines or {}).items()]
    if sim == "icarus":
        image = out / "sim.vvp"
        subprocess.run(["iverilog", "-g2005", "-o", str(image), "-y", str(RTL), "-s", harness,
                        *dflags, str(src)], check=True, capture_output=True, text=True)
        return ["vvp", "-n", str(image)]
    verilator = str(verilator_bin() / "verilator")
    subprocess.run([verilator, "--binary", "-O3", "--quiet", "-Wno-fatal", "-Wno-lint", "-Wno-style",
                    "-y", str(RTL), "--top-module", harness, "-Mdir", str(out), "-o", harness,
                    "-CFLAGS", "-O2 -std=c++20 -fcoroutines", *dflags, str(src)],
                   check=True, capture_output=True, text=True)
    return [str(out / harness)]


def run_harness(harness: str, sim: str, defines: dict | None = None,
                plusargs: list[str] | None = None) -> tuple[dict[str, int], float]:
    cmd = build_harness(harness, sim, defines) + list(plusargs or [])
    t0 = time.perf_counter()
    done = subprocess.run(cmd, check=True, capture_output=True, text=True)
    seconds = time.perf_counter() - t0
    values = {k: int(v) for k, v in re.findall(r"(\w+)=(-?\d+)", done.stdout)}
    return values, seconds
