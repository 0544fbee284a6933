# SPDX-License-Identifier: Apache-2.0
"""`interp run|model circ-arc --cx --cy --x0 --y0 --x1 --y1 --dir cw|ccw [--full]`."""
from ..models.arc import CircArc, arc_error
from . import Core, UsageError, register, signed_range
from .lecture import arc_points

# The model's point and E, which circ_arc keeps inside (its stepper's step stage).
PROBES = {"pos_u": "u_stepper.u_step_stage.position_u", "pos_v": "u_stepper.u_step_stage.position_v",
          "e": "u_stepper.u_step_stage.e_value"}


@register
class CircArcCore(Core):
    name = "circ-arc"
    toplevel = "circ_arc"
    probes = PROBES
    help = "production arc: any start/end on a circle, all octants, one step per clock"
    examples = [["--cx", "0", "--cy", "0", "--x0", "30", "--y0", "0", "--x1", "30", "--y1", "0", "--full"],
                ["--cx", "5", "--cy", "-5", "--x0", "25", "--y0", "-5", "--x1", "-15", "--y1", "-5",
                 "--dir", "cw"]]

    def add_arguments(self, parser):
        super().add_arguments(parser)
        for name, text in (("--cx", "centre X"), ("--cy", "centre Y"), ("--x0", "start X"),
                           ("--y0", "start Y"), ("--x1", "end X"), ("--y1", "end Y")):
            parser.add_argument(name, type=int, required=True, help=f"{text} (absolute, signed)")
        parser.add_argument("--dir", choices=("cw", "ccw"), default="ccw", help="direction (default ccw)")
        parser.add_argument("--full", action="store_true",
                            help="with end = start: a full circle (without it: no step)")

    def check(self, args):
        super().check(args)
        if args.width < 6:
            raise UsageError("--width must be at least 6 for circ-arc")
        for name in ("cx", "cy", "x0", "y0", "x1", "y1"):
            signed_range(getattr(args, name), args.width, f"--{name}")
        reason = arc_error(args.cx, args.cy, args.x0, args.y0, args.x1, args.y1, args.width)
        if reason:
            raise UsageError(f"{self.name}: {reason} (the core answers with its error strobe and no step)")

    def model(self, args):
        return CircArc(args.width)

    def load(self, args):
        return {"cx": args.cx, "cy": args.cy, "x0": args.x0, "y0": args.y0, "x1": args.x1, "y1": args.y1,
                "ccw": int(args.dir == "ccw"), "full": int(args.full)}

    def ideal(self, args):
        return arc_points(args.cx, args.cy, args.x0, args.y0, args.x1, args.y1, args.dir == "ccw", args.full)

    def plot_options(self, args):
        return {"start": (args.x0, args.y0), "centre": (args.cx, args.cy)}
