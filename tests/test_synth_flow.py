# SPDX-License-Identifier: Apache-2.0
"""The FPGA flow's own logic (no tools needed): source scan, parameters, report parsing."""
import pytest

from interp.cores import UsageError, load_all
from interp.flows import fusesoc, synth


def test_sources_follow_instantiations():
    names = [p.stem for p in synth.sources("su1571551")]
    assert names[0] == "su1571551"
    assert set(names) == {"su1571551", "updown_counter", "accum_addsub", "sign_analysis",
                          "mux2", "increment_former", "start_stop", "axis_order"}


def test_a_parameter_the_module_lacks_is_an_error():
    assert synth.checked(synth.Target("x", "mux2", {"WIDTH": 32})).parameters == {"WIDTH": 32}
    with pytest.raises(UsageError, match="declares no parameter EXACT"):
        synth.checked(synth.Target("x", "mux2", {"WIDTH": 32, "EXACT": 1}))
    with pytest.raises(UsageError, match="declares no parameter WIDTH"):
        synth.checked(synth.Target("m", "motion_top", {}), {"WIDTH": 32})


def test_every_table_row_sets_only_declared_parameters():
    """A row's parameter the module lacks would be dropped by Yosys: the core would be
    synthesized at its default width."""
    for row in synth.CORES:
        synth.checked(row)
        if row.width:
            assert row.width in synth.declared_parameters(synth.RTL / f"{row.toplevel}.v"), row.name
    motion = next(t for t in synth.CORES if t.toplevel == "motion_top")
    assert motion.parameters["W"] == synth.WIDTH


def test_every_cli_core_has_a_table_row():
    tops = {t.toplevel for t in synth.CORES}
    for name, core in load_all().items():
        assert core.toplevel in tops, f"{name}: add rtl/{core.toplevel}.v to CORES in interp/flows/synth.py"


def test_utilisation_parsing():
    log = ("Info: Device utilisation:\nInfo: \t         ICESTORM_LC:     576/   7680     7%\n"
           "Info: \t        ICESTORM_RAM:       0/     32     0%\n\nInfo: Placed 0 cells\n")
    assert synth.utilisation(log) == {"ICESTORM_LC": (576, 7680), "ICESTORM_RAM": (0, 32)}
    row = synth.add_utilisation({}, synth.FAMILIES["ice40"], log)
    assert (row["lut_capacity"], row["brams"], row["bram_capacity"], row["target_mhz"]) == (7680, 0, 32, 160)


def test_area_and_fmax_parsing():
    assert synth.area({"SB_LUT4": 10, "SB_CARRY": 4, "SB_DFFESR": 3, "SB_DFF": 2}, "ice40") == (10, 5)
    assert synth.area({"LUT4": 10, "CCU2C": 4, "TRELLIS_FF": 7, "PFUMX": 2}, "ecp5") == (18, 7)
    report = {"fmax": {"$glbnet$clk$TRELLIS_IO_IN": {"achieved": 136.72, "constraint": 260.0}}}
    assert synth.fmax(report) == 136.7
    assert synth.fmax({"fmax": {}}) is None


def test_fusesoc_core_lists_dependencies_and_parameters():
    text = fusesoc.core_text("su1571551", {p.stem for p in synth.RTL.glob("*.v")})
    assert "name: interp:rtl:su1571551:" in text
    assert "      - interp:rtl:updown_counter" in text
    assert "parameters: [WIDTH, EXACT]" in text and "default: 32" in text


def test_fusesoc_core_files_are_current(capsys):
    """Every rtl/*.core is what `python -m interp.flows.fusesoc` writes from its module (a new
    parameter or dependency is in the core file too)."""
    assert fusesoc.main(["--check"]) == 0, capsys.readouterr().out


def test_fusesoc_exports_every_declared_parameter():
    """A header comment holding ") (" must not cut the parameter list short."""
    for path in sorted(synth.RTL.glob("*.v")):
        exported = {name for name, _, _ in fusesoc.parameters(path.read_text())}
        assert exported == synth.declared_parameters(path), path.name


def test_family_forms_in_the_file_lists_and_core_files(tmp_path):
    """rtl/<family>/<name>.v replaces rtl/<name>.v in that family's file list (synthesis,
    lint, gate level, bitstream) and gets a fileset picked by the family's FuseSoC tool."""
    for name in ("top", "leaf"):
        (tmp_path / f"{name}.v").write_text(f"module {name}; {'leaf u();' if name == 'top' else ''} endmodule\n")
    (tmp_path / "ice40").mkdir()
    (tmp_path / "ice40" / "leaf.v").write_text("module leaf; endmodule\n")
    assert synth.sources("top", "ice40", tmp_path) == [tmp_path / "top.v", tmp_path / "ice40" / "leaf.v"]
    assert synth.sources("top", "ecp5", tmp_path) == [tmp_path / "top.v", tmp_path / "leaf.v"]
    text = fusesoc.core_text("leaf", {"top", "leaf"}, tmp_path)
    assert "      - ice40/leaf.v" in text and "      - leaf.v" in text
    assert 'filesets: ["tool_icestorm? (rtl_ice40)", "!tool_icestorm? (rtl)"]' in text
    (tmp_path / "ecp5").mkdir()
    (tmp_path / "ecp5" / "leaf.v").write_text("module leaf; endmodule\n")
    assert ('filesets: ["tool_icestorm? (rtl_ice40)", "tool_trellis? (rtl_ecp5)", '
            '"!tool_icestorm? (!tool_trellis? (rtl))"]') in fusesoc.core_text("leaf", {"top", "leaf"}, tmp_path)
    assert "filesets: [rtl]" in fusesoc.core_text("top", {"top", "leaf"}, tmp_path)
    (tmp_path / "ice40" / "orphan.v").write_text("module orphan; endmodule\n")
    assert fusesoc.main(["--check"], tmp_path) == 1


def test_lint_of_a_family_form_reads_the_family_cells(tmp_path):
    """A family form may instance the family's primitives: the lint checks its ports
    and parameters against Yosys's cell library."""
    from interp.flows import lint

    good = tmp_path / "inv.v"
    good.write_text("`default_nettype none\nmodule inv (input wire a, output wire y);\n"
                    "    SB_LUT4 #(.LUT_INIT(16'h5555)) u_lut (.O(y), .I0(a), .I1(1'b0), .I2(1'b0), .I3(1'b0));\n"
                    "endmodule\n`default_nettype wire\n")
    assert lint.lint("inv", [good], "ice40") is None
    bad = tmp_path / "ice40" / "inv.v"
    bad.parent.mkdir()
    bad.write_text(good.read_text().replace(".I3(1'b0)", ".I4(1'b0)"))
    assert "pin" in lint.lint("inv", [bad], "ice40")
    assert "SB_LUT4" in lint.lint("inv", [good], None)          # the portable list has no cells
