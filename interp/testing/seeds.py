# SPDX-License-Identifier: Apache-2.0
"""The random generator of every random test: its seed printed, SEED=... repeats a run."""
from __future__ import annotations

import os
import random
from typing import Callable


def seeded_random(name: str = "seed", log: Callable[[str], object] = print) -> tuple[random.Random, int]:
    """(generator, seed): the seed is SEED from the environment if set, else a fresh one; logged."""
    seed = int(os.environ.get("SEED", random.randrange(1 << 32)))
    log(f"{name} seed={seed} (re-run with SEED={seed})")
    return random.Random(seed), seed
