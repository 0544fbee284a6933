# SPDX-License-Identifier: Apache-2.0
"""Gate-level regression (`make test-synth`): cocotb benches on Yosys's netlist.

The same cocotb tests as the RTL benches, run on the iCE40-mapped netlist
(SB_LUT4/SB_CARRY/SB_DFF* with Yosys's cell models), so simulation and
synthesis cannot disagree silently.  Skipped unless INTERP_GATE=1 (set by
`make test-synth`), so `make test` never waits for synthesis.
"""
import os
import sys
from pathlib import Path

import pytest

from interp.simulation.runner import run_cocotb

TB = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.skipif(os.environ.get("INTERP_GATE") != "1",
                                reason="gate level runs under make test-synth (INTERP_GATE=1)")

# (CLI name, top, parameters, cocotb test module, its folder, test cases, watched nets)
CASES = [
    ("lin-exact", "lin_exact", {"WIDTH": 8}, "test_su1571551", "su1571551",
     ["patent_table", "zero_length", "start_while_busy_is_ignored", "reset_at_any_cycle",
      "random_full_width"], ["f", "ctr1", "ctr2"]),
    ("su1571551", "su1571551", {"WIDTH": 8, "EXACT": 1}, "test_su1571551", "su1571551",
     ["patent_table", "zero_length", "start_while_busy_is_ignored", "reset_at_any_cycle",
      "random_full_width"], ["f", "ctr1", "ctr2"]),
    ("su1571551/faithful", "su1571551", {"WIDTH": 8, "EXACT": 0}, "test_su1571551", "su1571551",
     ["patent_table", "zero_length", "reset_at_any_cycle"], ["f", "ctr1", "ctr2"]),
]


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_gate_level(sim, case):
    from interp.flows.synth import Target, checked, gate_netlist

    name, top, params, module, folder, cases, keep = case
    # The netlist of the iCE40 flow; Verilator gets Yosys's generic gates
    # (the iCE40 cell models use timing constructs only Icarus takes).
    family = "ice40" if sim == "icarus" else "generic"
    files = gate_netlist(checked(Target(name, top, params)), family, keep)
    sys.path.insert(0, str(TB / folder))
    run_cocotb(toplevel=top, test_module=module, sim=sim, parameters=params, testcase=cases,
               sources=files, name=f"gate_{name.replace('/', '-')}_{family}")


def test_fusesoc_core_files_are_current():
    from interp.flows import fusesoc

    assert fusesoc.main(["--check"]) == 0, "run python -m interp.flows.fusesoc"


@pytest.mark.parametrize("core", ["su1571551"])
def test_fusesoc_builds_with_dependencies(core, tmp_path):
    """FuseSoC resolves the core's building blocks and Icarus elaborates them."""
    import subprocess

    fusesoc = Path(sys.executable).parent / "fusesoc"
    run = subprocess.run([str(fusesoc), "--cores-root", str(TB.parent / "rtl"), "run",
                          "--build-root", str(tmp_path), "--setup", "--build", "--target", "default",
                          "--tool", "icarus", f"interp:rtl:{core}"], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]


@pytest.mark.parametrize("tool,family", [("icestorm", "ice40"), ("trellis", "ecp5"), ("icarus", None)])
def test_fusesoc_picks_the_family_form(tool, family, tmp_path):
    """A module's rtl/<family>/ form replaces rtl/<module>.v in the file list of the
    family's tool, also when the module is a dependency (scratch forms of mux2 in a copy)."""
    import shutil
    import subprocess

    from interp.flows import fusesoc

    rtl = tmp_path / "rtl"
    shutil.copytree(TB.parent / "rtl", rtl, ignore=shutil.ignore_patterns("*.core"))
    for fam in ("ice40", "ecp5"):
        (rtl / fam).mkdir(exist_ok=True)
        (rtl / fam / "mux2.v").write_text((rtl / "mux2.v").read_text())
    assert fusesoc.main([], rtl) == 0
    fusesoc_bin = Path(sys.executable).parent / "fusesoc"
    run = subprocess.run([str(fusesoc_bin), "--cores-root", str(rtl), "run", "--build-root", str(tmp_path / "b"),
                          "--setup", "--target", "default", "--tool", tool, "interp:rtl:su1571551"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    used = [p.relative_to(next((tmp_path / "b").glob("*/*/src"))).as_posix()
            for p in (tmp_path / "b").rglob("mux2.v")]
    want = f"interp_rtl_mux2_{fusesoc.VERSION}/" + (f"{family}/mux2.v" if family else "mux2.v")
    assert used == [want], used
