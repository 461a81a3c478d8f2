"""Fig. 3: the static network (b = 2.4, c = -3.5) in dead ends and in the original arenas.

A. Simple deadlock: escaped. B. Narrow passage (a gap between the end obstacles): trapped,
oscillating. C. Neural activations in the narrow passage. D-E. Input against output, coloured by
time: the hysteresis loops. F. The cluttered arena: explored without getting trapped. G. The
difficult arena (sharp corners, narrow passages): trapped. The json holds the escape counts of all
networks (Braitenberg beside static and plastic) over ``--seeds`` seeds and ±20% geometry changes.
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

NAME = "fig3"
NETWORK = "static"
LONG = {
    "cluttered (static)": {"arena": "cluttered", "controller": "static"},
    "difficult (static)": {"arena": "difficult", "controller": "static"},
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
    return build(
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


def plot(res: Result) -> Figure:
    """Panels A-G; the counts table printed below."""
    return draw(res, NETWORK, list(LONG))
