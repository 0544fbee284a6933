# SPDX-License-Identifier: Apache-2.0
"""Datasheets in docs/cores: timing diagrams, port tables, resource tables.

  python -m interp.docs waves       re-simulate each page's command (Icarus) -> docs/cores/wavedrom/<m>.json
  python -m interp.docs svg         WaveDrom JSON -> SVG (docs/cores/wavedrom/<m>.svg)
  python -m interp.docs resources   fill each page's resources table from docs/resources.csv
  python -m interp.docs check       report stale SVGs, port tables, resource tables, missing pages

`make docs` runs svg and resources (and waves with DOCS_WAVES=1).  The tests in
tests/test_docs.py use the functions below, so a page that drifts from the RTL,
from the CSV or from its JSON fails there with a one-line message.
"""
from __future__ import annotations

import argparse
import csv
import json
import re
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RTL = ROOT / "rtl"
DOCS = ROOT / "docs"
PAGES = DOCS / "cores"
WAVES = PAGES / "wavedrom"
RESOURCES_CSV = DOCS / "resources.csv"

# One datasheet per module, in the order of the index.
MODULES = ["su1571551", "lin_exact", "circ_su1665343", "lin_std", "lin_accel", "circ_quadrant",
           "circ_arc", "curve_tangent", "motion_top", "step_pacer", "step_sync", "step_dir", "sync_fifo"]

PORTS_BEGIN, PORTS_END = "<!-- ports:begin -->", "<!-- ports:end -->"
RES_BEGIN, RES_END = "<!-- resources:begin -->", "<!-- resources:end -->"


# ------------------------------------------------------------------ ports

@dataclass(frozen=True)
class Port:
    name: str
    direction: str      # input / output / inout
    width: str          # "1", "WIDTH", "PW+4", "3", ...
    comment: str = field(default="", compare=False)


_PORT = re.compile(r"^\s*(input|output|inout)\s+(?:wire\s+|reg\s+)?(?:signed\s+)?(\[[^\]]*\])?\s*(\w+)\s*,?\s*(?://\s*(.*))?$")


def width_of(rng: str | None) -> str:
    """[WIDTH-1:0] -> WIDTH, [7:0] -> 8, [PW+3:0] -> PW+4, none -> 1."""
    if not rng:
        return "1"
    msb, _, lsb = rng.strip("[]").partition(":")
    msb, lsb = msb.replace(" ", ""), lsb.replace(" ", "")
    if lsb != "0":
        return f"{msb}-{lsb}+1"
    if msb.isdigit():
        return str(int(msb) + 1)
    m = re.fullmatch(r"(.+)-1", msb)
    if m:
        return m.group(1)
    m = re.fullmatch(r"(.+)\+(\d+)", msb)
    if m:
        return f"{m.group(1)}+{int(m.group(2)) + 1}"
    return f"{msb}+1"


def rtl_ports(module: str, rtl: Path = RTL) -> list[Port]:
    """The ports of rtl/<module>.v's ANSI header, in order."""
    text = (rtl / f"{module}.v").read_text()
    start = re.search(rf"^\s*module\s+{module}\b", text, re.M)
    if not start:
        raise ValueError(f"rtl/{module}.v has no module {module}")
    body = text[start.end():]
    # the port list: after the parameter list's ") (" (or the first "("), up to ");"
    m = re.search(r"\)\s*\(", body) if re.match(r"\s*#\s*\(", body) else re.search(r"\(", body)
    header = body[m.end():body.index(");", m.end())]
    ports = []
    for line in header.splitlines():
        pm = _PORT.match(line)
        if pm:
            ports.append(Port(pm.group(3), pm.group(1), width_of(pm.group(2)), (pm.group(4) or "").strip()))
    return ports


@dataclass(frozen=True)
class Parameter:
    name: str
    default: str
    comment: str


def rtl_parameters(module: str, rtl: Path = RTL) -> list[Parameter]:
    text = (rtl / f"{module}.v").read_text()
    start = re.search(rf"^\s*module\s+{module}\b", text, re.M)
    body = text[start.end():]
    if not re.match(r"\s*#\s*\(", body):
        return []
    header = body[:re.search(r"\)\s*\(", body).start()]
    return [Parameter(n, d.strip(), (c or "").strip()) for n, d, c in
            re.findall(r"parameter\s+(?:integer\s+)?(\w+)\s*=\s*([^,/\n]+),?\s*(?://\s*(.*))?", header)]


def verilator_ports(module: str, rtl: Path = RTL) -> list[tuple[str, str, int]]:
    """(name, direction, width) of the module's ports at its default parameters, as
    Verilator elaborates them (--json-only): an independent check of rtl_ports."""
    import subprocess

    from .simulation.runner import verilator_bin

    with tempfile.TemporaryDirectory() as tmp:
        run = subprocess.run([str(verilator_bin() / "verilator"), "--json-only", "-Wno-fatal", "-Wno-lint",
                              "-Wno-style", f"-I{rtl}", "--top-module", module, str(rtl / f"{module}.v"),
                              "-Mdir", tmp], capture_output=True, text=True)
        trees = list(Path(tmp).glob("*.tree.json"))
        if run.returncode or not trees:
            raise RuntimeError(f"verilator --json-only failed on rtl/{module}.v: {run.stderr.strip()[:300]}")
        tree = json.loads(trees[0].read_text())
    types, ports = {}, []

    def walk(node):
        if isinstance(node, dict):
            if node.get("type") == "BASICDTYPE":
                types[node["addr"]] = node.get("range")
            if node.get("type") == "VAR" and node.get("isPrimaryIO"):
                ports.append((node["name"], node["direction"].lower(), node["dtypep"]))
            for value in node.values():
                walk(value)
        elif isinstance(node, list):
            for value in node:
                walk(value)

    walk(tree)
    out = []
    for name, direction, dtype in ports:
        rng = types.get(dtype)
        msb, lsb = (int(v) for v in rng.split(":")) if rng else (0, 0)
        out.append((name, direction, abs(msb - lsb) + 1))
    return out


def width_value(width: str, parameters: dict[str, int]) -> int:
    """A width expression of rtl_ports ("WIDTH", "PW+4", ...) at the given parameter values."""
    expr = re.sub(r"[A-Za-z_]\w*", lambda m: str(parameters[m.group(0)]), width)
    if not re.fullmatch(r"[\d+\-*() ]+", expr):
        raise ValueError(f"width expression {width!r}")
    return int(eval(expr))      # digits and + - * ( ) only


def default_parameters(module: str, rtl: Path = RTL) -> dict[str, int]:
    """Each parameter's default; a default may be an expression of the ones before it
    (names, digits, + - * ( ), comparisons and one `c ? a : b`)."""
    values: dict[str, int] = {}
    for p in rtl_parameters(module, rtl):
        values[p.name] = _default_value(p.default, values)
    return values


def _default_value(text: str, known: dict[str, int]) -> int:
    if "?" in text:
        condition, rest = text.split("?", 1)
        if_true, if_false = rest.split(":", 1)
        chosen = if_true if _default_value(condition, known) else if_false
        return _default_value(chosen, known)
    expr = re.sub(r"[A-Za-z_]\w*", lambda m: str(known[m.group(0)]), text)
    if not re.fullmatch(r"[\d+\-*()<>= ]+", expr):
        raise ValueError(f"parameter default {text!r}")
    return int(eval(expr))      # digits, + - * ( ) and comparisons only


def _cells(line: str) -> list[str]:
    return [c.strip().strip("`").strip() for c in line.strip().strip("|").split("|")]


def page_ports(page: Path) -> list[Port]:
    """The ports table between the ports markers: name, direction, width (meaning not compared)."""
    text = page.read_text()
    if PORTS_BEGIN not in text or PORTS_END not in text:
        raise ValueError(f"{page.name}: no {PORTS_BEGIN} ... {PORTS_END} table")
    block = text[text.index(PORTS_BEGIN) + len(PORTS_BEGIN):text.index(PORTS_END)]
    rows = [line for line in block.splitlines() if line.strip().startswith("|")]
    ports = []
    for line in rows[2:]:                       # header and separator rows first
        name, direction, width = _cells(line)[:3]
        ports.append(Port(name, direction, width.replace(" ", "")))
    return ports


def ports_diff(module: str, page: Path | None = None, rtl: Path = RTL, source: str | None = None) -> list[str]:
    """One line per difference between the page's ports table and the ports of
    rtl/<source>.v (source: the module itself unless given)."""
    page = page or PAGES / f"{module}.md"
    source = source or module
    want, have = rtl_ports(source, rtl), page_ports(page)
    rel = _rel(page)
    lines = []
    want_by, have_by = {p.name: p for p in want}, {p.name: p for p in have}
    for p in want:
        if p.name not in have_by:
            lines.append(f"{rel}: port {p.name} ({p.direction}, {p.width}) of rtl/{source}.v missing from the table")
        elif have_by[p.name] != p:
            q = have_by[p.name]
            lines.append(f"{rel}: port {p.name}: table says {q.direction} {q.width}, "
                         f"rtl/{source}.v says {p.direction} {p.width}")
    for p in have:
        if p.name not in want_by:
            lines.append(f"{rel}: port {p.name} in the table is not a port of rtl/{source}.v")
    if not lines and [p.name for p in want] != [p.name for p in have]:
        lines.append(f"{rel}: ports table order differs from rtl/{source}.v: "
                     f"{' '.join(p.name for p in want)}")
    return lines


def port_source(module: str, rtl: Path = RTL) -> str:
    """The RTL whose ports a page documents: the module's own file; lin_exact's page
    (same ports as su1571551) reads su1571551's until rtl/lin_exact.v exists."""
    if module == "lin_exact" and not (rtl / "lin_exact.v").exists():
        return "su1571551"
    return module


def ports_table(module: str, source: str | None = None) -> str:
    """A ports table drawn from the RTL (a page's starting point; meanings from its comments)."""
    rows = ["| port | direction | width | meaning |", "|---|---|---|---|"]
    for p in rtl_ports(source or module):
        rows.append(f"| `{p.name}` | {p.direction} | {p.width} | {p.comment} |")
    return "\n".join(rows)


# ------------------------------------------------------------------ resources

# The flow's CSV names cores by the command line's name (a variant after '/');
# these are the ones that differ from their module's name.
ALIASES = {"su1665343": "circ_su1665343", "curve": "curve_tangent"}


# Modules the synthesis flow does not build on their own, and why.
NOT_SYNTHESIZED = {"sync_fifo": "the synthesis flow does not build it on its own; "
                                "it is counted inside `step_sync` and `motion_top`"}


def module_of(core: str) -> str | None:
    base = core.split("/")[0].replace("-", "_")
    base = ALIASES.get(base, base)
    return base if base in MODULES or (RTL / f"{base}.v").exists() else None


def resource_pages(pages: Path = PAGES) -> list[tuple[str, Path]]:
    """(module, page) for every datasheet with a resources table: the indexed modules'
    pages and any other page that carries the markers (named like its module)."""
    found = {m: pages / f"{m}.md" for m in MODULES if (pages / f"{m}.md").exists()}
    for page in sorted(pages.glob("*.md")):
        if page.stem not in found and RES_BEGIN in page.read_text():
            found[page.stem] = page
    return list(found.items())


def read_resources(path: Path = RESOURCES_CSV) -> list[dict]:
    if not path.exists():
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def resources_table(module: str, rows: list[dict]) -> str:
    mine = [r for r in rows if module_of(r["core"]) == module]
    if not mine:
        if not rows:
            return "_No figures yet: docs/resources.csv is missing. Run `make synth` and `make docs`._"
        if module in NOT_SYNTHESIZED:
            return f"_No row in docs/resources.csv: {NOT_SYNTHESIZED[module]}._"
        return ("_No row for this module in docs/resources.csv yet: `make synth`, copy out/synth.csv "
                "to docs/resources.csv, `make docs`._")
    lines = ["| build (flow name) | family | device | Fmax (MHz) | placements (median MHz) | LUTs (of the device's) | FFs |",
             "|---|---|---|---|---|---|---|"]
    for r in mine:
        fmax = r.get("fmax_mhz") or "—"
        median = re.search(r"median ([0-9.]+)", r.get("note") or "")
        seeds = (f"{r['seeds']}" + (f" ({median.group(1)})" if median else "")) if r.get("seeds") not in (None, "", "0") else "—"
        luts = f"{r['luts']} of {r['lut_capacity']}" if r.get("lut_capacity") else r["luts"]
        lines.append(f"| `{r['core']}` | {r['family']} | {r['device']} | {fmax} | {seeds} | {luts} | {r['ffs']} |")
    if any(not r.get("fmax_mhz") for r in mine):
        lines.append("\n— : does not fit that device (the flow reports its area after synthesis, no Fmax).")
    return "\n".join(lines)


def with_resources(text: str, module: str, rows: list[dict]) -> str:
    if RES_BEGIN not in text or RES_END not in text:
        raise ValueError(f"{module}.md: no {RES_BEGIN} ... {RES_END} markers")
    head, rest = text.split(RES_BEGIN, 1)
    _, tail = rest.split(RES_END, 1)
    return f"{head}{RES_BEGIN}\n{resources_table(module, rows)}\n{RES_END}{tail}"


def update_resources(csv_path: Path = RESOURCES_CSV) -> list[Path]:
    rows, changed = read_resources(csv_path), []
    for module, page in resource_pages():
        text = page.read_text()
        new = with_resources(text, module, rows)
        if new != text:
            page.write_text(new)
            changed.append(page)
    return changed


# ------------------------------------------------------------------ WaveDrom

def render_svg(source: Path) -> str:
    import wavedrom

    return wavedrom.render(source.read_text()).tostring() + "\n"


def update_svgs() -> list[Path]:
    changed = []
    for src in sorted(WAVES.glob("*.json")):
        svg = src.with_suffix(".svg")
        text = render_svg(src)
        if not svg.exists() or svg.read_text() != text:
            svg.write_text(text)
            changed.append(svg)
    return changed


# A small VCD reader: values sampled just before each rising clock edge; sample
# k is the value of cycle k, the clock period that begins with edge k and ends
# with edge k + 1 (the edge at which a register takes it).

def read_vcd(path: Path, wanted: set[str], clock: str) -> dict[str, list[str]]:
    ids: dict[str, list[str]] = {}          # VCD id -> full names
    scope: list[str] = []
    cur: dict[str, str] = {}
    samples: dict[str, list[str]] = {n: [] for n in wanted}
    clk_val = "x"
    clk_id = None
    pending: list[tuple[str, str]] = []

    def flush():
        nonlocal clk_val
        # changes at one time stamp: sample before applying them if clk rises now
        rises = any(i == clk_id and v == "1" for i, v in pending) and clk_val != "1"
        if rises:
            for n in wanted:
                samples[n].append(cur.get(n, "x"))
        for i, v in pending:
            for n in ids.get(i, []):
                cur[n] = v
            if i == clk_id:
                clk_val = v
        pending.clear()

    with open(path) as f:
        in_header = True
        for line in f:
            tok = line.split()
            if not tok:
                continue
            if in_header:
                if tok[0] == "$scope":
                    scope.append(tok[2])
                elif tok[0] == "$upscope":
                    scope.pop()
                elif tok[0] == "$var":
                    name = ".".join(scope + [tok[4]])
                    ids.setdefault(tok[3], []).append(name)
                    if name == clock:
                        clk_id = tok[3]
                elif tok[0] == "$enddefinitions":
                    in_header = False
                    if clk_id is None:
                        raise ValueError(f"{path}: no clock {clock}")
                continue
            t = tok[0]
            if t.startswith("#"):
                flush()
            elif t[0] in "bBrR":
                pending.append((tok[1], t[1:]))
            elif t[0] in "01xXzZ":
                pending.append((t[1:], t[0]))
    flush()
    return {n: v[1:] for n, v in samples.items()}     # before edge k + 1 = during cycle k


@dataclass
class Signal:
    label: str
    path: str               # full VCD name
    kind: str = "bit"       # bit / u (unsigned bus) / s<N> (signed bus of N bits) / b<N> (N binary digits)


@dataclass
class Diagram:
    module: str
    title: str
    signals: list[Signal]
    windows: list[tuple[str, int, int]]     # (event signal, cycles before, cycles after)
    clock: str
    command: list[str]                       # how the VCD is made (see simulate)
    foot: str = ""


def _bus_text(bits: str, kind: str) -> str:
    if any(c in "xXzZ" for c in bits):
        return "x"
    if kind.startswith("b"):                # binary, bit 0 on the right
        return bits.zfill(int(kind[1:]))[-int(kind[1:]):]
    v = int(bits, 2)
    if kind.startswith("s"):
        n = int(kind[1:])
        v &= (1 << n) - 1
        if v >> (n - 1):
            v -= 1 << n
    return str(v)


def to_wavedrom(d: Diagram, samples: dict[str, list[str]], start_signal: str) -> dict:
    """Cycles around each event (first cycle the event signal is 1 from the start on), gaps between."""
    n = len(samples[d.clock])
    start = next((k for k, v in enumerate(samples[start_signal]) if v == "1"), None)
    if start is None:
        raise ValueError(f"{d.module}: the simulation never raised {start_signal}")
    spans = []
    for event, before, after in d.windows:
        if event == "start":
            at = start
        else:
            at = next((k for k in range(start, n) if samples[event][k] == "1"), None)
            if at is None:
                raise ValueError(f"{d.module}: {event} never rose after start")
        spans.append([max(0, at - before), min(n - 1, at + after)])
    spans.sort()
    merged = [spans[0]]
    for lo, hi in spans[1:]:
        if lo <= merged[-1][1] + 2:
            merged[-1][1] = max(merged[-1][1], hi)
        else:
            merged.append([lo, hi])
    cycles: list[int | None] = []
    for i, (lo, hi) in enumerate(merged):
        if i:
            cycles.append(None)                  # a gap
        cycles += list(range(lo, hi + 1))
    rows = [{"name": "clk", "wave": "".join("|" if c is None else ("p" if i == 0 else ".")
                                              for i, c in enumerate(cycles))}]
    # cycle numbers relative to the start
    marks, data = [], []
    for c in cycles:
        if c is None:
            marks.append("|")
        else:
            marks.append("=")
            data.append(str(c - start))
    rows.append({"name": "cycle", "wave": "".join(marks), "data": data})
    for s in d.signals:
        vals = samples[s.path]
        wave, data, prev = [], [], None
        for c in cycles:
            if c is None:
                wave.append("|")
                continue
            if s.kind == "bit":
                v = vals[c] if vals[c] in "01" else "x"
                wave.append("." if v == prev else v)
            else:
                v = _bus_text(vals[c], s.kind)
                if v == prev:
                    wave.append(".")
                elif v == "x":
                    wave.append("x")
                else:
                    wave.append("=")
                    data.append(v)
            prev = v
        row = {"name": s.label, "wave": "".join(wave)}
        if data:
            row["data"] = data
        rows.append(row)
    out = {"signal": rows, "head": {"text": d.title}, "config": {"hscale": 1}}
    if d.foot:
        out["foot"] = {"text": d.foot}
    return out


def dump_wavedrom(wave: dict) -> str:
    """WaveDrom JSON with one signal per line (diffs stay readable)."""
    rows = ",\n".join("  " + json.dumps(r, ensure_ascii=False) for r in wave["signal"])
    rest = "".join(f',\n "{k}": {json.dumps(v, ensure_ascii=False)}' for k, v in wave.items() if k != "signal")
    return f'{{"signal": [\n{rows}\n ]{rest}\n}}\n'


def simulate(d: Diagram, vcd: Path) -> None:
    """Make the diagram's VCD with Icarus: `interp run` of a core (its top possibly
    replaced by a module with the same ports) or `interp gcode`."""
    from .cli import build_parser
    from .cores import load_all

    kind, *rest = d.command
    if kind == "gcode":
        from .cli import main

        with tempfile.TemporaryDirectory() as tmp:
            prog = Path(tmp) / "prog.nc"
            prog.write_text(rest[0])
            rc = main(["gcode", str(prog), *rest[1:], "--steps", str(Path(tmp) / "s.csv"), "--vcd", str(vcd)])
            if rc:
                raise RuntimeError(f"interp gcode failed for {d.module}")
        return
    top, parameters, cli = rest[0], rest[1], rest[2:]
    from .simulation.jobs import job_env
    from .simulation.runner import run_cocotb

    registry = load_all()
    with tempfile.TemporaryDirectory() as tmp:
        args = build_parser().parse_args(["run", *cli, "--steps", str(Path(tmp) / "s.csv")])
        core = registry[args.core]
        core.check(args)
        out = Path(tmp) / "samples.json"
        job = {"core": core.name, "args": {k: v for k, v in vars(args).items()
                                           if isinstance(v, (int, float, str, bool, list, type(None)))},
               "out": str(out)}
        params = core.parameters(args)
        params = {k: v for k, v in {**params, **parameters}.items() if k in _declared(top)}
        run_cocotb(toplevel=top, test_module="interp.simulation.rtl_driver", sim="icarus", parameters=params,
                   env=job_env("INTERP_JOB", job, tmp), waves=str(vcd), name=f"docs_{top}",
                   test_dir=Path(tmp), quiet=True)


def _declared(module: str) -> set[str]:
    return {p.name for p in rtl_parameters(module)}


def _core(top: str, names: list[str], scope: str | None = None) -> list[Signal]:
    scope = scope or top
    return [Signal(n, f"{scope}.{n}", k) for n, k in names]


_LINE = [("rst", "bit"), ("start", "bit"), ("tick", "bit"), ("x", "s8"), ("y", "s8"), ("busy", "bit"),
         ("step_x", "bit"), ("step_y", "bit"), ("dir_x", "bit"), ("dir_y", "bit"), ("done", "bit")]
_QUAD = [("start", "bit"), ("tick", "bit"), ("x0", "s8"), ("y0", "s8"), ("x1", "s8"), ("y1", "s8"),
         ("ccw", "bit"), ("busy", "bit"), ("step_x", "bit"), ("step_y", "bit"), ("dir_x", "bit"),
         ("dir_y", "bit"), ("done", "bit"), ("error", "bit")]
_MT = "motion_top"
# The G-code build (W 32, FRAC 32) on a machine slowed down for the eye: a 1 kHz clock and
# 1 step/mm, so F12000 mm/min is 0.2 step per clock, reached in about 16 clocks (an
# acceleration of 12.5 m/s^2); pulse 2 cycles, set-up 1, hold 1.
_MACHINE = [f"axis.{a}.{k}={v}" for a in "xyz"
            for k, v in (("steps_per_mm", 1), ("max_rate_mm_min", 60000), ("accel_mm_s2", 12500))]
_GCODE = ["gcode", "G21 G91\nG01 X30 Y-20 F12000\nG01 X-10\n", "--clock-hz", "1000", "--sim", "icarus",
          "--push-interval", "1",
          *[w for kv in _MACHINE + ["output.pulse_ns=2000000", "output.dir_setup_ns=1000000",
                                    "output.dir_hold_ns=1000000"] for w in ("--set", kv)]]


def diagrams() -> dict[str, Diagram]:
    lx, lx_cli = "lin_exact", ["lin-exact"]
    qtop, qscope = "circ_quadrant", "circ_quadrant"
    d = [
        Diagram("su1571551", "su1571551, WIDTH 8, faithful (EXACT 0): the patent's move X = 7, Y = 3",
                _core("su1571551", _LINE), [("start", 2, 14)], "su1571551.clk",
                ["run", "su1571551", {"EXACT": 0}, "su1571551", "--x", "7", "--y", "3", "--mode", "faithful",
                 "--width", "8"]),
        # Until rtl/lin_exact.v is there, su1571551 EXACT 1 stands in: the same ports and
        # outputs in every cycle (proved), so the diagram is the same either way.
        Diagram("lin_exact", "lin_exact, WIDTH 8: move X = 7, Y = -3",
                _core(lx, _LINE), [("start", 2, 14)], f"{lx}.clk",
                ["run", lx, {"EXACT": 1}, *lx_cli, "--x", "7", "--y", "-3", "--width", "8"]),
        Diagram("lin_std", "lin_std, WIDTH 8: move X = 3, Y = -2 (one axis per tick)",
                _core("lin_std", _LINE + [("pos_x", "s8"), ("pos_y", "s8")]), [("start", 2, 9)], "lin_std.clk",
                ["run", "lin_std", {}, "lin-std", "--x", "3", "--y", "-2", "--width", "8"]),
        Diagram("lin_accel", "lin_accel, WIDTH 8: move X = -5, Y = 2 (leading axis, diagonal steps)",
                _core("lin_accel", _LINE), [("start", 2, 9)], "lin_accel.clk",
                ["run", "lin_accel", {}, "lin-accel", "--x", "-5", "--y", "2", "--width", "8"]),
        Diagram("circ_su1665343", "circ_su1665343, WIDTH 5: quadrant R = 3 from (3, 0) to (0, 3)",
                _core("circ_su1665343", [("start", "bit"), ("tick", "bit"), ("r", "u"), ("x0", "u"), ("y0", "u"),
                                         ("busy", "bit"), ("step_x", "bit"), ("step_y", "bit"), ("dir_x", "bit"),
                                         ("dir_y", "bit"), ("done", "bit"), ("error", "bit")]),
                [("start", 1, 3), ("step_y", 4, 40)], "circ_su1665343.clk",
                ["run", "circ_su1665343", {}, "su1665343", "--r", "3", "--width", "5"],
                "set-up 3·WIDTH + 8 = 23 cycles, then 3 cycles per step (6 at the sector switch)"),
        Diagram("circ_quadrant", "circ_quadrant, WIDTH 8, ACCEL 1: quarter circle (4, 0) -> (0, 4), ccw",
                _core("circ_quadrant", _QUAD, qscope), [("start", 1, 3), ("step_y", 3, 12)], f"{qtop}.clk",
                ["run", qtop, {"ACCEL": 1}, "circ-accel", "--x0", "4", "--y0", "0", "--x1", "0",
                 "--y1", "4", "--dir", "ccw", "--width", "8"],
                "set-up: the command is checked in cycle 2·WIDTH + 16, steps from 2·WIDTH + 17"),
        Diagram("circ_arc", "circ_arc, WIDTH 8: arc centre (0, 0) from (4, 0) to (0, 4), ccw",
                _core("circ_arc", [("start", "bit"), ("tick", "bit"), ("cx", "s8"), ("cy", "s8"), ("x0", "s8"),
                                   ("y0", "s8"), ("x1", "s8"), ("y1", "s8"), ("ccw", "bit"), ("full", "bit"),
                                   ("busy", "bit"), ("step_x", "bit"), ("step_y", "bit"), ("dir_x", "bit"),
                                   ("dir_y", "bit"), ("done", "bit"), ("error", "bit")]),
                [("start", 1, 3), ("step_x", 5, 14)], "circ_arc.clk",
                ["run", "circ_arc", {}, "circ-arc", "--cx", "0", "--cy", "0", "--x0", "4", "--y0", "0",
                 "--x1", "0", "--y1", "4", "--dir", "ccw", "--width", "8"],
                "set-up 2·WIDTH + 22 cycles to the first step; + 6 cycles per octant crossed"),
        Diagram("curve_tangent", "curve_tangent, WIDTH 16, PW 24: circle radius 4 from (4, 0) to y = 4",
                _core("curve_tangent", [("start", "bit"), ("tick", "bit"), ("x0", "s16"), ("y0", "s16"),
                                        ("p0", "s24"), ("q0", "s24"), ("end_sel", "u"), ("end_coord", "s16"),
                                        ("busy", "bit"), ("step_x", "bit"), ("step_y", "bit"), ("dir_x", "bit"),
                                        ("dir_y", "bit"), ("done", "bit"), ("error", "bit")]),
                [("start", 2, 10)], "curve_tangent.clk",
                ["run", "curve_tangent", {}, "curve", "--curve", "circle", "--a", "4"]),
        Diagram("motion_top", "motion_top, W 32: G91 G01 X30 Y-20, G01 X-10 (feed 0.2 step/clock; pulse 2, setup 1, hold 1)",
                _core(_MT, [("cmd_valid", "bit"), ("cmd_kind", "u"), ("cmd_x", "s32"), ("cmd_y", "s32"),
                            ("cmd_feed", "u"), ("queue_level", "u"), ("busy", "bit"), ("step_x", "bit"),
                            ("dir_x", "bit"), ("step_y", "bit"), ("dir_y", "bit"), ("pos_x", "s32"),
                            ("pos_y", "s32"), ("done", "bit"), ("error", "bit")]),
                [("start", 1, 40), ("step_x", 2, 30)], f"{_MT}.clk", _GCODE),
        Diagram("sync_fifo", "sync_fifo inside motion_top (WIDTH = the command word, DEPTH 4): two commands queued",
                _core("sync_fifo", [("push", "bit"), ("pop", "bit"), ("valid", "bit"), ("full", "bit"),
                                    ("level", "u"), ("overflow", "bit")], f"{_MT}.u_queue"),
                [("start", 1, 12)], f"{_MT}.clk", _GCODE),
        Diagram("step_sync", "step_sync inside motion_top (AXES 3, DEPTH 2, LATENCY 2): the first command's steps",
                _core("step_sync", [("in_step", "b3"), ("in_dir", "b3"), ("stop", "bit"), ("tick", "bit"),
                                    ("out_valid", "bit"), ("out_step", "b3"), ("out_dir", "b3"), ("level", "u"),
                                    ("overflow", "bit")], f"{_MT}.u_sync"),
                [("start", 1, 24)], f"{_MT}.clk", _GCODE, "axis bits ZYX (bit 0 = X)"),
        Diagram("step_pacer", "step_pacer inside motion_top (FEED_W 34, FRAC 32): the speed ramps up to 0.2 step/clock",
                _core("step_pacer", [("sum", "u"), ("jerk_shift", "u"), ("step_valid", "bit"), ("step_axes", "u"),
                                     ("step_cost", "u"), ("drive_ready", "bit"), ("due", "bit"), ("fire", "bit")],
                      f"{_MT}.u_profile.u_pacer"),
                [("start", 1, 4), ("fire", 4, 30)], f"{_MT}.clk", _GCODE, "sum: the filtered speed (path units per clock, "
                "2^32 = one axial step); a step leaves when the phase covers its cost (the true length of "
                "one step of the segment) and the output stage is ready"),
        Diagram("step_dir", "step_dir inside motion_top (AXES 3): pulse width 2, setup 1, hold 1",
                _core("step_dir", [("pulse_width", "u"), ("setup", "u"), ("hold", "u"), ("valid", "bit"),
                                   ("step_in", "b3"), ("dir_in", "b3"), ("ready", "bit"), ("step", "b3"), ("dir", "b3")],
                      f"{_MT}.u_out"),
                [("start", 1, 30)], f"{_MT}.clk", _GCODE, "axis bits ZYX (bit 0 = X); X reverses in the second command"),
    ]
    return {x.module: x for x in d}


def _start_signal(d: Diagram) -> str:
    if d.command[0] == "gcode":
        return f"{_MT}.cmd_valid"
    return f"{d.signals[0].path.rsplit('.', 1)[0]}.start"


def simulated_wave(module: str) -> dict:
    """The module's diagram as WaveDrom data, from a fresh Icarus simulation."""
    d = diagrams()[module]
    scope = d.signals[0].path.rsplit(".", 1)[0]
    events = [(ev if ev == "start" else f"{scope}.{ev}", b, a) for ev, b, a in d.windows]
    start = _start_signal(d)
    wanted = {s.path for s in d.signals} | {d.clock, start} | {ev for ev, _, _ in events if ev != "start"}
    with tempfile.TemporaryDirectory() as tmp:
        vcd = Path(tmp) / "w.vcd"
        simulate(d, vcd)
        samples = read_vcd(vcd, wanted, d.clock)
    d.windows = events
    return to_wavedrom(d, samples, start)


def regenerate_wave(module: str) -> Path:
    WAVES.mkdir(parents=True, exist_ok=True)
    out = WAVES / f"{module}.json"
    out.write_text(dump_wavedrom(simulated_wave(module)))
    return out


# ------------------------------------------------------------------ checks

def _rel(path: Path) -> Path:
    return path.relative_to(ROOT) if path.is_relative_to(ROOT) else path


def stale_svgs(waves: Path = WAVES) -> list[str]:
    lines = []
    for src in sorted(waves.glob("*.json")):
        svg = src.with_suffix(".svg")
        if not svg.exists():
            lines.append(f"{_rel(svg)} missing (make docs)")
        elif svg.read_text() != render_svg(src):
            lines.append(f"{_rel(svg)} is stale: not what wavedrom renders from {src.name} (make docs)")
    return lines


def stale_resources(csv_path: Path = RESOURCES_CSV, pages: Path = PAGES) -> list[str]:
    rows, lines = read_resources(csv_path), []
    for module, page in resource_pages(pages):
        text = page.read_text()
        if with_resources(text, module, rows) != text:
            lines.append(f"{_rel(page)}: resources table differs from what docs/resources.csv gives (make docs)")
    return lines


_LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)|<img[^>]*src=\"([^\"]+)\"")


def broken_links(pages: Path = PAGES) -> list[str]:
    lines = []
    for page in sorted(pages.glob("*.md")):
        for m in _LINK.finditer(page.read_text()):
            target = m.group(1) or m.group(2)
            if re.match(r"[a-z]+:", target) or target.startswith("#"):
                continue
            path = (page.parent / target.split("#")[0]).resolve()
            if not path.exists():
                lines.append(f"{_rel(page)}: link {target} does not resolve")
    return lines


def missing_pages() -> list[str]:
    return [f"docs/cores/{m}.md missing" for m in MODULES if not (PAGES / f"{m}.md").exists()]


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m interp.docs", description=__doc__.splitlines()[0])
    p.add_argument("what", choices=["waves", "svg", "resources", "check", "ports"])
    p.add_argument("modules", nargs="*", help="modules (default: all)")
    args = p.parse_args(argv)
    mods = args.modules or MODULES
    if args.what == "waves":
        for m in mods:
            print(f"docs: {regenerate_wave(m).relative_to(ROOT)}")
    elif args.what == "svg":
        for f in update_svgs():
            print(f"docs: {f.relative_to(ROOT)}")
    elif args.what == "resources":
        if not RESOURCES_CSV.exists():
            print("docs: docs/resources.csv missing; tables say so (make synth, copy out/synth.csv)")
        for f in update_resources():
            print(f"docs: {f.relative_to(ROOT)}")
    elif args.what == "ports":
        for m in mods:
            print(f"### {m}\n{ports_table(m)}\n")
    else:
        problems = missing_pages() + stale_svgs() + stale_resources() + broken_links()
        for m in MODULES:
            if (PAGES / f"{m}.md").exists():
                problems += ports_diff(m, source=port_source(m))
        for line in problems:
            print(line)
        return 1 if problems else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
