# SPDX-License-Identifier: Apache-2.0
"""`interp wave CORE`: a core's built-in example to out/<CORE>.vcd, opened in GTKWave.

  interp wave CORE [--out DIR] [--no-open]

CORE is a CLI core name (circ-arc, curve, su1571551, lin-exact, su1665343) or
`motion` (the G-code demo program through motion_top).  The run writes
DIR/<CORE>.vcd (Icarus) and DIR/<CORE>.gtkw: the save file sim/<module>.gtkw
with its dump file, its vector ranges (from the VCD) and its zoom set so the
window shows the whole run (GTKWave also runs a one-line Tcl script that
zooms to the whole run whatever the window's size).  Without a display (DISPLAY unset) or without
gtkwave it says so in one line and leaves the two files.

GTKWave's zoom.  The save file's `*Z ...` line holds the zoom Z; GTKWave 3.3
shows 2^-Z / 200 VCD time units per pixel (measured on GTKWave 3.3.118 under
Xvfb: Z = -4 shows 0.08 ps per pixel of a 1 ps VCD, Z = -20 shows 5.2 ns).
`[timestart]` is the left edge.  Codes (states, command kinds, error codes)
are shown by name through translate filter files, sim/filters/*.txt (one
"value name" a line): the save files name them from the repository root,
the written save file by absolute path.  The save files' window is [size] 1400 x 800
with the signal tree (sst_width) and names (signals_width) on the left; the
rest, less a margin, is the wave area that `fit_zoom` fills.
"""
from __future__ import annotations

import math
import os
import re
import shutil
import subprocess
from pathlib import Path

from ..cores import REGISTRY, UsageError

ROOT = Path(__file__).resolve().parents[2]
SIM = ROOT / "sim"
MOTION = "motion"
ZOOM_UNITS_PER_PIXEL = 1 / 200      # GTKWave 3.3: units per pixel = 2^-zoom / 200
MARGIN_PX = 160                     # window chrome, scroll bar and some room on the right


# ---- VCD reading ------------------------------------------------------------------------

def vcd_signals(path) -> dict[str, str]:
    """Hierarchical names in the VCD header: {'top.sub.name': 'top.sub.name[7:0]'}."""
    scope: list[str] = []
    names: dict[str, str] = {}
    with open(path) as f:
        for line in f:
            words = line.split()
            if not words:
                continue
            if words[0] == "$scope":
                scope.append(words[2])
            elif words[0] == "$upscope":
                scope.pop()
            elif words[0] == "$var":
                # $var wire 32 ! x0 [31:0] $end   (Icarus puts the range apart)
                ref = words[4]
                rng = words[5] if len(words) > 6 and words[5].startswith("[") else ""
                base = ".".join(scope + [ref.split("[")[0]])
                names[base] = ".".join(scope + [ref]) + rng if "[" not in ref else ".".join(scope + [ref])
            elif words[0] == "$enddefinitions":
                break
    return names


def vcd_timescale(path) -> tuple[int, str]:
    """The VCD's $timescale as (number, unit), e.g. (1, 'ps')."""
    text = Path(path).read_text(errors="replace")[:4096]
    m = re.search(r"\$timescale\s+(\d+)\s*([munpf]?s)\s+\$end", text)
    if not m:
        raise RuntimeError(f"{path}: no $timescale in the VCD header")
    return int(m.group(1)), m.group(2)


def vcd_end_time(path) -> int:
    """The last time stamp (#N) of the VCD, in its time units."""
    size = os.path.getsize(path)
    with open(path, "rb") as f:
        f.seek(max(0, size - 65536))
        tail = f.read().decode(errors="replace")
    stamps = re.findall(r"^#(\d+)", tail, re.M)
    if not stamps:
        raise RuntimeError(f"{path}: no time stamp in the VCD")
    return int(stamps[-1])


# ---- save files -------------------------------------------------------------------------

def save_file_filters(text: str) -> list[str]:
    """The translate filter files (`^N path`, paths from the repository root) a save file uses."""
    return [line.split(" ", 1)[1] for line in text.splitlines() if re.match(r"\^\d+ ", line)]


def save_file_signals(text: str) -> list[str]:
    """The signal names a save file shows (aliases removed), in order."""
    out = []
    for line in text.splitlines():
        if not line or line[0] in "[@-*#^":
            continue
        out.append(line.split("} ", 1)[1] if line.startswith("+{") else line)
    return out


def wave_width(text: str) -> int:
    """Pixels of the wave area of the save file's window."""
    def number(key, default):
        m = re.search(rf"^\[{key}\]\s+(\d+)", text, re.M)
        return int(m.group(1)) if m else default
    size = re.search(r"^\[size\]\s+(\d+)", text, re.M)
    width = int(size.group(1)) if size else 1000
    return max(100, width - number("sst_width", 200) - number("signals_width", 200) - MARGIN_PX)


def zoom_for(end: int, pixels: int) -> float:
    """The GTKWave zoom that shows 0 .. end (VCD units) in `pixels`."""
    units_per_px = max(end, 1) / pixels
    return math.floor(-math.log2(units_per_px / ZOOM_UNITS_PER_PIXEL) * 1e6) / 1e6  # 6 places, not less


def visible_span(text: str) -> tuple[int, float]:
    """(left edge, time units shown) of a save file's window."""
    start = re.search(r"^\[timestart\]\s+(\d+)", text, re.M)
    zoom = re.search(r"^\*(-?[\d.]+)", text, re.M)
    if not zoom:
        return (int(start.group(1)) if start else 0, 0.0)
    return (int(start.group(1)) if start else 0,
            wave_width(text) * 2 ** -float(zoom.group(1)) * ZOOM_UNITS_PER_PIXEL)


def fit(text: str, vcd, dumpfile: str | None = None) -> tuple[str, list[str]]:
    """The save file with its zoom set to the VCD's whole run, its vector ranges taken
    from the VCD and (given) its dump file; also the signals the VCD lacks."""
    names = vcd_signals(vcd)
    zoom = zoom_for(vcd_end_time(vcd), wave_width(text))
    zoom_line = f"*{zoom:.6f} 0" + " -1" * 26
    missing = []
    out = []
    for line in text.splitlines():
        if line.startswith("*"):
            line = zoom_line
        elif line.startswith("[timestart]"):
            line = "[timestart] 0"
        elif line.startswith("[dumpfile]") and dumpfile:
            line = f'[dumpfile] "{dumpfile}"'
        elif re.match(r"\^\d+ ", line):          # translate filter file: absolute path
            number, path = line[1:].split(" ", 1)
            line = f"^{number} {(ROOT / path).resolve() if not Path(path).is_absolute() else path}"
        elif line and line[0] not in "[@-#^":
            alias, name = (line.split("} ", 1)[0] + "} ", line.split("} ", 1)[1]) \
                if line.startswith("+{") else ("", line)
            base = name.split("[")[0]
            if base in names:
                line = alias + names[base]
            else:
                missing.append(name)
        out.append(line)
    if not any(line.startswith("*") for line in out):      # no zoom line yet: after [pos]
        at = next((i + 1 for i, line in enumerate(out) if line.startswith("[pos]")), 0)
        out.insert(at, zoom_line)
    return "\n".join(out) + "\n", missing


# ---- the runs -----------------------------------------------------------------------------

def targets() -> dict[str, str]:
    """CLI name -> Verilog module, for every core with a save file sim/<module>.gtkw."""
    found = {name: core.toplevel for name, core in REGISTRY.items() if (SIM / f"{core.toplevel}.gtkw").exists()}
    found[MOTION] = "motion_top"
    return found


def run_example(name: str, vcd: Path, out: Path) -> None:
    """The core's first built-in example (or the G-code demo) through Icarus, to `vcd`."""
    from ..cli import build_parser

    if name == MOTION:
        from .gcode import DEMO, DEMO_OPTIONS

        src = out / "motion_demo.nc"
        src.write_text(DEMO)
        argv = ["gcode", str(src), *DEMO_OPTIONS, "--sim", "icarus", "--steps", str(out / f"{name}_steps.csv"),
                "--vcd", str(vcd)]
    else:
        if not REGISTRY[name].examples:
            raise UsageError(f"core {name} has no built-in example to run")
        argv = ["run", name, *REGISTRY[name].examples[0], "--steps", str(out / f"{name}_steps.csv"),
                "--vcd", str(vcd)]
    args = build_parser().parse_args(argv)
    if args.func(args):
        raise RuntimeError(f"the {name} example failed")


def make_wave(name: str, out) -> tuple[Path, Path]:
    """Run the example, write DIR/<name>.vcd and the fitted DIR/<name>.gtkw."""
    found = targets()
    if name not in found:
        raise UsageError(f"no save file for {name!r}; choose from {', '.join(sorted(found))}")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    vcd, save = out / f"{name}.vcd", out / f"{name}.gtkw"
    run_example(name, vcd, out)
    text, missing = fit((SIM / f"{found[name]}.gtkw").read_text(), vcd, str(vcd.resolve()))
    for signal in missing:
        print(f"interp wave: {signal} (in sim/{found[name]}.gtkw) is not in {vcd}")
    save.write_text(text)
    return vcd, save


def add_parser(sub) -> None:
    p = sub.add_parser("wave", help="a core's example to a VCD, opened in GTKWave with its save file")
    p.add_argument("core", help="circ-arc, curve, su1571551, lin-exact, su1665343 or motion")
    p.add_argument("--out", default="out", help="output folder (default out)")
    p.add_argument("--no-open", action="store_true", help="write the files, do not start GTKWave")
    p.set_defaults(func=run)


def run(args) -> int:
    vcd, save = make_wave(args.core, args.out)
    print(f"{args.core}: {vcd} {save}")
    if args.no_open:
        return 0
    if not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
        print(f"interp wave: no display (DISPLAY unset): open it elsewhere with `gtkwave {vcd} {save}`")
        return 0
    if not shutil.which("gtkwave"):
        print(f"interp wave: gtkwave is not installed (apt-get install gtkwave), then `gtkwave {vcd} {save}`")
        return 0
    script = save.with_suffix(".tcl")           # zoom to the whole run in any window size
    script.write_text("gtkwave::/Time/Zoom/Zoom_Full\n")
    subprocess.run(["gtkwave", "-S", str(script), str(vcd), str(save)], check=False)
    return 0
