# SPDX-License-Identifier: Apache-2.0
"""`interp run|model su1571551 --x X --y Y --mode faithful|exact` and `lin-exact --x X --y Y`."""
from ..models.su1571551 import MODES, Su1571551
from . import Core, register, signed_range


@register
class Su1571551Core(Core):
    name = "su1571551"
    toplevel = "su1571551"
    help = "SU 1571551 linear interpolator (diagonal + axial steps)"
    trace_header = ["step", "kind", "f", "ctr1", "ctr2"]
    examples = [["--x", "7", "--y", "3", "--mode", "faithful"],
                ["--x", "-40", "--y", "23", "--mode", "exact"],
                ["--x", "-40", "--y", "23", "--mode", "faithful"]]

    def add_arguments(self, parser):
        super().add_arguments(parser)
        parser.add_argument("--x", type=int, required=True, help="signed X increment in steps")
        parser.add_argument("--y", type=int, required=True, help="signed Y increment in steps")
        parser.add_argument("--mode", choices=MODES, default="exact",
                            help="faithful: the patent's live counters; exact: expression (1)")

    def check(self, args):
        super().check(args)
        signed_range(args.x, args.width, "--x")
        signed_range(args.y, args.width, "--y")

    def parameters(self, args):
        return {"WIDTH": args.width, "EXACT": int(args.mode == "exact")}

    def model(self, args):
        return Su1571551(args.width, args.mode == "exact")

    def load(self, args):
        return {"x": args.x, "y": args.y}

    def trace(self, samples):
        rows = []
        for s in samples:
            if s["step_x"] or s["step_y"]:
                rows.append({"step": len(rows) + 1,
                             "kind": "diagonal" if s["step_x"] and s["step_y"] else "axial",
                             "f": s["f"] / 2, "ctr1": s["ctr1"], "ctr2": s["ctr2"] + 1})
        return rows

    def ideal(self, args):
        return [(0, 0), (args.x, args.y)]



@register
class LinExactCore(Su1571551Core):
    """`interp run|model lin-exact --x X --y Y`: the production linear core
    (rtl/lin_exact.v), SU 1571551's exact mode retimed; same cycle model."""
    name = "lin-exact"
    toplevel = "lin_exact"
    help = "production linear core: SU 1571551's exact mode (expression (1)), retimed"
    examples = [["--x", "-40", "--y", "23"]]

    def add_arguments(self, parser):
        Core.add_arguments(self, parser)
        parser.add_argument("--x", type=int, required=True, help="signed X increment in steps")
        parser.add_argument("--y", type=int, required=True, help="signed Y increment in steps")

    def parameters(self, args):
        return {"WIDTH": args.width}

    def model(self, args):
        return Su1571551(args.width, True)
