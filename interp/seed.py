"""Seeds for random tests: printed, and taken from $SEED when set (to re-run one)."""
import os
import random


def rng_for(log, test: str) -> random.Random:
    seed = int(os.environ.get("SEED", random.randrange(1 << 32)))
    log.info("%s seed=%d (re-run with SEED=%d)", test, seed, seed)
    return random.Random(seed)
