"""The FPGA flow's own logic (no tools needed): source scan, parameters, report parsing."""
from interp import fusesoc, synth


def test_sources_follow_instantiations():
    names = [p.stem for p in synth.sources("su1571551")]
    assert names[0] == "su1571551"
    assert set(names) == {"su1571551", "updown_counter", "accum_addsub", "sign_analysis",
                          "mux2", "increment_former", "start_stop", "axis_order"}


def test_only_declared_parameters_are_passed():
    t = synth.resolved(synth.Target("x", "mux2", {"WIDTH": 32, "EXACT": 1}))
    assert t.parameters == {"WIDTH": 32}


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


def test_fusesoc_exports_every_declared_parameter():
    """A header comment holding ") (" must not cut the parameter list short."""
    for path in sorted(synth.RTL.glob("*.v")):
        exported = {name for name, _, _ in fusesoc.parameters(path.read_text())}
        assert exported == synth.declared_parameters(path), path.name
