"""Random environments of Table 2 and Fig. 6 (2-20 boxes): the environments, run specs and success rule.

Environment i of a table (seed S) is the ``random`` arena (9 x 9 m inside walls and 1 x 1 m boxes, the
sizes of the authors' simulated arenas; ``size`` changes the boxes) with ``n_boxes`` drawn uniformly
from 2-20 by a Generator of (S, i), laid out by run seed S + i, at a random position and rotation,
the robot's start cleared; every network walks the same environments with the same seeds.
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
#: The rows of Table 2: name -> (controller, variant). ``plastic-tuned`` joins where the tuned variant is shipped.
ROWS: dict[str, tuple[str, str]] = {
    "plastic-paper": ("plastic", "paper"),
    "plastic-original": ("plastic", "original"),
    "static": ("static", "paper"),
    "braitenberg": ("braitenberg", "paper"),
}
BOXES = (2, 20)  # inclusive range of the number of boxes (paper: 2 to 20)
EXTENT = 9.0  # m, side of the walled field (the original's arena is 9 x 9 m)
SIZE = 1.0  # m, side of each box (the authors' arenas use 1 x 1 m boxes)
STEPS = 20_000  # control steps per run (2000 s)
QUICK_STEPS = 5_000
RULE = (
    "success: at the end of the run the robot is not stuck: its last 3000 control steps (300 s) did not "
    "stay within a disc of radius 0.5 m; failure otherwise"
)


def environments(n: int, seed: int) -> list[dict[str, Any]]:
    """The first ``n`` environments of table seed ``seed``: [{'seed': run seed, 'n_boxes': boxes}, ...]."""
    out = []
    for i in range(n):
        rng = np.random.default_rng(np.random.SeedSequence([seed, i]))
        out.append({"seed": seed + i, "n_boxes": int(rng.integers(BOXES[0], BOXES[1] + 1))})
    return out


FAILURE_RULE = (
    "failure classes (runs stuck at the end): 'latched spin' where the steering commanded a turn in one "
    "direction for >= 80% of the last 3000 steps; else 'wedged' where both ultrasonic rays were blind (no "
    "echo nearer than 0.38 m) for >= 50% of them; else 'other'"
)
LATCHED, BLIND = 0.8, 0.5


def spec(
    env: dict[str, Any],
    controller: str,
    steps: int,
    body: str,
    climbing: bool = False,
    *,
    variant: str = "paper",
    size: float = SIZE,
    params: dict[str, float] | None = None,
) -> dict[str, Any]:
    """The run spec of one network in one environment (``climbing``: leg reflexes and backbone control on)."""
    opts = {"n_boxes": env["n_boxes"], "extent": EXTENT, "size": size}
    out: dict[str, Any] = {
        "arena": "random",
        "arena_opts": opts,
        "controller": controller,
        "body": body,
        "steps": steps,
        "seed": env["seed"],
    }
    if variant != "paper":
        out["variant"] = variant
    if params:
        out["params"] = dict(params)
    return {**out, "reflexes": True, "backbone": True} if climbing else out


def failure_class(summary: dict[str, Any]) -> str | None:
    """None for a success; else 'latched spin', 'wedged' or 'other' by :data:`FAILURE_RULE`."""
    if not summary["trapped"]:
        return None
    if summary["end_turn_share"] >= LATCHED:
        return "latched spin"
    return "wedged" if summary["end_blind_share"] >= BLIND else "other"


def wilson(successes: int, n: int, z: float = 1.959964) -> tuple[float, float]:
    """Wilson score 95% interval of a success rate (``z`` = 1.96)."""
    if n == 0:
        return (0.0, 1.0)
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return (max(0.0, centre - half), min(1.0, centre + half))
