"""Fig. 5: the plastic network in dead ends and in the difficult arena.

A. Simple deadlock and B. narrow passage: escaped, by a long turn in one direction once the
weights have grown. C. Neural activations and weights in the narrow passage. D-E. Input against
output, coloured by time: switching between hysteresis and single-attractor states. F. The
difficult arena: plastic explores. G. Its weights over time. The json compares it with static and
Braitenberg over the same number of steps (trapping, coverage) and holds the escape counts of every
network over ``--seeds`` seeds and ±20% geometry changes, the plastic network started from zero (as
in the paper's exploration experiment) and from b = 2.4, q = 3.5 (its Fig. 4 start).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from neurowalk.experiments import Result
from neurowalk.experiments.suites.deadends import build
from neurowalk.experiments.suites.deadends_plot import plot as draw
from neurowalk.sim.config import DEFAULT_ENGINE

if TYPE_CHECKING:
    from matplotlib.figure import Figure

NAME = "fig5"
NETWORK = "plastic"
LONG = {
    "difficult (plastic)": {"arena": "difficult", "controller": "plastic"},
    "difficult (static)": {"arena": "difficult", "controller": "static"},
    "difficult (braitenberg)": {"arena": "difficult", "controller": "braitenberg"},
}


def run(
    *,
    quick: bool = False,
    seed: int = 0,
    seeds: int | None = None,
    climbing: bool = False,
    variant: str = "paper",
    gait: str = "wave",
    engine: str = DEFAULT_ENGINE,
    device: str | None = None,
    out: Path | None = None,
) -> Result:
    """Outcome table over ``seeds`` seeds (default 10; 3 with ``quick``), example and long runs.

    ``climbing``: with the leg reflexes and backbone control of Fig. 10 switched on. ``variant``: the networks'
    variant (``paper`` or ``original``). ``gait``: the locomotion network's gait (``wave`` by default). ``engine``:
    ``mujoco`` (default) or ``warp`` (MuJoCo Warp, the runs as worlds of one model). ``out``: the folder of the
    resumable result stores (``results.sqlite``, ``traces.sqlite``): a rerun goes on from the runs they hold.
    """
    res = build(
        NAME,
        NETWORK,
        LONG,
        quick=quick,
        seed=seed,
        seeds=seeds,
        climbing=climbing,
        variant=variant,
        gait=gait,
        engine=engine,
        device=device,
        out=out,
    )
    runs = res.summary["runs"]
    p, s = runs["difficult (plastic)"], runs["difficult (static)"]
    res.summary["difficult_comparison"] = {
        "plastic_trapped": p["trapped"],
        "static_trapped": s["trapped"],
        "braitenberg_trapped": runs["difficult (braitenberg)"]["trapped"],
        "plastic_coverage": p["coverage"],
        "static_coverage": s["coverage"],
        "braitenberg_coverage": runs["difficult (braitenberg)"]["coverage"],
        "plastic_covers_more": p["coverage"] > s["coverage"],
    }
    return res


def plot(res: Result) -> Figure:
    """Panels A-G; the counts table printed below."""
    return draw(res, NETWORK, list(LONG), weights_panel=True)
