# SPDX-License-Identifier: Apache-2.0
"""Curve core: the paper's error table through the RTL (interp curve-error), three modes."""
from ..commands.curve_error import experiment
from ..models.curve import PAPER_SCALES


def tables(quick: bool):
    rows = experiment(scales=PAPER_SCALES[:2] if quick else PAPER_SCALES)
    header = ["curve", "A", "B", "paper", "literal", "improved", "re-anchor 8", "steps"]
    return [("curve_tangent: max error in steps, the paper's measure (RTL, Icarus)", header,
             [[r["curve"], r["a"], r["b"], r["paper_error"], r["literal"], r["improved"], r["reanchor"],
               r["literal_steps"]] for r in rows])]
