"""Paper figures and tables, and the studies behind them.

* :mod:`.study`: :class:`Study` (an experiment: its runs, measure, picture and claims), :class:`Settings` and
  :func:`~neurowalk.experiments.study.run_study`, the one runner.
* :mod:`.stores`: the one run function (:func:`~neurowalk.experiments.study_runs.run_kept`) and the one result store
  a study's runs are kept in, with the :class:`~neurowalk.experiments.study_runs.Term` s a run keeps beside its summary.
* :mod:`.figures`: one module per paper figure or table, declared as a study: ``runs(settings)`` (each run a
  :class:`Plan`: its label, config and the terms it keeps), ``measure(settings, runs)`` (numbers only), ``plot(result)``
  and ``claims(summary, quick)`` (its results judged against the paper); ``fig2``, the network alone, plans no run.
* :mod:`.suites`: the runs and terms figures share (dead ends, random environments, climbing, the real-robot runs).
* :mod:`.optimize`, :mod:`.calibration`, :mod:`.baselines`: the studies of ``neurowalk optimize``, ``calibrate``
  and ``baseline``.
* :mod:`.output` writes a figure's numbers and picture; :mod:`.cma_record` keeps a CMA-ES search (optimize and the
  evolved baseline).

Where a setting comes from: the command line's flags make one frozen :class:`Settings`; a study takes the optional
ones it names (its line below); the runner applies the run settings to every config a study's ``runs`` gives
(:meth:`Settings.apply`: body, climbing, variant, params, gait, engine, control rate), but those a run fixes
itself; ``runs`` and ``measure`` read the others (seeds, size, quick, seed).

:data:`FIGURES` maps a figure name to its :class:`~neurowalk.experiments.study.Study`; the CLI, the tests and
batch runs look them up there. It is a table written out below, each figure with the settings it takes: a figure's
module is imported when one of its functions is first used, so listing the figures imports none of them. A
:class:`Result` holds a JSON-able summary (the numbers behind the picture) and named arrays, which
:func:`~neurowalk.experiments.output.save_data` writes next to the PNG so that a figure can be redrawn without
rerunning.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from neurowalk.experiments.study import Plan, Result, Settings, Study

__all__ = ["FIGURES", "FunctionAt", "Plan", "Result", "Settings", "Study"]


@dataclass(frozen=True)
class FunctionAt:
    """Function ``name`` of module ``module`` (a dotted path), imported when it is first called."""

    module: str
    name: str

    def load(self) -> Callable[..., Any]:
        """The function (its module imported now if it was not)."""
        return getattr(importlib.import_module(self.module), self.name)

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return self.load()(*args, **kwargs)


def _study(
    name: str, title: str, takes: str = "", body: str | None = None, outputs: str = "", module: str | None = None
) -> Study:
    """Study ``name`` declared by :mod:`neurowalk.experiments.figures`.``module``'s (default: ``name``'s) ``runs``,
    ``measure`` and ``plot`` (as a user's study file declares them), run by
    :func:`~neurowalk.experiments.study.run_study`, and judged by its ``claims``; ``takes``: the optional settings it
    honours, ``outputs``: its ``render`` and ``videos`` where it has them (space-separated lists)."""
    path = f"{__name__}.figures.{module or name}"
    at = {part: FunctionAt(path, part) for part in ("runs", "measure", "plot", "claims", *outputs.split())}
    return Study(name, title, takes=takes.split(), body=body, records_physics=True, **at)  # type: ignore[arg-type]


PHYSICS = "seeds climbing variant gait engine control_hz"  # fig3 and fig5

FIGURES: dict[str, Study] = {
    "table1": _study(
        "table1",
        "walking direction for each sign of the outputs O1, O2, and speed (paper Table 1)",
        "control_hz",
    ),
    "fig2": _study("fig2", "fixed points and hysteresis of the sensory network"),
    "fig3": _study("fig3", "static network: dead ends, hysteresis, cluttered and difficult arenas", PHYSICS),
    "fig4": _study("fig4", "weight changes for constant and changing inputs", "variant params control_hz"),
    "fig5": _study("fig5", "plastic network: dead ends, weight dynamics, the difficult arena", PHYSICS),
    "fig6": _study(
        "fig6",
        "sixteen random environments: trajectories, start and end, failures marked (paper Fig. 6)",
        "body workers size variant params control_hz",
        body="surrogate",
    ),
    "fig7": _study(
        "fig7",
        "joint angles of all legs: forward, backward, turn right, turn left (physics)",
        "control_hz",
    ),
    "fig8": _study(
        "fig8",
        "narrow passage: snapshots, paths and escapes of the plastic and static networks (paper Fig. 8)",
        "seeds workers video variant params control_hz",
        outputs="render videos",
    ),
    "fig9": _study(
        "fig9",
        "complex path: snapshots, paths and outcome map of the plastic and static networks (paper Fig. 9)",
        "seeds workers video variant params control_hz",
        outputs="render videos",
    ),
    "fig10": _study(
        "fig10",
        "climbing track: climb a step, avoid a wall, climb a second step (paper Fig. 10)",
        "seeds workers variant control_hz",
        outputs="render",
    ),
    "table2": _study(
        "table2",
        "random environments: success and failure counts per network (paper Table 2)",
        "seeds body workers climbing size variant params engine control_hz",
        body="surrogate",
    ),
    "escape-map": _study(
        "escape-map",
        "escape rate against trap size for all three networks",
        "seeds climbing variant gait workers control_hz",
        module="escape_map",
    ),
    "sensitivity": _study(
        "sensitivity",
        "the dead ends' and the climbing track's outcomes with their invented dimension at 0.8, 1.0, 1.2 x",
        "seeds workers variant control_hz",
    ),
    "latched-spin": _study(
        "latched-spin",
        "the plastic network's failure in Table 2: a latched spin in a pocket (surrogate)",
        "variant params workers",
        module="latched",
    ),
    "ablation": _study(
        "ablation",
        "the authors' code's options one at a time, and success against run length, on Table 2's environments",
        "seeds workers",
    ),
    "steps": _study(
        "steps",
        "step-height sweep: highest step climbed, with and without backbone control and reflexes",
        "seeds workers control_hz",
    ),
    "bodies": _study(
        "bodies",
        "the networks on other robots: dead ends and Table 2 on AMOSII and a wheeled robot at two sizes",
        "seeds workers control_hz",
    ),
    "surrogate": _study(
        "surrogate",
        "planar surrogate vs physics: held-out calibration and dead-end outcomes",
        "seeds",
        module="surrogate_check",
    ),
}
