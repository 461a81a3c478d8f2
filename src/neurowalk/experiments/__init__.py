"""Paper figures and tables, and the studies behind them.

* :mod:`.figures`: one module per paper figure or table, ``run(*, quick, seed, ...) -> Result`` and
  ``plot(result)``; :data:`FIGURES` below names them.
* :mod:`.suites`: the run suites figures and studies share (dead ends, random environments, climbing, the
  real-robot runs).
* :mod:`.optimize`, :mod:`.calibration`, :mod:`.baselines`: the studies of ``neurowalk optimize``, ``calibrate``
  and ``baseline``.
* :mod:`.output` writes a figure's numbers and picture; :mod:`.stores` keeps a figure's runs; :mod:`.cma_record`
  keeps a CMA-ES search (optimize and the evolved baseline).

:data:`FIGURES` maps a figure name to its :class:`Experiment`; the CLI, the tests and batch runs look them up
there. It is a table written out below: a figure's module is imported when its ``run`` or ``plot`` is first used,
so listing the figures imports none of them. A :class:`Result` holds a JSON-able summary (the numbers behind the
picture) and named arrays, which :func:`~neurowalk.experiments.output.save` writes next to the PNG so that a
figure can be redrawn without rerunning.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure


@dataclass
class Result:
    """Numbers behind a figure: ``summary`` goes to NAME.json, ``arrays`` to NAME.npz."""

    name: str
    summary: dict[str, Any]
    arrays: dict[str, np.ndarray] = field(default_factory=dict)


@dataclass(frozen=True)
class FunctionAt:
    """Function ``name`` of module ``module`` (a dotted path), imported when it is first called or inspected.

    ``inspect.signature`` and ``functools.wraps`` see the function itself (through ``__wrapped__``).
    """

    module: str
    name: str

    def load(self) -> Callable[..., Any]:
        """The function (its module imported now if it was not)."""
        return getattr(importlib.import_module(self.module), self.name)

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return self.load()(*args, **kwargs)

    @property
    def __wrapped__(self) -> Callable[..., Any]:
        return self.load()


@dataclass(frozen=True)
class Experiment:
    """A figure: how to compute it and how to draw it."""

    name: str
    title: str
    run: Callable[..., Result]  # run(*, quick: bool, seed: int) -> Result
    plot: Callable[[Result], Figure]


def _figure(name: str, title: str, module: str) -> Experiment:
    """Figure ``name``: ``run`` and ``plot`` of :mod:`neurowalk.experiments.figures`.``module``."""
    path = f"{__name__}.figures.{module}"
    return Experiment(name, title, FunctionAt(path, "run"), FunctionAt(path, "plot"))


FIGURES: dict[str, Experiment] = {
    "table1": _figure(
        "table1", "walking direction for each sign of the outputs O1, O2, and speed (paper Table 1)", "table1"
    ),
    "fig2": _figure("fig2", "fixed points and hysteresis of the sensory network", "fig2"),
    "fig3": _figure("fig3", "static network: dead ends, hysteresis, cluttered and difficult arenas", "fig3"),
    "fig4": _figure("fig4", "weight changes for constant and changing inputs", "fig4"),
    "fig5": _figure("fig5", "plastic network: dead ends, weight dynamics, the difficult arena", "fig5"),
    "fig6": _figure(
        "fig6", "sixteen random environments: trajectories, start and end, failures marked (paper Fig. 6)", "fig6"
    ),
    "fig7": _figure("fig7", "joint angles of all legs: forward, backward, turn right, turn left (physics)", "fig7"),
    "fig8": _figure(
        "fig8",
        "narrow passage: snapshots, paths and escapes of the plastic and static networks (paper Fig. 8)",
        "fig8",
    ),
    "fig9": _figure(
        "fig9",
        "complex path: snapshots, paths and outcome map of the plastic and static networks (paper Fig. 9)",
        "fig9",
    ),
    "fig10": _figure(
        "fig10", "climbing track: climb a step, avoid a wall, climb a second step (paper Fig. 10)", "fig10"
    ),
    "table2": _figure(
        "table2", "random environments: success and failure counts per network (paper Table 2)", "table2"
    ),
    "escape-map": _figure("escape-map", "escape rate against trap size for all three networks", "escape_map"),
    "latched-spin": _figure(
        "latched-spin",
        "the plastic network's failure in Table 2: a latched spin in a pocket (surrogate)",
        "latched",
    ),
    "steps": _figure(
        "steps", "step-height sweep: highest step climbed, with and without backbone control and reflexes", "steps"
    ),
    "bodies": _figure(
        "bodies",
        "the networks on other robots: dead ends and Table 2 on AMOSII and a wheeled robot at two sizes",
        "bodies",
    ),
    "surrogate": _figure(
        "surrogate", "planar surrogate vs physics: held-out calibration and dead-end outcomes", "surrogate_check"
    ),
}
