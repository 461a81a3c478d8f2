"""Random environments of Table 2 and Fig. 6 (2-20 boxes): the environments, run specs and success rule.

Environment i of a table (seed S) is the ``random`` arena with ``n_boxes`` drawn uniformly from 2-20
by a Generator of (S, i), laid out by run seed S + i; every network walks the same environments with
the same seeds. Success rule (also written into the json): the run never stayed within a disc of
0.5 m radius for 3000 control steps (300 s) in a row, anywhere in the run (``ever_trapped`` false).
Table 2 runs through the sweep engine into ``DIR/results.sqlite``, so a killed table resumes where it
stopped; runs on the planar surrogate by default, on physics with ``--body amosii``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

NETWORKS: tuple[str, ...] = ("plastic", "static", "braitenberg")
BOXES = (2, 20)  # inclusive range of the number of boxes (paper: 2 to 20)
STEPS = 20_000  # control steps per run (2000 s)
QUICK_STEPS = 5_000
RULE = ("success: the robot never stayed within a disc of radius 0.5 m for 3000 consecutive control steps "
        "(300 s) anywhere in the run; failure otherwise")  # fmt: skip


def environments(n: int, seed: int) -> list[dict[str, Any]]:
    """The first ``n`` environments of table seed ``seed``: [{'seed': run seed, 'n_boxes': boxes}, ...]."""
    out = []
    for i in range(n):
        rng = np.random.default_rng(np.random.SeedSequence([seed, i]))
        out.append({"seed": seed + i, "n_boxes": int(rng.integers(BOXES[0], BOXES[1] + 1))})
    return out


def spec(env: dict[str, Any], controller: str, steps: int, body: str) -> dict[str, Any]:
    """The run spec of one network in one environment."""
    return {"arena": "random", "arena_opts": {"n_boxes": env["n_boxes"]}, "controller": controller,
            "body": body, "steps": steps, "seed": env["seed"]}  # fmt: skip


def wilson(successes: int, n: int, z: float = 1.959964) -> tuple[float, float]:
    """Wilson score 95% interval of a success rate (``z`` = 1.96)."""
    if n == 0:
        return (0.0, 1.0)
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return (max(0.0, centre - half), min(1.0, centre + half))
