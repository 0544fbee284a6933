# SPDX-License-Identifier: Apache-2.0
# Thin wrapper: the logic lives in Python (interp) and Verilog (rtl/).
# Every target sets up .venv by itself on a fresh machine.
SHELL   := /bin/bash
VENV    ?= .venv
PY      := $(VENV)/bin/python
INTERP  := $(VENV)/bin/interp
JOBS    ?= auto

.PHONY: all deps test test-all demo docs-demo wave lint bench clean fpga-deps synth bitstream test-synth formal docs regs
all: test

# Debian packages only if missing (CI machines have them), then the venv.
deps: $(VENV)/.installed
$(VENV)/.installed: pyproject.toml
	@command -v iverilog >/dev/null || { apt-get update -qq && apt-get install -y -qq iverilog; }
	python3 -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e ".[test]"
	touch $@

test: deps lint
	$(VENV)/bin/pytest -n $(JOBS) tb tests

# make test plus the long sweeps (tests marked slow).
test-all: deps lint
	INTERP_TEST_ALL=1 $(VENV)/bin/pytest -n $(JOBS) tb tests

demo: deps
	$(INTERP) demo --out out/demo

# The README's picture docs/demo.png: a line, an arc, a curve and the G-code demo through the
# RTL (Icarus), with each run's deviation from the programmed path.
docs-demo: deps
	$(INTERP) demo --out out/docs-demo --overview-only --overview docs/demo.png

# A core's built-in example to out/$(CORE).vcd, opened in GTKWave with sim/<module>.gtkw
# (zoomed to the whole run). CORE: circ-arc, curve, su1571551 (the patent's view),
# lin-exact, su1665343, motion (the G-code demo through motion_top).
CORE ?= su1571551
wave: deps
	@if [ -n "$$DISPLAY" ] && ! command -v gtkwave >/dev/null; then apt-get update -qq && apt-get install -y -qq gtkwave; fi
	$(INTERP) wave $(CORE)

# Verilator -Wall on every module's file list: portable, and each FPGA family's (rtl/<family>/).
lint: deps
	$(PY) -m interp.flows.lint

bench: deps
	$(INTERP) bench --md out/bench.md

# FPGA flow: the YoWASP tools (large) are installed here, not by `deps`.
fpga-deps: deps $(VENV)/.fpga
$(VENV)/.fpga: pyproject.toml
	$(PY) -m pip install -q -e ".[fpga]"
	touch $@

# Fmax / LUT / FF of every core at width 32 on iCE40 HX8K and ECP5-25F, one line per build;
# e.g. make synth SYNTH_ARGS="--core lin-std --family ice40" (interp synth --help).
synth: fpga-deps
	@mkdir -p out
	$(INTERP) synth --csv out/synth.csv $(SYNTH_ARGS)

# Bitstreams of the boards (boards/<board>/top.v around rtl/uart_controller.v): iCE40-HX8K
# breakout, ULX3S; out/bitstream/boards.csv: clock, Fmax, LUTs, FFs, BRAMs per board;
# out/bitstream/board_area.csv: LUTs and FFs per module of each board's netlist.
bitstream: fpga-deps
	$(INTERP) synth --bitstream out/bitstream --csv out/bitstream/boards.csv; status=$$?; \
	$(PY) -m interp.flows.board_area out/bitstream/board_area.csv; exit $$status

# Cocotb benches re-run on the Yosys netlists (Icarus: iCE40 cells; Verilator: generic gates).
test-synth: fpga-deps
	INTERP_GATE=1 $(VENV)/bin/pytest -n $(JOBS) tb/gate


# SymbiYosys proofs of formal/*.sby, one line per task (PASS stamps: a proof re-runs when its
# sources change); e.g. make formal PROOFS="blocks su1571551:prf".
formal: fpga-deps
	$(PY) -m interp.flows.formal $(PROOFS)

# Datasheets (docs/cores): WaveDrom JSON -> SVG and the resources tables from
# docs/resources.csv (copy of `make synth`'s out/synth.csv); DOCS_WAVES=1 first
# re-simulates the timing diagrams' JSON on Icarus.
docs: deps
	@if [ -n "$(DOCS_WAVES)" ]; then $(PY) -m interp.docs waves; fi
	$(PY) -m interp.docs svg
	$(PY) -m interp.docs resources

# The register map: regs/controller.rdl -> rtl/controller_regs.vh, interp/link/registers.py,
# sw/interp_controller.h, docs/registers.md (committed; tests/test_registers.py checks them).
regs: deps
	$(PY) -m interp.regs

clean:
	rm -rf sim_build out .pytest_cache
