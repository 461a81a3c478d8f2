"""Random environments of Table 2 and Fig. 6 (2-20 boxes): the environments, run specs and success rule.

Environment i of a table (seed S) is the ``random`` arena (9 x 9 m inside walls, the size of the
original simulator's arena; boxes 0.6 m) with ``n_boxes`` drawn uniformly from 2-20 by a Generator of
(S, i), laid out by run seed S + i; every network walks the same environments with the same seeds.
Success rule (also written into the json): at the end of the run the robot is not stuck, i.e. its
last 3000 control steps (300 s) did not stay within a disc of 0.5 m radius (``trapped`` false). A
robot that was held up for a while and got out counts as a success (the json also counts the runs
that were ever held up that long, ``ever_trapped``).
Table 2 runs through the sweep engine into ``DIR/results.sqlite``, so a killed table resumes where it
stopped; runs on the planar surrogate by default, on physics with ``--body amosii``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

NETWORKS: tuple[str, ...] = ("plastic", "static", "braitenberg")
BOXES = (2, 20)  # inclusive range of the number of boxes (paper: 2 to 20)
EXTENT = 9.0  # m, side of the walled field (the original's arena is 9 x 9 m)
SIZE = 0.6  # m, side of each box
STEPS = 20_000  # control steps per run (2000 s)
QUICK_STEPS = 5_000
RULE = ("success: at the end of the run the robot is not stuck: its last 3000 control steps (300 s) did not "
        "stay within a disc of radius 0.5 m; failure otherwise")  # fmt: skip


def environments(n: int, seed: int) -> list[dict[str, Any]]:
    """The first ``n`` environments of table seed ``seed``: [{'seed': run seed, 'n_boxes': boxes}, ...]."""
    out = []
    for i in range(n):
        rng = np.random.default_rng(np.random.SeedSequence([seed, i]))
        out.append({"seed": seed + i, "n_boxes": int(rng.integers(BOXES[0], BOXES[1] + 1))})
    return out


def spec(env: dict[str, Any], controller: str, steps: int, body: str, climbing: bool = False) -> dict[str, Any]:
    """The run spec of one network in one environment (``climbing``: leg reflexes and backbone control on)."""
    out = {"arena": "random", "arena_opts": {"n_boxes": env["n_boxes"], "extent": EXTENT, "size": SIZE},
           "controller": controller, "body": body, "steps": steps, "seed": env["seed"]}  # fmt: skip
    return {**out, "reflexes": True, "backbone": True} if climbing else out


def wilson(successes: int, n: int, z: float = 1.959964) -> tuple[float, float]:
    """Wilson score 95% interval of a success rate (``z`` = 1.96)."""
    if n == 0:
        return (0.0, 1.0)
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return (max(0.0, centre - half), min(1.0, centre + half))
