# SPDX-License-Identifier: Apache-2.0
"""`interp synth`: Fmax and area of the cores on iCE40 HX8K and ECP5-25F (Yosys + nextpnr).

One line per build on stdout (core, family, device, Fmax against the placement
target, LUTs of the device's, FFs, block RAMs, seeds); `--csv FILE` writes the
rows as CSV.  A bad request (unknown core, a parameter the module does not
declare, a design that does not lint) stops before any tool runs, with one
line and exit status 2; a failed build is one line and exit status 1.
`--bitstream DIR` builds the boards instead (boards/<board>/top.v): one line per
board, `--csv FILE` then writes board,family,device,clock_mhz,fmax_mhz,luts,
lut_capacity,ffs,brams,note; a board that does not fit or misses its clock keeps
its row (note) and makes the exit status 1.
"""
from __future__ import annotations

import csv
import sys
from pathlib import Path

from ..cores import UsageError


def add_parser(sub) -> None:
    p = sub.add_parser("synth", help="Yosys + nextpnr for every core: Fmax, LUTs, FFs at width 32",
                       description="Synthesize and place-and-route the cores (table CORES in "
                       "interp/flows/synth.py) on iCE40 HX8K and ECP5-25F; one summary line per build.")
    p.add_argument("--core", action="append", metavar="NAME",
                   help="only this core (repeatable; CLI name such as lin-std, or Verilog top; "
                   "--list shows them)")
    p.add_argument("--family", action="append", choices=["ice40", "ecp5"],
                   help="only this FPGA family (repeatable; default both)")
    p.add_argument("--width", type=int, metavar="N",
                   help="set each chosen core's width parameter (WIDTH; W for motion_top) to N; "
                   "cores without one (feed_rate, step_sync, step_dir) keep theirs unless named")
    p.add_argument("--param", action="append", metavar="NAME=VALUE",
                   help="set a Verilog parameter of the chosen cores, or with --bitstream of the board tops "
                   "(repeatable); each chosen module must declare it")
    p.add_argument("--seeds", type=int, metavar="N",
                   help="placement seeds to try (default: the table's, 8 for the cores with an Fmax goal)")
    p.add_argument("--force", action="store_true", help="re-run even where a cached result is current")
    p.add_argument("--csv", metavar="FILE", help="also write the rows as CSV "
                   "(core,family,device,fmax_mhz,luts,ffs,target_mhz,lut_capacity,brams,"
                   "bram_capacity,seeds,parameters,note; with --bitstream: "
                   "board,family,device,clock_mhz,fmax_mhz,luts,lut_capacity,ffs,brams,note)")
    p.add_argument("--list", action="store_true", help="list the cores and their parameters; run nothing")
    p.add_argument("--bitstream", metavar="DIR", help="instead: build the boards' bitstreams "
                   "(boards/hx8k_breakout: iCE40-HX8K breakout; boards/ulx3s: ULX3S 25F) into DIR, "
                   "one line per board")
    p.set_defaults(func=run)


def run(args) -> int:
    from ..flows import synth

    if args.list:
        for t in synth.table_rows():
            params = " ".join(f"{k}={v}" for k, v in t.parameters.items()) or "(defaults)"
            print(f"{t.name:<20} rtl/{t.toplevel}.v  {params}"
                  + (f"  seeds {t.seeds}" if t.seeds > 1 else ""))
        return 0
    if args.seeds is not None and args.seeds < 1:
        raise UsageError("--seeds must be at least 1")
    if args.width is not None and args.width < 2:
        raise UsageError("--width must be at least 2")
    params = synth.parse_params(args.param)
    if args.bitstream:
        if args.core or args.width is not None or args.seeds is not None:
            raise UsageError("--bitstream builds the boards (boards/*/top.v) only: "
                             "no --core, --width or --seeds (--param sets the tops' parameters)")
        chosen = [name for name, board in synth.BOARDS.items() if not args.family or board.family in args.family]
        for name in chosen:                 # every --param a parameter of each chosen top
            synth.board_with(name, params)
        need_tools(synth)
        rows, failed = [], 0
        for name in chosen:
            try:
                path, row = synth.bitstream(name, Path(args.bitstream), log=progress, force=args.force,
                                            params=params)
            except synth.FlowError as exc:
                print(f"synth: failed: {str(exc).splitlines()[0]}", file=sys.stderr)
                failed += 1
                continue
            rows.append(row)
            print(synth.board_summary(row) + (f"  -> {path}" if path else ""), flush=True)
            if path is None:
                failed += 1
        if args.csv:
            write_csv(args.csv, synth.BOARD_CSV_HEADER, rows)
        return 1 if failed else 0
    # Check the request (names, parameters, lint) before the tools are needed.
    chosen = synth.targets(args.core, params, args.width, args.seeds, args.family)
    need_tools(synth)
    rows, failures = synth.table(args.core, args.family, args.force, log=progress, chosen=chosen,
                                 on_row=lambda row: print(synth.summary(row), flush=True))
    if args.csv:
        write_csv(args.csv, synth.CSV_HEADER, rows)
    for failure in failures:
        print(f"synth: failed: {failure}", file=sys.stderr)
    return 1 if failures else 0


def write_csv(path: str, header: list[str], rows: list[dict]) -> None:
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, header, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)


def need_tools(synth) -> None:
    if not synth.have_tools():
        raise UsageError("the YoWASP tools are not installed: make fpga-deps "
                         "(or pip install -e '.[fpga]')")


def progress(message: str) -> None:
    print(message, file=sys.stderr, flush=True)
