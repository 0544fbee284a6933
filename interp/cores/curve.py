# SPDX-License-Identifier: Apache-2.0
"""`interp run|model curve --curve NAME --a A --b B ...`: the tangent-method curve core."""
from __future__ import annotations

from ..models.base import move
from ..models.curve import (CURVES, END_X, END_Y, CurveTangent, Program, anchored_e, distance,
                            ideal_points, program, projections, steps)
from . import Core, UsageError, register, signed_range


@register
class CurveCore(Core):
    name = "curve"
    toplevel = "curve_tangent"
    help = "arbitrary planar curves by the tangent method (Bulatnikov 2011)"
    band = 0.5
    examples = [["--curve", "exponent", "--a", "100", "--b", "10", "--mode", "improved"],
                ["--curve", "circle", "--a", "40", "--mode", "improved"],
                ["--curve", "circle", "--a", "40", "--mode", "literal"]]

    def add_arguments(self, parser):
        parser.add_argument("--curve", choices=sorted(CURVES), required=True)
        parser.add_argument("--a", type=int, required=True, help="scale A (on y; the radius of a circle)")
        parser.add_argument("--b", type=int, help="scale B (on x; default A)")
        parser.add_argument("--x0", type=int, help="start node x (with --y0; default: the curve's start)")
        parser.add_argument("--y0", type=int, help="start node y, within half a step of the curve")
        end = parser.add_mutually_exclusive_group()
        end.add_argument("--end-x", type=int, help="stop when x reaches this value")
        end.add_argument("--end-y", type=int, help="stop when y reaches this value")
        parser.add_argument("--count", type=int, help="number of steps, or the step budget with --end-x/--end-y")
        parser.add_argument("--reverse", action="store_true", help="travel against the tangent")
        parser.add_argument("--mode", choices=["literal", "improved"], default="literal",
                            help="literal: the paper's points 1-9; improved: see docs/algorithms.md")
        parser.add_argument("--reanchor", type=int, default=0, metavar="N",
                            help="restart every N steps with E from the true curve (0: never)")
        parser.add_argument("--width", type=int, default=16, help="coordinate width WIDTH (default 16)")
        parser.add_argument("--pw", type=int, default=24, help="projection width PW (default 24)")

    def program(self, args) -> Program:
        spec, b = CURVES[args.curve], args.b if args.b is not None else args.a
        end = (END_X, args.end_x) if args.end_x is not None else \
            (END_Y, args.end_y) if args.end_y is not None else None
        if end is None and args.count is None:
            end = spec.end(args.a, b)
        return program(spec, args.a, b, args.x0, args.y0, end=end, count=args.count,
                       reverse=args.reverse, improved=args.mode == "improved")

    def check(self, args):
        if not 3 <= args.width <= 32 or not 3 <= args.pw <= 48:
            raise UsageError("--width must be 3 .. 32 and --pw 3 .. 48")
        if args.a <= 0 or (args.b is not None and args.b <= 0):
            raise UsageError("--a and --b must be positive")
        if (args.x0 is None) != (args.y0 is None):
            raise UsageError("give both --x0 and --y0, or neither")
        if args.count is not None and not 0 <= args.count < 1 << 24:
            raise UsageError("--count must be 0 .. 2^24 - 1")
        spec, b = CURVES[args.curve], args.b if args.b is not None else args.a
        try:
            prog = self.program(args)
        except (ValueError, ZeroDivisionError) as err:
            raise UsageError(f"curve {args.curve} with A={args.a}, B={b}: {err}") from None
        off = distance(spec, args.a, b, prog.x0, prog.y0)
        if off > 0.5:
            raise UsageError(f"start point ({prog.x0}, {prog.y0}) is {off:.3g} steps off the {args.curve}")
        for what in ("x0", "y0", "end_coord"):
            signed_range(getattr(prog, what), args.width, what)
        for what in ("p0", "q0", "dp_dx", "dp_dy", "dq_dx", "dq_dy"):
            signed_range(getattr(prog, what), args.pw, f"{what} (A={args.a}, B={b})")
        res = steps(prog, args.width, args.pw)
        if res.error:
            raise UsageError(f"the core stops after {len(res.steps)} steps: {res.error} "
                             "(a wider --width/--pw or a shorter path fits)")

    def parameters(self, args):
        return {"WIDTH": args.width, "PW": args.pw, "CW": 24}

    def model(self, args):
        return CurveTangent(args.width, args.pw, 24)

    def load(self, args):
        return self.program(args).inputs()

    def stimulus(self, args):
        if not args.reanchor:
            return move(self.load(args), max_cycles=args.max_cycles)
        return self._segments(args)

    def _segments(self, args):
        """Re-anchoring: restart every N steps at the reached node with E from the true curve."""
        prog = self.program(args)
        spec, b = CURVES[args.curve], args.b if args.b is not None else args.a
        x, y, left = prog.x0, prog.y0, prog.count
        while left > 0:
            seg = self.program(args)
            seg.x0, seg.y0 = x, y
            seg.p0, seg.q0 = projections(spec, args.a, b, x, y)
            seg.count, seg.e_load = min(args.reanchor, left), 1
            seg.e_init = anchored_e(spec, args.a, b, x, y, args.reverse)
            made = 0
            gen = move(seg.inputs(), max_cycles=args.max_cycles, idle_after=0)
            sample = yield next(gen)
            try:
                while True:
                    made += sample["step_x"] | sample["step_y"]
                    if sample["done"]:
                        x, y, error = sample["x_q"], sample["y_q"], sample["error"]
                    sample = yield gen.send(sample)
            except StopIteration:
                pass
            left -= seg.count
            if error or made < seg.count:        # reached the end, or stopped on bad input
                break
        yield {**seg.inputs(), "start": 0, "tick": 1}

    def ideal(self, args):
        prog = self.program(args)
        pts = [(prog.x0, prog.y0)] + [(s.x, s.y) for s in steps(prog, args.width, args.pw).steps]
        return ideal_points(CURVES[args.curve], args.a, args.b if args.b is not None else args.a, pts)

    def plot_options(self, args):
        prog = self.program(args)
        centre = {"centre": (0, 0)} if args.curve in ("circle", "ellipse") else {}
        return {"start": (prog.x0, prog.y0), "band": self.band, **centre}
