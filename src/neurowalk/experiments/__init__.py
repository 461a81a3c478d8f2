"""Paper figures and tables, one module each: ``run(quick, seed) -> Result`` and ``plot(result)``.

:data:`FIGURES` maps a figure name to its :class:`Experiment`; the CLI, the tests and batch runs
look them up there. A :class:`Result` holds a JSON-able summary (the numbers behind the picture)
and named arrays, which :func:`~neurowalk.experiments.output.save` writes next to the PNG so that a
figure can be redrawn without rerunning.
"""

from __future__ import annotations

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
class Experiment:
    """A registered figure: how to compute it and how to draw it."""

    name: str
    title: str
    run: Callable[..., Result]  # run(*, quick: bool, seed: int) -> Result
    plot: Callable[[Result], Figure]


FIGURES: dict[str, Experiment] = {}


def register(name: str, title: str) -> Callable[[Callable[..., Result]], Callable[..., Result]]:
    """Decorator for a module's ``run``; the module's ``plot`` is looked up by name at call time."""

    def deco(run: Callable[..., Result]) -> Callable[..., Result]:
        import sys

        module = sys.modules[run.__module__]
        FIGURES[name] = Experiment(name=name, title=title, run=run, plot=lambda r: module.plot(r))
        return run

    return deco


def _load() -> None:
    # Importing the modules fills the registry.
    from neurowalk.experiments.figures import (  # noqa: F401
        bodies,
        escape_map,
        fig2,
        fig3,
        fig4,
        fig5,
        fig6,
        fig7,
        fig8,
        fig9,
        fig10,
        latched,
        steps,
        surrogate_check,
        table2,
    )


_load()
