# SPDX-License-Identifier: Apache-2.0
"""The circular cores' half-step test (interp.models.lecture.within_half_step, the
integer form circle_setup computes) against its definition |sqrt(b) - sqrt(a)| <= 1/2."""
import math
from decimal import Decimal, localcontext

from interp.testing.seeds import seeded_random
from interp.models.lecture import within_half_step


def exact(a: int, b: int) -> bool:
    """The definition with 60-digit square roots (no integer pair sits exactly on 1/2)."""
    with localcontext() as ctx:
        ctx.prec = 60
        return abs(Decimal(b).sqrt() - Decimal(a).sqrt()) <= Decimal("0.5")


def test_every_small_pair():
    """Every a <= 120 against every b <= 250 (radii up to ~15.8)."""
    wrong = [(a, b) for a in range(121) for b in range(251) if within_half_step(a, b) != exact(a, b)]
    assert not wrong, f"{len(wrong)} pairs differ, first {wrong[:3]}"


def test_random_pairs_near_the_band_edges():
    """Random 62-bit pairs, most of them within a few units of the band's edges."""
    rng, seed = seeded_random()
    top = (1 << 62) - 1
    for _ in range(5000):
        a = rng.randint(0, top)
        r = math.isqrt(a)
        edge = (r + rng.choice([-1, 1]) * 0.5) ** 2
        b = min(top, max(0, int(edge) + rng.randint(-2, 2))) if rng.random() < 0.8 else rng.randint(0, top)
        assert within_half_step(a, b) == exact(a, b), f"a={a} b={b} (seed {seed})"
    for a, b in [(top, top), (top, 0), (0, top), (top, top - 1)]:
        assert within_half_step(a, b) == exact(a, b), f"a={a} b={b}"
