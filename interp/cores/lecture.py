# SPDX-License-Identifier: Apache-2.0
"""`interp run|model lin-std|lin-accel --x X --y Y` and
`interp run|model circ-std|circ-accel --x0 --y0 --x1 --y1 --dir cw|ccw` (the lecture).

circ-std and circ-accel are one module, rtl/circ_quadrant.v, with ACCEL = 0 / 1."""
import math

from ..models.lecture import CircQuadrant, LinAccel, LinStd, quadrant_error
from . import Core, UsageError, register, signed_range


class LinearCore(Core):
    model_class = LinStd

    def add_arguments(self, parser):
        super().add_arguments(parser)
        parser.add_argument("--x", type=int, required=True, help="signed X increment in steps")
        parser.add_argument("--y", type=int, required=True, help="signed Y increment in steps")

    def check(self, args):
        super().check(args)
        signed_range(args.x, args.width, "--x")
        signed_range(args.y, args.width, "--y")

    def model(self, args):
        return self.model_class(args.width)

    def load(self, args):
        return {"x": args.x, "y": args.y}

    def ideal(self, args):
        return [(0, 0), (args.x, args.y)]


@register
class LinStdCore(LinearCore):
    name = "lin-std"
    toplevel = "lin_std"
    help = "lecture: standard linear interpolation (one axis per tick)"
    examples = [["--x", "5", "--y", "3"], ["--x", "-40", "--y", "23"]]


@register
class LinAccelCore(LinearCore):
    name = "lin-accel"
    toplevel = "lin_accel"
    help = "lecture: accelerated linear interpolation (leading axis, diagonal steps)"
    model_class = LinAccel
    examples = [["--x", "5", "--y", "3"], ["--x", "-40", "--y", "23"]]


def arc_points(cx, cy, x0, y0, x1, y1, ccw, full=False, n=200):
    """The ideal arc from the start point's angle to the end point's, for plots, in
    absolute coordinates (the plotted steps start at (x0, y0): `plot_options`).
    Points close enough that the chords are within 0.001 step of the arc."""
    r = math.hypot(x0 - cx, y0 - cy)
    t0, t1 = math.atan2(y0 - cy, x0 - cx), math.atan2(y1 - cy, x1 - cx)
    sweep = (t1 - t0) % (2 * math.pi) if ccw else -((t0 - t1) % (2 * math.pi))
    if full and sweep == 0:
        sweep = 2 * math.pi if ccw else -2 * math.pi
    n = max(n, math.ceil(abs(sweep) / math.sqrt(0.008 / max(r, 1))))
    return [(cx + r * math.cos(t0 + sweep * k / n), cy + r * math.sin(t0 + sweep * k / n))
            for k in range(n + 1)]


class QuadrantCore(Core):
    toplevel = "circ_quadrant"
    accel = False

    def add_arguments(self, parser):
        super().add_arguments(parser)
        for name, text in (("--x0", "start X"), ("--y0", "start Y"), ("--x1", "end X"), ("--y1", "end Y")):
            parser.add_argument(name, type=int, required=True, help=f"{text} (first quadrant, centre at the origin)")
        parser.add_argument("--dir", choices=("cw", "ccw"), default="ccw", help="direction (default ccw)")

    def check(self, args):
        super().check(args)
        if args.width < 3:
            raise UsageError("--width must be at least 3 for the circular cores")
        for name in ("x0", "y0", "x1", "y1"):
            signed_range(getattr(args, name), args.width, f"--{name}")
        reason = quadrant_error(args.x0, args.y0, args.x1, args.y1, args.dir == "ccw")
        if reason:
            raise UsageError(f"{self.name}: {reason} (the core answers with its error strobe and no step)")

    def parameters(self, args):
        return {"WIDTH": args.width, "ACCEL": int(self.accel)}

    def model(self, args):
        return CircQuadrant(args.width, self.accel)

    def load(self, args):
        return {"x0": args.x0, "y0": args.y0, "x1": args.x1, "y1": args.y1, "ccw": int(args.dir == "ccw")}

    def ideal(self, args):
        return arc_points(0, 0, args.x0, args.y0, args.x1, args.y1, args.dir == "ccw")

    def plot_options(self, args):
        return {"start": (args.x0, args.y0), "centre": (0, 0)}


@register
class CircStdCore(QuadrantCore):
    name = "circ-std"
    help = "lecture: standard circular interpolation, first quadrant"
    examples = [["--x0", "20", "--y0", "0", "--x1", "0", "--y1", "20", "--dir", "ccw"]]


@register
class CircAccelCore(QuadrantCore):
    name = "circ-accel"
    help = "lecture: accelerated circular interpolation by octants, first quadrant"
    accel = True
    examples = [["--x0", "20", "--y0", "0", "--x1", "0", "--y1", "20", "--dir", "ccw"]]
