# SPDX-License-Identifier: Apache-2.0
"""`make formal` (interp/flows/formal.py) without the tools: one line per task, a
failure is a line with the reason and the log, and the exit status says it."""
import pytest

from interp.flows import formal

SBY = """[tasks]
one
two

[options]
mode prove

[engines]
smtbmc boolector

[script]
read -formal {name}.v
prep -top {name}

[files]
{path}
"""


@pytest.fixture
def proofs(tmp_path, monkeypatch):
    (tmp_path / "rtl").mkdir()
    (tmp_path / "rtl" / "ok.v").write_text("module ok; endmodule\n")
    (tmp_path / "formal").mkdir()
    (tmp_path / "formal" / "ok.sby").write_text(SBY.format(name="ok", path="../rtl/ok.v"))
    (tmp_path / "formal" / "gone.sby").write_text(SBY.format(name="gone", path="../rtl/gone.v"))
    monkeypatch.setattr(formal, "FORMAL", tmp_path / "formal")
    monkeypatch.setattr(formal, "BUILD", tmp_path / "build")
    monkeypatch.setattr(formal, "have_tools", lambda: True)
    monkeypatch.setattr(formal, "warm_up", lambda: None)
    return tmp_path


def test_every_task_of_every_sby_one_line_each(proofs, monkeypatch, capsys):
    results = {"one": ("PASS", 1.0), "two": ("FAIL", 2.0)}
    real_prove = formal.prove
    monkeypatch.setattr(formal, "prove", lambda sby, task: real_prove(sby, task) if sby.stem == "gone"
                        else results[task])
    assert formal.main([]) == 1
    lines = capsys.readouterr().out.splitlines()
    assert [ln.split()[1] for ln in lines[:-1]] == ["gone:one", "gone:two", "ok:one", "ok:two"]
    assert "ERROR" in lines[0] and "gone.v, which does not exist" in lines[0]
    assert "PASS (1.0 s)" in lines[2]
    assert "FAIL (2.0 s): see" in lines[3] and "ok_two/logfile.txt" in lines[3]
    assert lines[-1] == "formal: 1 of 4 passed, 3 FAILED"


def test_all_passing_is_exit_0(proofs, monkeypatch, capsys):
    monkeypatch.setattr(formal, "prove", lambda sby, task: ("PASS", 0.5))
    assert formal.main(["ok"]) == 0
    assert capsys.readouterr().out.splitlines()[-1] == "formal: 2 of 2 passed"


def test_unknown_proof_and_missing_tools_are_one_line(proofs, monkeypatch, capsys):
    assert formal.main(["ok:three"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no proof 'ok:three'" in err[0] and "ok:one" in err[0]
    monkeypatch.setattr(formal, "have_tools", lambda: False)
    assert formal.main([]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "make fpga-deps" in err[0]


def test_reason_is_the_first_failure_line_of_the_log(tmp_path):
    (tmp_path / "logfile.txt").write_text(
        "SBY 10:00:00 [x] engine_0: starting\n"
        "SBY 10:00:01 [x] engine_0.basecase: ##   0:00:00  Assert failed in top: check.v:12.9-12.30\n"
        "SBY 10:00:01 [x] DONE (FAIL, rc=2)\n")
    assert formal.reason(tmp_path) == "engine_0.basecase: ##   0:00:00  Assert failed in top: check.v:12.9-12.30"
    assert formal.reason(tmp_path / "none") == ""
