# SPDX-License-Identifier: Apache-2.0
"""`interp synth`'s error paths and output, without the YoWASP tools: a bad request
stops before any tool runs (one line on stderr, exit status 2), a failed build is one
line (exit status 1), and each build prints one summary line."""
import csv

import pytest

from interp.cli import main
from interp.flows import synth

GOOD = """`default_nettype none
module good #(
    parameter integer WIDTH = 4   // width
) (
    input  wire             clk,
    input  wire [WIDTH-1:0] d,
    output reg  [WIDTH-1:0] q
);
    always @(posedge clk) q <= d;
endmodule
`default_nettype wire
"""
BAD = GOOD.replace("module good", "module bad").replace("q <= d;", "q <= {d, 1'b0};")   # WIDTHTRUNC


def one_line_error(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "Traceback" not in err[0], err
    return err[0]


@pytest.fixture
def no_tools(monkeypatch):
    """The tools must not be reached: implement() fails the test if it is called."""
    def implement(*args, **kwargs):
        raise AssertionError("a tool ran on a bad request")
    monkeypatch.setattr(synth, "implement", implement)


@pytest.fixture
def scratch_rtl(tmp_path, monkeypatch):
    """An rtl/ folder with a clean module and one that does not lint, and a table of both."""
    (tmp_path / "good.v").write_text(GOOD)
    (tmp_path / "bad.v").write_text(BAD)
    monkeypatch.setattr(synth, "RTL", tmp_path)
    monkeypatch.setattr(synth, "CORES", [synth.Target("good", "good", {"WIDTH": 8}),
                                         synth.Target("bad", "bad", {"WIDTH": 8})])
    return tmp_path


def test_unknown_core(capsys, no_tools):
    assert main(["synth", "--core", "nosuchcore"]) == 2
    line = one_line_error(capsys)
    assert "unknown core 'nosuchcore'" in line and "lin-std" in line


def test_undeclared_parameter_on_the_command_line(capsys, no_tools):
    assert main(["synth", "--core", "lin-std", "--param", "EXACT=1"]) == 2
    assert "rtl/lin_std.v declares no parameter EXACT" in one_line_error(capsys)


def test_width_of_a_core_without_one(capsys, no_tools):
    assert main(["synth", "--core", "step_dir", "--width", "16"]) == 2
    assert "no width parameter" in one_line_error(capsys)


@pytest.mark.parametrize("param", ["WIDTH", "WIDTH=x", "=3", "W IDTH=3"])
def test_malformed_param(capsys, no_tools, param):
    assert main(["synth", "--core", "lin-std", "--param", param]) == 2
    assert "expected NAME=INTEGER" in one_line_error(capsys)


def test_undeclared_parameter_in_a_table_row(capsys, no_tools, scratch_rtl, monkeypatch):
    monkeypatch.setattr(synth, "CORES", [synth.Target("good", "good", {"WIDTH": 8, "DEPTH": 2})])
    assert main(["synth", "--core", "good"]) == 2
    assert "rtl/good.v declares no parameter DEPTH (it declares: WIDTH)" in one_line_error(capsys)


def test_lint_error_stops_the_flow(capsys, no_tools, scratch_rtl):
    assert main(["synth", "--core", "bad", "--family", "ice40"]) == 2
    line = one_line_error(capsys)
    assert "core bad on ice40 does not lint" in line and "WIDTHTRUNC" in line and "bad.v" in line


def test_lint_error_in_a_family_form(capsys, no_tools, scratch_rtl):
    """The flow lints the family's file list: rtl/ice40/<name>.v replaces rtl/<name>.v."""
    (scratch_rtl / "ice40").mkdir()
    (scratch_rtl / "ice40" / "good.v").write_text(BAD.replace("module bad", "module good"))
    assert synth.targets(["good"], families=["ecp5"])      # the portable form is clean
    assert main(["synth", "--core", "good", "--family", "ice40"]) == 2
    assert "core good on ice40 does not lint" in one_line_error(capsys)


def test_missing_tools_is_one_line(capsys, no_tools, monkeypatch):
    monkeypatch.setattr(synth, "have_tools", lambda: False)
    assert main(["synth", "--core", "lin-std"]) == 2
    assert "make fpga-deps" in one_line_error(capsys)


def fake_row(target, family, force=False, log=print):
    return {"core": target.name, "family": family.name, "device": family.device, "fmax_mhz": 123.4,
            "luts": 100, "ffs": 50, "seeds": target.seeds, "target_mhz": family.freq_mhz,
            "lut_capacity": 7680, "brams": 0, "bram_capacity": 32,
            "parameters": " ".join(f"{k}={v}" for k, v in target.parameters.items()), "note": ""}


def test_summary_lines_and_csv(capsys, tmp_path, monkeypatch):
    seen = []
    monkeypatch.setattr(synth, "have_tools", lambda: True)
    monkeypatch.setattr(synth, "implement", lambda t, f, *a, **k: seen.append(t) or fake_row(t, f))
    out = tmp_path / "synth.csv"
    assert main(["synth", "--core", "motion_top", "--core", "lin-std", "--family", "ice40",
                 "--width", "24", "--seeds", "2", "--csv", str(out)]) == 0
    assert [t.parameters for t in seen] == [{"WIDTH": 24}, {"W": 24, "POS_W": 32}]
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 2
    assert lines[0].startswith("lin-std") and "Fmax  123.4 MHz (target 160)" in lines[0]
    assert "LUTs    100/7680" in lines[0] and "FFs    50" in lines[0] and "BRAMs  0/32" in lines[0]
    assert "seeds 2" in lines[0] and "WIDTH=24" in lines[0]
    rows = list(csv.reader(out.open()))
    assert rows[0][:6] == ["core", "family", "device", "fmax_mhz", "luts", "ffs"]
    assert rows[1][:6] == ["lin-std", "ice40", "iCE40HX8K-CT256", "123.4", "100", "50"]


def test_failed_build_is_one_line_and_exit_1(capsys, monkeypatch):
    def implement(target, family, *args, **kwargs):
        raise synth.FlowError("yosys failed: ERROR: boom (see build/synth/x/yosys.log)\nlog tail\nmore")
    monkeypatch.setattr(synth, "have_tools", lambda: True)
    monkeypatch.setattr(synth, "implement", implement)
    assert main(["synth", "--core", "lin-std", "--family", "ecp5"]) == 1
    assert one_line_error(capsys) == \
        "synth: failed: lin-std on ecp5: yosys failed: ERROR: boom (see build/synth/x/yosys.log)"


def test_list_needs_no_tools(capsys, monkeypatch):
    monkeypatch.setattr(synth, "have_tools", lambda: False)
    assert main(["synth", "--list"]) == 0
    out = capsys.readouterr().out
    assert "motion_top" in out and "W=32" in out and "lin-std" in out
