"""What a ``neurowalk optimize`` search is set to: its sizes, seeds, body and files, and their checks.

Shared by the search (:mod:`.search`) and its report (:mod:`.report`), which import this module and not each other
the other way round.

Sizes (:data:`FULL`, :data:`QUICK`): the full search, 8 candidates x 12 generations on 80 environments of 20000
steps (Table 2's run length) and 3 seeds per dead end, then 200 held-out environments: about 9000 runs, 20-35 min
on 2 shared cores. ``quick``: 6 x 5 candidates on 16 environments of 10000 steps, 50 held-out environments: about
a minute (at 5000 steps nearly every candidate succeeds everywhere, so the objective would be flat).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from neurowalk.sim.episode import MAX_STEPS

BODY = "surrogate"
TRAIN_SEED = 1000  # table seed of the training environments (run seeds 1000, 1001, ...)
HELDOUT_SEED = 0  # table seed of the held-out environments: Table 2's own (run seeds 0, 1, ...)
SIGMA0 = 0.2  # initial CMA-ES step size in the normalised space (the bounds are 1 apart)
STATE_FILE = "cmaes.json"
OLD_STATE_FILE = "cmaes.pkl"  # older versions' pickled state: never read
CMA_MISSING = "neurowalk optimize needs the cma package: `pip install -e '.[optimize]'` in neurowalk's folder"


@dataclass(frozen=True)
class Sizes:
    """How big a search is: candidates per generation, generations, environments, steps, dead-end seeds."""

    population: int  # candidates per generation (CMA-ES lambda)
    generations: int
    environments: int  # training environments per candidate
    heldout: int  # held-out environments per validated network
    steps: int  # control steps per environment run (10 Hz)
    deadend_seeds: int  # runs per dead-end geometry (seeds 0 ...)


FULL = Sizes(population=8, generations=12, environments=80, heldout=200, steps=20_000, deadend_seeds=3)
QUICK = Sizes(population=6, generations=5, environments=16, heldout=50, steps=10_000, deadend_seeds=2)


def check_sizes(s: Sizes) -> None:
    """Raise ValueError naming the first size out of range (population >= 2, the rest >= 1; steps <= MAX_STEPS)."""
    for name, v in asdict(s).items():
        lo = 2 if name == "population" else 1
        if isinstance(v, bool) or not isinstance(v, int | np.integer) or v < lo:
            raise ValueError(f"{name} must be a whole number >= {lo}, got {v!r}")
    if s.steps > MAX_STEPS:
        raise ValueError(f"steps must be at most {MAX_STEPS:,} (the longest run), got {s.steps!r}")


def check_seeds(seed: int, train_seed: int, heldout_seed: int, sizes: Sizes) -> None:
    """Seeds >= 0 (CMA-ES's < 2**32 - 1, run seeds < 2**63); training and held-out run seeds must not overlap."""
    for name, v in (("seed", seed), ("train_seed", train_seed), ("heldout_seed", heldout_seed)):
        if isinstance(v, bool) or not isinstance(v, int | np.integer) or v < 0:
            raise ValueError(f"{name} must be a whole number >= 0, got {v!r}")
    if seed >= 2**32 - 1:
        raise ValueError(f"seed must be below 2**32 - 1 (the CMA-ES random state), got {seed!r}")
    a, b = (train_seed, train_seed + sizes.environments), (heldout_seed, heldout_seed + sizes.heldout)
    for name, (first, stop) in (("train_seed", a), ("heldout_seed", b)):
        if stop > 2**63:
            raise ValueError(f"{name} {first} + its {stop - first} environments: run seeds must stay below 2**63")
    if a[0] < b[1] and b[0] < a[1]:
        raise ValueError(
            f"training run seeds {a[0]}-{a[1] - 1} overlap the held-out ones {b[0]}-{b[1] - 1}: "
            "choose a train seed and a held-out seed further apart"
        )
