# SPDX-License-Identifier: Apache-2.0
"""`interp run|model su1665343 --r R [--x0 X --y0 Y]`: the SU 1665343 circular interpolator."""
from ..models.su1665343 import Su1665343, start_error, trace
from . import Core, UsageError, register


@register
class Su1665343Core(Core):
    name = "su1665343"
    toplevel = "circ_su1665343"
    help = "SU 1665343 circular interpolator (one quadrant, ones'-complement datapath)"
    trace_header = ["step", "kind", "ct7", "ct8", "code", "f"]
    examples = [["--r", "12"], ["--r", "100"], ["--r", "100", "--x0", "71", "--y0", "71"]]

    def add_arguments(self, parser):
        parser.add_argument("--width", type=int, default=16,
                            help="CT7/CT8 width in bits, 4 .. 30 (default 16); R <= 2^(width-1) - 2")
        parser.add_argument("--r", type=int, required=True, help="radius in steps")
        parser.add_argument("--x0", type=int, help="start point X (default R); with --y0")
        parser.add_argument("--y0", type=int, help="start point Y (default 0); with --x0")

    def check(self, args):
        if not 4 <= args.width <= 30:
            raise UsageError(f"--width {args.width} is outside 4 .. 30")
        if (args.x0 is None) != (args.y0 is None):
            raise UsageError("give both --x0 and --y0, or neither")
        x0, y0 = self._start(args)
        why = start_error(args.r, x0, y0, args.width)
        if why:
            raise UsageError(why)
        self.width = args.width          # for trace(): decoding the ones'-complement codes

    @staticmethod
    def _start(args):
        return (args.r, 0) if args.x0 is None else (args.x0, args.y0)

    def parameters(self, args):
        return {"WIDTH": args.width}

    def model(self, args):
        return Su1665343(args.width)

    def load(self, args):
        x0, y0 = self._start(args)
        return {"r": args.r, "x0": x0, "y0": y0}

    def trace(self, samples):
        return trace(samples, getattr(self, "width", 16))

    def ideal(self, args):
        import math
        x0, y0 = self._start(args)
        a0 = math.atan2(y0, x0)
        n = max(200, math.ceil((math.pi / 2 - a0) / math.sqrt(0.008 / args.r)))
        return [(args.r * math.cos(a0 + (math.pi / 2 - a0) * k / n),
                 args.r * math.sin(a0 + (math.pi / 2 - a0) * k / n)) for k in range(n + 1)]

    def plot_options(self, args):
        return {"start": self._start(args), "centre": (0, 0)}
