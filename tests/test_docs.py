# SPDX-License-Identifier: Apache-2.0
"""The datasheets in docs/cores stay true to their sources.

(a) every SVG is what wavedrom renders from its JSON now;
(b) every ports table equals the module's ports in rtl/<module>.v (name, direction, width);
(c) every resources table is what the generator makes from docs/resources.csv;
(d) every module has a page, every relative link in docs/cores resolves.
Each check also runs once on a broken copy of its input, so it is shown to fail.
Regenerate with `make docs`.
"""
from __future__ import annotations

import csv
import json
import shutil

import pytest

from interp import docs

JSONS = sorted(docs.WAVES.glob("*.json"))


def _wavedrom():
    try:
        import wavedrom  # noqa: F401
    except ImportError:
        pytest.fail("the wavedrom package is missing: `make deps` installs the test extras")


# ---------------------------------------------------------------- (a) SVGs

def test_every_page_has_a_diagram():
    missing = [m for m in docs.MODULES if not (docs.WAVES / f"{m}.json").exists()]
    assert not missing, f"no docs/cores/wavedrom/<module>.json for: {', '.join(missing)}"


@pytest.mark.parametrize("source", JSONS, ids=[p.stem for p in JSONS])
def test_svg_matches_json(source):
    _wavedrom()
    svg = source.with_suffix(".svg")
    assert svg.exists(), f"{svg.relative_to(docs.ROOT)} missing: run `make docs`"
    assert svg.read_text() == docs.render_svg(source), \
        f"{svg.relative_to(docs.ROOT)} is stale: not what wavedrom renders from {source.name} (make docs)"


def test_svg_check_catches_a_stale_svg(tmp_path):
    _wavedrom()
    src = JSONS[0]
    shutil.copy(src, tmp_path / src.name)
    shutil.copy(src.with_suffix(".svg"), tmp_path / src.with_suffix(".svg").name)
    assert docs.stale_svgs(tmp_path) == []
    text = (tmp_path / src.name).read_text()
    (tmp_path / src.name).write_text(text.replace('"wave": "p', '"wave": "n', 1))
    assert len(docs.stale_svgs(tmp_path)) == 1


@pytest.mark.parametrize("module", docs.MODULES)
def test_diagram_is_the_simulation(module):
    """Each diagram's JSON is what the RTL does now: re-simulated on Icarus (about 2 s each)."""
    if shutil.which("iverilog") is None:
        pytest.skip("iverilog not installed (make deps installs it)")
    committed = json.loads((docs.WAVES / f"{module}.json").read_text())
    fresh = docs.simulated_wave(module)
    assert committed == fresh, (f"docs/cores/wavedrom/{module}.json differs from a fresh simulation: "
                                f"DOCS_WAVES=1 make docs (then check the page's timing text)")


# ---------------------------------------------------------------- (b) ports

@pytest.mark.parametrize("module", docs.MODULES)
def test_ports_table_matches_rtl(module):
    page = docs.PAGES / f"{module}.md"
    if not page.exists():
        pytest.fail(f"docs/cores/{module}.md missing")
    diff = docs.ports_diff(module, source=docs.port_source(module))
    assert not diff, "\n".join(diff)


def test_ports_check_catches_changes(tmp_path):
    rtl = tmp_path / "rtl"
    rtl.mkdir()
    page = docs.PAGES / "lin_std.md"
    original = (docs.RTL / "lin_std.v").read_text()
    cases = {
        "renamed": original.replace("pos_y   // register 4", "position_y   // register 4"),
        "width": original.replace("output reg  [WIDTH-1:0] pos_y", "output reg  [WIDTH:0] pos_y"),
        "direction": original.replace("output reg              done", "input  wire             done"),
        "added": original.replace("    output reg  [WIDTH-1:0] pos_y   // register 4",
                                  "    output reg  [WIDTH-1:0] pos_y,  // register 4\n    output wire extra"),
    }
    assert docs.ports_diff("lin_std", page) == []
    for what, text in cases.items():
        assert text != original, what
        (rtl / "lin_std.v").write_text(text)
        diff = docs.ports_diff("lin_std", page, rtl)
        assert len(diff) >= 1 and all("\n" not in line for line in diff), what


@pytest.mark.parametrize("module", docs.MODULES)
def test_port_parser_agrees_with_verilator(module):
    """The header parser the ports check uses, against Verilator's elaboration
    (names, directions, widths at the default parameters)."""
    source = docs.port_source(module)
    defaults = docs.default_parameters(source)
    mine = [(p.name, p.direction, docs.width_value(p.width, defaults)) for p in docs.rtl_ports(source)]
    theirs = docs.verilator_ports(source)
    assert mine == theirs, f"rtl/{source}.v: header parser {mine} != verilator {theirs}"


@pytest.mark.parametrize("rng, width", [(None, "1"), ("[7:0]", "8"), ("[WIDTH-1:0]", "WIDTH"),
                                        ("[PW+3:0]", "PW+4"), ("[W-1:0]", "W"), ("[QLW-1:0]", "QLW")])
def test_width_expressions(rng, width):
    assert docs.width_of(rng) == width


# ---------------------------------------------------------------- (c) resources

def test_resources_tables_match_csv():
    stale = docs.stale_resources()
    assert not stale, "\n".join(stale)


def test_resources_csv_has_the_flows_header():
    if not docs.RESOURCES_CSV.exists():
        pytest.skip("docs/resources.csv not made yet (make synth; the pages say so)")
    with open(docs.RESOURCES_CSV, newline="") as f:
        header = next(csv.reader(f))
    assert header[:6] == ["core", "family", "device", "fmax_mhz", "luts", "ffs"], header


def test_resources_check_catches_a_changed_figure(tmp_path):
    pages = tmp_path / "cores"
    pages.mkdir()
    shutil.copy(docs.PAGES / "lin_std.md", pages / "lin_std.md")
    table = tmp_path / "resources.csv"
    rows = [{"core": "lin-std", "family": "ice40", "device": "iCE40HX8K-CT256",
             "fmax_mhz": "100.0", "luts": "10", "ffs": "5"}]

    def write():
        with open(table, "w", newline="") as f:
            w = csv.DictWriter(f, ["core", "family", "device", "fmax_mhz", "luts", "ffs"])
            w.writeheader()
            w.writerows(rows)

    write()
    page = pages / "lin_std.md"
    page.write_text(docs.with_resources(page.read_text(), "lin_std", docs.read_resources(table)))
    assert docs.stale_resources(table, pages) == []
    assert "| 100.0 | — | 10 | 5 |" in page.read_text()
    rows[0]["luts"] = "11"
    write()
    assert len(docs.stale_resources(table, pages)) == 1


def test_resources_check_covers_pages_outside_the_index(tmp_path):
    """A datasheet that is not in the index (speed_ramp) but carries the markers is
    checked too, by the module named like the page."""
    pages = tmp_path / "cores"
    pages.mkdir()
    (pages / "speed_ramp.md").write_text(f"# speed_ramp\n{docs.RES_BEGIN}\nhand-copied\n{docs.RES_END}\n")
    (pages / "notes.md").write_text("# no table here\n")
    table = tmp_path / "resources.csv"
    table.write_text("core,family,device,fmax_mhz,luts,ffs\nspeed_ramp,ecp5,LFE5U-25F,29.4,9263,1932\n")
    assert [m for m, _ in docs.resource_pages(pages)] == ["speed_ramp"]
    assert len(docs.stale_resources(table, pages)) == 1
    page = pages / "speed_ramp.md"
    page.write_text(docs.with_resources(page.read_text(), "speed_ramp", docs.read_resources(table)))
    assert "| 29.4 | — | 9263 | 1932 |" in page.read_text()
    assert docs.stale_resources(table, pages) == []


# ---------------------------------------------------------------- (d) pages and links

def test_every_module_has_a_page():
    missing = docs.missing_pages()
    assert not missing, "\n".join(missing)


def test_index_lists_every_page():
    index = (docs.PAGES / "README.md").read_text()
    absent = [m for m in docs.MODULES if f"]({m}.md)" not in index]
    assert not absent, f"docs/cores/README.md does not link: {', '.join(absent)}"


def test_relative_links_resolve():
    broken = docs.broken_links()
    assert not broken, "\n".join(broken)


def test_link_check_catches_a_broken_link(tmp_path):
    (tmp_path / "page.md").write_text("[there](there.md) ![img](wavedrom/x.svg) [web](https://example.org)\n")
    (tmp_path / "there.md").write_text("")
    assert docs.broken_links(tmp_path) == [f"{tmp_path / 'page.md'}: link wavedrom/x.svg does not resolve"]


def test_no_citation_of_unpublished_material():
    # the words a citation of material outside the repository would use (the style
    # guide's name is spelled in two parts so that this file does not cite it either)
    pattern = ("SPEC", "seed 0", "STYLE" + ".md", "../shared", "issue ")
    hits = [f"{p.name}: {w}" for p in sorted(docs.PAGES.glob("*.md")) for w in pattern if w in p.read_text()]
    hits += [f"{p.name}: {w}" for p in JSONS for w in pattern if w in p.read_text()]
    assert not hits, "\n".join(hits)
