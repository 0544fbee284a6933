# SPDX-License-Identifier: Apache-2.0
"""The GTKWave save files sim/*.gtkw against the VCDs `make wave CORE=...` makes.

`make wave CORE=name` is `interp wave name`, i.e. `make_wave(name, out)`: these
tests call the same function (Icarus), then check that every signal a save
file names is in the VCD (a renamed port or internal fails here) and that the
save file's zoom shows the whole run (the committed file and the one written
for the run).
"""
from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from interp.commands.wave import (ROOT, SIM, fit, make_wave, save_file_filters, save_file_signals, targets,
                                  vcd_end_time, vcd_signals, visible_span, zoom_for)
from interp.cores import REGISTRY, load_all

load_all()
WAVES = sorted(targets())
needs_icarus = pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus Verilog")
_runs: dict = {}


def wave(name, tmp_path_factory):
    """One run per core for the whole module: (vcd, fitted save file)."""
    if name not in _runs:
        _runs[name] = make_wave(name, tmp_path_factory.mktemp(name.replace("-", "_")))
    return _runs[name]


def test_every_production_core_has_a_save_file():
    for module in ("circ_arc", "curve_tangent", "su1571551", "lin_exact", "motion_top", "circ_su1665343"):
        assert (SIM / f"{module}.gtkw").exists(), f"sim/{module}.gtkw is missing"
    assert {"circ-arc", "curve", "su1571551", "motion"} <= set(WAVES)


@pytest.mark.parametrize("groups", [("circ_arc", "curve_tangent", "lin_exact", "motion_top")])
def test_save_files_group_by_function(groups):
    for module in groups:
        text = (SIM / f"{module}.gtkw").read_text()
        for group in ("command", "handshake", "steps X", "steps Y"):
            assert f"@800200\n-{group}\n" in text, f"sim/{module}.gtkw has no group {group!r}"


@pytest.mark.parametrize("save", sorted(p.name for p in SIM.glob("*.gtkw")))
def test_translate_filters_exist(save):
    """Codes shown by name: each filter file exists (path from the repository root), 'value name' lines."""
    for path in save_file_filters((SIM / save).read_text()):
        assert not path.startswith("/"), f"sim/{save}: filter {path} must be relative to the repository"
        lines = (ROOT / path).read_text().splitlines()
        assert lines and all(len(line.split()) == 2 for line in lines), f"{path}: want 'value name' lines"


def test_zoom_arithmetic():
    text = "[size] 1400 800\n[sst_width] 220\n[signals_width] 300\n[timestart] 0\n"
    for end in (1, 1000, 3_025_000, 10**12):
        shown = text + f"*{zoom_for(end, 1400 - 220 - 300 - 160):.6f} 0\n"
        start, span = visible_span(shown)
        assert start == 0 and end * 0.999 <= span <= end * 1.001


@needs_icarus
@pytest.mark.parametrize("name", WAVES)
def test_save_file_matches_vcd(name, tmp_path_factory):
    vcd, save = wave(name, tmp_path_factory)
    module = targets()[name]
    committed = (SIM / f"{module}.gtkw").read_text()
    names = set(vcd_signals(vcd).values())
    for path in save_file_filters(save.read_text()):
        assert path.startswith("/") and Path(path).exists(), f"{save}: filter {path} is not an absolute path"
    missing = [s for s in save_file_signals(committed) if s not in names]
    assert not missing, f"sim/{module}.gtkw names signals that {vcd.name} lacks: {missing}"
    assert save_file_signals(committed), f"sim/{module}.gtkw shows no signal"
    end = vcd_end_time(vcd)
    assert end > 0
    for what, text in ((f"sim/{module}.gtkw", committed), (str(save), save.read_text())):
        start, span = visible_span(text)
        assert start == 0, f"{what} starts at {start}, not at the run's start"
        assert span >= end, (f"{what} shows 0 .. {span:.0f} of a run to {end} (VCD units): "
                             f"refit its `*` zoom line, e.g. from `interp wave {name} --no-open`")
        assert span <= 2 * end, f"{what} shows 0 .. {span:.0f}, the run (to {end}) is squeezed into the left half"


@needs_icarus
def test_lin_exact_save_file_has_su1571551s_ports(tmp_path_factory):
    """lin_exact has su1571551's ports: its save file must fit that VCD (or its own, once it exists)."""
    text = (SIM / "lin_exact.gtkw").read_text()
    if "lin-exact" in REGISTRY:
        vcd, _ = wave("lin-exact", tmp_path_factory)
    else:
        vcd, _ = wave("su1571551", tmp_path_factory)
        text = text.replace("lin_exact.", "su1571551.")
    fitted, missing = fit(text, vcd)
    assert not missing, f"sim/lin_exact.gtkw names signals the linear core lacks: {missing}"
    assert visible_span(fitted)[1] >= vcd_end_time(vcd)


def test_unknown_core_is_one_line(capsys):
    from interp.cli import main

    assert main(["wave", "no-such-core", "--no-open"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no save file" in err[0]
