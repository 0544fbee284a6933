# SPDX-License-Identifier: Apache-2.0
"""Golden models of the tangent-method curve interpolator (the paper by Bulatnikov and Bulatnikova).

The tangent's projections at node (x, y) are affine:
    ΔX = φ(x, y) = p0 + dp_dx·(x − x0) + dp_dy·(y − y0)
    ΔY = ψ(x, y) = q0 + dq_dx·(x − x0) + dq_dy·(y − y0)
so hardware keeps them up to date with adders as x and y move.

`steps()` is the paper's algorithm written step by step (points 1–9):
    1  E0 = |ΔX| − 2|ΔY| (x-major, |ΔX| ≥ |ΔY|)   or   |ΔY| − 2|ΔX| (y-major)
    2  major axis: δ = sign; minor axis: δ = sign if E < 0 else 0
    3  move;  4  new projections ΔX', ΔY'
    5  E += 2(L' − S') if E < 0 else E −= 2S'      (L, S: |major|, |minor|)
    6  E += (L' − 2S') − (L − 2S)                 (change of the initial value E0)
    8  major axis changed: E += (new E0 form − old E0 form), both at the new projections
    9  end test
The merged formula of point 7 (garbled in the OCR), derived from 5 + 6:
    E' = E + L' − 4S' − L + 2S + (2L' if E < 0 else 0)
and with 8 folded in (major axis changes): E' += 3S' − 3L'.

`improved` mode (not in the paper; see docs/algorithms.md): the step uses the mean of the
old and new minor projections (trapezoid slope, S + S' instead of 2S'), and on a
change of major axis the deviation part of E changes sign (a node above the
curve is behind it horizontally), so E := −E − L' − S'.  Merged:
    E' = E + L' − 3S' − L + S + (2L' if E < 0 else 0);  switch: E' := −E' − L' − S'.

`CurveTangent` is the cycle model of rtl/curve_tangent.v.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from .base import MOTION_OUTPUTS, CycleModel

END_COUNT, END_X, END_Y = 0, 1, 2   # end_sel codes


def sign(v: int) -> int:
    return (v > 0) - (v < 0)


@dataclass
class Program:
    """Everything the core takes with `start` (integers, as on the ports)."""

    x0: int
    y0: int
    p0: int                 # ΔX at (x0, y0)
    q0: int                 # ΔY at (x0, y0)
    dp_dx: int
    dp_dy: int
    dq_dx: int
    dq_dy: int
    count: int              # steps (end_sel 0) or step budget
    end_sel: int = END_COUNT
    end_coord: int = 0
    reverse: int = 0
    improved: int = 0
    e_load: int = 0         # 1: E starts at e_init (re-anchoring) instead of E0
    e_init: int = 0

    def inputs(self) -> dict[str, int]:
        return dict(vars(self))

    def as_ports(self, width: int, pw: int, cw: int) -> "Program":
        """The program as the core sees it: every value cut to its port's width."""
        w = {"x0": width, "y0": width, "end_coord": width, "e_init": pw + 4,
             **{k: pw for k in ("p0", "q0", "dp_dx", "dp_dy", "dq_dx", "dq_dy")}}
        u = {"count": cw, "end_sel": 2, "reverse": 1, "improved": 1, "e_load": 1}
        return Program(**{k: wrap(v, w[k]) if k in w else v & ((1 << u[k]) - 1)
                          for k, v in vars(self).items()})


def e0_form(major: int, minor: int) -> int:
    """Point 1: the initial evaluation function for |major| >= |minor|."""
    return major - 2 * minor


def merged_update(e: int, l: int, s: int, l2: int, s2: int, switch: bool, improved: bool) -> int:
    """Point 7 (+ 8): new E from the old (L, S) and new (L', S') in the old orientation."""
    diag = 2 * l2 if e < 0 else 0
    if improved:
        e2 = e + l2 - 3 * s2 - l + s + diag
        return -e2 - l2 - s2 if switch else e2
    e2 = e + l2 - 4 * s2 - l + 2 * s + diag
    return e2 + 3 * s2 - 3 * l2 if switch else e2


def literal_update(e: int, l: int, s: int, l2: int, s2: int, switch: bool) -> int:
    """Points 5, 6 and 8 applied one after the other, as the paper prints them."""
    e = e + 2 * (l2 - s2) if e < 0 else e - 2 * s2                  # 5
    e = e + e0_form(l2, s2) - e0_form(l, s)                          # 6
    if switch:
        e = e + e0_form(s2, l2) - e0_form(l2, s2)                    # 8
    return e


@dataclass
class Step:
    dx: int
    dy: int
    x: int
    y: int
    e: int                  # E after the step
    p: int                  # ΔX at the new node
    q: int                  # ΔY at the new node


@dataclass
class Result:
    steps: list[Step] = field(default_factory=list)
    error: str | None = None      # why the move stopped early, None if it ended normally


def steps(prog: Program, width: int = 16, pw: int = 24, max_steps: int | None = None) -> Result:
    """The paper's points 1–9 (literal) or the improved variant, one step at a time."""
    ew = pw + 4
    x, y, p, q = prog.x0, prog.y0, prog.p0, prog.q0
    xmaj = abs(p) >= abs(q)
    e = prog.e_init if prog.e_load else (e0_form(abs(p), abs(q)) if xmaj else e0_form(abs(q), abs(p)))
    out = Result()
    if prog.end_sel not in (END_COUNT, END_X, END_Y):
        out.error = "end_sel"
        return out
    n = prog.count
    rev = -1 if prog.reverse else 1
    while True:
        if n == 0 or (prog.end_sel == END_X and x == prog.end_coord) or \
                (prog.end_sel == END_Y and y == prog.end_coord):
            return out                                                  # 9
        if max_steps is not None and len(out.steps) >= max_steps:
            return out
        if p == 0 and q == 0:
            out.error = "stall"
            return out
        if xmaj:                                                        # 2
            dx, dy = rev * sign(p), (rev * sign(q) if e < 0 else 0)
        else:
            dx, dy = (rev * sign(p) if e < 0 else 0), rev * sign(q)
        x2, y2 = x + dx, y + dy                                         # 3
        p2 = p + dx * prog.dp_dx + dy * prog.dp_dy                      # 4
        q2 = q + dx * prog.dq_dx + dy * prog.dq_dy
        l, s, l2, s2 = (abs(p), abs(q), abs(p2), abs(q2)) if xmaj else (abs(q), abs(p), abs(q2), abs(p2))
        xmaj2 = abs(p2) >= abs(q2)
        if prog.improved:
            e2 = merged_update(e, l, s, l2, s2, xmaj2 != xmaj, True)
        else:
            e2 = literal_update(e, l, s, l2, s2, xmaj2 != xmaj)         # 5, 6, 8
        if not (fits(x2, width) and fits(y2, width)):
            out.error = "range"
        elif not (fits(p2, pw) and fits(q2, pw)):
            out.error = "projection overflow"
        elif not fits(e2, ew):
            out.error = "E overflow"
        if out.error:
            return out
        x, y, p, q, e, xmaj, n = x2, y2, p2, q2, e2, xmaj2, n - 1
        out.steps.append(Step(dx, dy, x, y, e, p, q))


def fits(v: int, bits: int) -> bool:
    return -(1 << (bits - 1)) <= v < (1 << (bits - 1))


def wrap(v: int, bits: int) -> int:
    v &= (1 << bits) - 1
    return v - (1 << bits) if v >> (bits - 1) else v


class CurveTangent(CycleModel):
    """Cycle model of rtl/curve_tangent.v (registers named as the RTL's)."""

    watch = {**MOTION_OUTPUTS, "error": False, "x_q": True, "y_q": True, "p": True, "q": True,
             "e_q": True, "cnt_q": False}
    # the RTL's register names
    x_q = property(lambda self: self.x)
    y_q = property(lambda self: self.y)
    e_q = property(lambda self: self.e)
    cnt_q = property(lambda self: self.cnt)

    def __init__(self, width: int = 16, pw: int = 24, cw: int = 24):
        self.width, self.pw, self.cw, self.ew = width, pw, cw, pw + 4
        self.reset()

    def reset(self) -> None:
        self.run = 0
        self.x = self.y = self.p = self.q = self.e = self.cnt = 0
        self.prog: Program | None = None
        self.xmaj = 0
        self.step_x = self.step_y = self.dir_x = self.dir_y = self.done = self.error = 0

    @property
    def busy(self) -> int:
        return self.run

    def clock(self, inputs) -> None:
        if inputs.get("rst"):
            self.reset()
            return
        self.step_x = self.step_y = self.done = self.error = 0
        if inputs.get("start") and not self.run:
            self._load(inputs)
            return
        if not self.run:
            return
        prog = self.prog
        at_end = self.cnt == 0 or (prog.end_sel == END_X and self.x == prog.end_coord) or \
            (prog.end_sel == END_Y and self.y == prog.end_coord)
        bad_sel = prog.end_sel not in (END_COUNT, END_X, END_Y)
        if at_end or bad_sel:
            self.run, self.done, self.error = 0, 1, int(bad_sel)
            return
        if not inputs.get("tick"):
            return
        one = Program(**{**vars(prog), "x0": self.x, "y0": self.y, "p0": self.p, "q0": self.q,
                         "e_load": 1, "e_init": self.e, "count": 1, "end_sel": END_COUNT,
                         "improved": prog.improved})
        if prog.improved:
            res = steps(one, self.width, self.pw)
        else:
            res = self._merged_step(one)
        if res.error:
            self.run, self.done, self.error = 0, 1, 1
            return
        s = res.steps[0]
        self.step_x, self.step_y = int(s.dx != 0), int(s.dy != 0)
        if s.dx:
            self.dir_x = int(s.dx < 0)
        if s.dy:
            self.dir_y = int(s.dy < 0)
        self.x, self.y, self.p, self.q, self.e = s.x, s.y, s.p, s.q, s.e
        self.cnt -= 1

    def _merged_step(self, one: Program) -> Result:
        """The RTL computes the merged formula (point 7 + 8); it must equal steps()."""
        res = steps(one, self.width, self.pw)
        if res.steps:
            s = res.steps[0]
            p, q = one.p0, one.q0
            xmaj = abs(p) >= abs(q)
            l, sm, l2, s2 = (abs(p), abs(q), abs(s.p), abs(s.q)) if xmaj else (abs(q), abs(p), abs(s.q), abs(s.p))
            merged = merged_update(one.e_init, l, sm, l2, s2, (abs(s.p) >= abs(s.q)) != xmaj, False)
            assert merged == s.e, "merged formula differs from points 5 + 6 + 8"
        return res

    def _load(self, inputs) -> None:
        names = vars(Program(0, 0, 0, 0, 0, 0, 0, 0, 0))
        prog = Program(**{k: inputs[k] for k in names}).as_ports(self.width, self.pw, self.cw)
        self.prog = prog
        self.run = 1
        self.x, self.y, self.p, self.q, self.cnt = prog.x0, prog.y0, prog.p0, prog.q0, prog.count
        p, q = abs(prog.p0), abs(prog.q0)
        self.e = prog.e_init if prog.e_load else (e0_form(p, q) if p >= q else e0_form(q, p))


# ---------------------------------------------------------------------------
# The curves: projections, start, end, the true curve (for errors, plots, checks)
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class CurveSpec:
    """One curve family with scales A (on y) and B (on x), as in the paper's table."""

    name: str
    equation: str
    coeffs: object          # (a, b) -> (px, py, pc, qx, qy, qc): ΔX = px·x + py·y + pc, ΔY likewise
    start: object           # (a, b) -> (x0, y0), an integer point of the curve
    end: object             # (a, b) -> (end_sel, end_coord)
    residual: object        # (a, b, x, y) -> (F, dF/dx, dF/dy), F = 0 on the curve
    f: object = None        # y(x) and x(y) for the paper's curves (error measured the paper's way)
    finv: object = None
    slope: object = None


CURVES: dict[str, CurveSpec] = {c.name: c for c in [
    CurveSpec("exponent", "y = A·e^(x/B)", lambda a, b: (0, 0, b, 0, 1, 0),
              lambda a, b: (0, a), lambda a, b: (END_X, b),
              lambda a, b, x, y: (y - a * math.exp(x / b), -a / b * math.exp(x / b), 1.0),
              f=lambda a, b, x: a * math.exp(x / b),
              finv=lambda a, b, y: b * math.log(y / a) if y > 0 else -math.inf,
              slope=lambda a, b, x: a / b * math.exp(x / b)),
    CurveSpec("logarithm", "y = A·ln(x/B)", lambda a, b: (1, 0, 0, 0, 0, a),
              lambda a, b: (b, 0), lambda a, b: (END_X, 2 * a),
              lambda a, b, x, y: ((y - a * math.log(x / b), -a / x, 1.0) if x > 0 else (math.inf, 1.0, 1.0)),
              f=lambda a, b, x: a * math.log(x / b) if x > 0 else -math.inf,
              finv=lambda a, b, y: b * math.exp(y / a),
              slope=lambda a, b, x: a / x if x > 0 else math.inf),
    CurveSpec("hyperbola", "x·y = A·B", lambda a, b: (1, 0, 0, 0, -1, 0),
              lambda a, b: (b, a), lambda a, b: (END_X, a),
              lambda a, b, x, y: (x * y - a * b, float(y), float(x)),
              f=lambda a, b, x: a * b / x if x else math.inf,
              finv=lambda a, b, y: a * b / y if y else math.inf,
              slope=lambda a, b, x: a * b / (x * x) if x else math.inf),
    CurveSpec("sqrt", "y = A·√(x/B)", lambda a, b: (0, 2 * b, 0, 0, 0, a * a),
              lambda a, b: (0, 0), lambda a, b: (END_X, a * a // b),
              lambda a, b, x, y: (y * y - a * a * x / b, -a * a / b, 2.0 * y),
              f=lambda a, b, x: a * math.sqrt(x / b) if x > 0 else 0.0,
              finv=lambda a, b, y: b * (y / a) ** 2,
              slope=lambda a, b, x: a / (2 * math.sqrt(b * x)) if x > 0 else math.inf),
    CurveSpec("ellipse", "x²/B² + y²/A² = 1, counter-clockwise", lambda a, b: (0, -b * b, 0, a * a, 0, 0),
              lambda a, b: (b, 0), lambda a, b: (END_Y, a),
              lambda a, b, x, y: (a * a * x * x + b * b * y * y - a * a * b * b,
                                  2.0 * a * a * x, 2.0 * b * b * y)),
    CurveSpec("circle", "x² + y² = A², counter-clockwise", lambda a, b: (0, -1, 0, 1, 0, 0),
              lambda a, b: (a, 0), lambda a, b: (END_Y, a),
              lambda a, b, x, y: (x * x + y * y - a * a, 2.0 * x, 2.0 * y)),
    CurveSpec("parabola", "y = A·(x/B)²", lambda a, b: (0, 0, b * b, 2 * a, 0, 0),
              lambda a, b: (0, 0), lambda a, b: (END_X, b),
              lambda a, b, x, y: (b * b * y - a * x * x, -2.0 * a * x, float(b * b))),
    CurveSpec("line", "B·y = A·x", lambda a, b: (0, 0, b, 0, 0, a),
              lambda a, b: (0, 0), lambda a, b: (END_X, b),
              lambda a, b, x, y: (b * y - a * x, float(-a), float(b))),
]}

# The paper's experiment: scalings (A, B) and its maximum errors in steps.
PAPER_SCALES = [(100, 10), (250, 50), (500, 100), (1000, 200)]
PAPER_CURVES = ["exponent", "logarithm", "hyperbola", "sqrt"]
PAPER_ERROR = {
    "exponent": [0.6513, 0.6589, 0.6612, 0.6712],
    "logarithm": [0.8419, 0.8501, 0.8516, 0.8621],
    "hyperbola": [0.5908, 0.5913, 0.6091, 0.6104],
    "sqrt": [0.4813, 0.4927, 0.5055, 0.5161],
}


def projections(spec: CurveSpec, a: int, b: int, x: int, y: int) -> tuple[int, int]:
    px, py, pc, qx, qy, qc = spec.coeffs(a, b)
    return px * x + py * y + pc, qx * x + qy * y + qc


def distance(spec: CurveSpec, a: int, b: int, x: float, y: float) -> float:
    """Distance of (x, y) from the curve, to first order (|F| / |grad F|)."""
    F, fx, fy = spec.residual(a, b, x, y)
    norm = math.hypot(fx, fy)
    return abs(F) / norm if norm else (0.0 if F == 0 else math.inf)


def program(spec: CurveSpec, a: int, b: int, x0: int | None = None, y0: int | None = None,
            end: tuple[int, int] | None = None, count: int | None = None,
            reverse: bool = False, improved: bool = False) -> Program:
    """The core's inputs for a curve; count is the budget when the end is a coordinate."""
    if x0 is None:
        x0, y0 = spec.start(a, b)
    px, py, pc, qx, qy, qc = spec.coeffs(a, b)
    p0, q0 = projections(spec, a, b, x0, y0)
    if count is not None and end is None:
        end_sel, end_coord = END_COUNT, 0
    else:
        end_sel, end_coord = end if end is not None else spec.end(a, b)
        if count is None:                          # budget: a path long enough to get there
            count = 4 * (abs(x0 - end_coord) + abs(y0 - end_coord)) + 64 \
                if end_sel else 0
    return Program(x0=x0, y0=y0, p0=p0, q0=q0, dp_dx=px, dp_dy=py, dq_dx=qx, dq_dy=qy,
                   count=count, end_sel=end_sel, end_coord=end_coord,
                   reverse=int(reverse), improved=int(improved))


def anchored_e(spec: CurveSpec, a: int, b: int, x: int, y: int, reverse: bool = False) -> int:
    """E for node (x, y) from the true curve: E = 2L·d + L − 2S (re-anchoring).

    d is the node's offset from the curve along the minor axis, counted positive
    in the direction the minor axis moves (first order: F / F_minor).
    """
    p, q = projections(spec, a, b, x, y)
    F, fx, fy = spec.residual(a, b, x, y)
    rev = -1 if reverse else 1
    if abs(p) >= abs(q):
        lng, sht, d = abs(p), abs(q), (F / fy if fy else 0.0) * rev * sign(q)
    else:
        lng, sht, d = abs(q), abs(p), (F / fx if fx else 0.0) * rev * sign(p)
    return round(2 * lng * d + lng - 2 * sht)


def paper_error(spec: CurveSpec, a: int, b: int, points) -> float:
    """Max error the paper's way: vertical where |slope| <= 1, horizontal beyond."""
    worst = 0.0
    for x, y in points:
        if spec.slope is not None:
            if abs(spec.slope(a, b, x)) <= 1:
                e = abs(y - spec.f(a, b, x))
            else:
                e = abs(x - spec.finv(a, b, y))
        else:
            e = distance(spec, a, b, x, y)
        worst = max(worst, e)
    return worst


def ideal_points(spec: CurveSpec, a: int, b: int, pts) -> list[tuple[float, float]]:
    """The true curve over the part the path covers, for plots."""
    n = 600
    if spec.f is not None or spec.name in ("parabola", "line"):
        xs = [p[0] for p in pts]
        lo, hi = min(xs), max(xs)
        if spec.name == "parabola":
            fx = lambda x: a * (x / b) ** 2        # noqa: E731
        elif spec.name == "line":
            fx = lambda x: a * x / b               # noqa: E731
        else:
            fx = lambda x: spec.f(a, b, x)         # noqa: E731
        out = [(lo + (hi - lo) * i / n, fx(lo + (hi - lo) * i / n)) for i in range(n + 1)]
        if spec.name in ("exponent", "logarithm", "sqrt", "hyperbola"):   # steep parts: sample in y
            ys = [p[1] for p in pts]
            ylo, yhi = min(ys), max(ys)
            out += [(spec.finv(a, b, ylo + (yhi - ylo) * i / n), ylo + (yhi - ylo) * i / n)
                    for i in range(n + 1)]
            out = sorted(o for o in out if math.isfinite(o[0]) and math.isfinite(o[1]))
        return out
    rx, ry = (a, a) if spec.name == "circle" else (b, a)
    return [(rx * math.cos(2 * math.pi * i / n), ry * math.sin(2 * math.pi * i / n)) for i in range(n + 1)]
