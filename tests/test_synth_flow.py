"""The FPGA flow's own logic (no tools needed): source scan, parameters, report parsing."""
import pytest

from interp.cores import UsageError, load_all
from interp.flows import fusesoc, synth


def test_sources_follow_instantiations():
    names = [p.stem for p in synth.sources("su1571551")]
    assert names[0] == "su1571551"
    assert set(names) == {"su1571551", "updown_counter", "accum_addsub", "sign_analysis",
                          "mux2", "increment_former", "start_stop", "carry_select_add", "axis_order"}


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
    assert "parameters: [WIDTH, EXACT, CARRY_SELECT]" in text and "default: 32" in text


def test_fusesoc_exports_every_declared_parameter():
    """A header comment holding ") (" must not cut the parameter list short."""
    for path in sorted(synth.RTL.glob("*.v")):
        exported = {name for name, _, _ in fusesoc.parameters(path.read_text())}
        assert exported == synth.declared_parameters(path), path.name
