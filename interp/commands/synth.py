"""`interp synth [--csv FILE]`: Fmax and area of every core on iCE40 HX8K and ECP5-25F."""
from __future__ import annotations

import csv
import sys
from pathlib import Path

from ..cores import UsageError


def add_parser(sub) -> None:
    p = sub.add_parser("synth", help="Yosys + nextpnr for every core: Fmax, LUTs, FFs at width 32")
    p.add_argument("--csv", metavar="FILE", help="also write the table as CSV "
                   "(core,family,device,fmax_mhz,luts,ffs)")
    p.add_argument("--core", action="append", help="only this core (repeatable; CLI name)")
    p.add_argument("--family", action="append", choices=["ice40", "ecp5"],
                   help="only this FPGA family (repeatable)")
    p.add_argument("--force", action="store_true", help="re-run even where a cached result is current")
    p.add_argument("--bitstream", metavar="DIR", help="instead: build the board wrapper's bitstreams "
                   "(iCE40-HX8K breakout, ULX3S 25F) into DIR")
    p.set_defaults(func=run)


def run(args) -> int:
    from ..flows import synth

    if not synth.have_tools():
        raise UsageError("the YoWASP tools are not installed: pip install -e '.[fpga]' (or make synth)")
    if args.bitstream:
        for board in synth.BOARDS:
            print(synth.bitstream(board, Path(args.bitstream),
                                  log=lambda m: print(m, file=sys.stderr, flush=True)))
        return 0
    rows, notes = synth.table(args.core, args.family, args.force,
                              log=lambda m: print(m, file=sys.stderr, flush=True))
    writer = csv.DictWriter(sys.stdout, synth.CSV_HEADER, extrasaction="ignore")
    writer.writeheader()
    writer.writerows(rows)
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, synth.CSV_HEADER, extrasaction="ignore")
            w.writeheader()
            w.writerows(rows)
    for note in notes:
        print(f"synth: {note}", file=sys.stderr)
    return 1 if any("failed" in n for n in notes) else 0
