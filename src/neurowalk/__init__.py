"""neurowalk: adaptive neural control of the walking robot AMOSII (Grinke et al. 2015) on MuJoCo.

The public API, in one place::

    from neurowalk import EpisodeConfig, run_episode, run_all, plot_run, make_arena, make_body

    ep = run_episode(EpisodeConfig(arena="corner", steps=3000, seed=0))   # the paper's robot, the CPU loop
    print(ep.summary["escaped"], ep.summary["final_weights"])
    plot_run(ep).savefig("run.png")

Engines and bodies by name: :data:`ENGINES` (``mujoco``: the CPU loop; ``warp``: MuJoCo Warp), :data:`BODIES`
(``amosii``, ``surrogate``, ``wheeled``, ...), :class:`EngineOptions` (device, threads) and :class:`Streaming`
(where a long run's rows go). The names load on first use, so that the ``neurowalk`` command starts at once (and a
Ctrl-C while it starts is answered in one line, by the command, not by a traceback from deep inside an import).

The Gymnasium environments ``neurowalk/Explore-v0`` and ``neurowalk/ExplorePhysics-v0`` are registered by
``import neurowalk.envs`` (:mod:`neurowalk.envs`); ``import neurowalk`` has no side effect.
"""

from __future__ import annotations

import importlib

__version__ = "0.1.0"

_LAZY = {
    "ACTUATORS": "neurowalk.anatomy",
    "LEGS": "neurowalk.anatomy",
    "Controller": "neurowalk.controller",
    "FixedController": "neurowalk.controller",
    "NeuralController": "neurowalk.controller",
    "SensoryParams": "neurowalk.neural.sensory",
    "simulate": "neurowalk.neural.sensory",
    "Observation": "neurowalk.observation",
    "EpisodeConfig": "neurowalk.sim.config",
    "Episode": "neurowalk.sim.config",
    "run_episode": "neurowalk.sim.episode",
    "EngineOptions": "neurowalk.sim.engine_interface",
    "Streaming": "neurowalk.sim.engine_interface",
    "Engine": "neurowalk.sim.engine_interface",
    "ENGINES": "neurowalk.sim.engines",
    "engine_for": "neurowalk.sim.engines",
    "run_all": "neurowalk.experiments.study_runs",
    "plot_run": "neurowalk.plotting",
    "Study": "neurowalk.experiments.study",
    "Plan": "neurowalk.experiments.plan",
    "Settings": "neurowalk.experiments.study",
    "run_study": "neurowalk.experiments.study",
    "load_study": "neurowalk.experiments.study_check",
    "check_study": "neurowalk.experiments.study_check",
    "Term": "neurowalk.experiments.study_runs",
    "Kept": "neurowalk.experiments.study_runs",
    "RunSummary": "neurowalk.sim.run_summary",
    "make_arena": "neurowalk.arenas",
    "table2_environments": "neurowalk.sim.table2",
    "table2_config": "neurowalk.sim.table2",
    "ARENAS": "neurowalk.arenas",
    "make_body": "neurowalk.body.registry",
    "BODIES": "neurowalk.body.registry",
    "check_body": "neurowalk.body.check",
    "check_engine": "neurowalk.sim.check",
    "check_controller": "neurowalk.controller",
}


def __getattr__(name: str) -> object:
    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'neurowalk' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_LAZY})


__all__ = [  # noqa: RUF022 (grouped by what they are)
    "__version__",
    # running
    "EpisodeConfig",
    "Episode",
    "run_episode",
    "run_all",
    "plot_run",
    # experiments of many runs
    "Study",
    "Plan",
    "Settings",
    "run_study",
    "load_study",
    "check_study",
    "Term",
    "Kept",
    "RunSummary",
    # worlds, robots, engines
    "make_arena",
    "table2_environments",
    "table2_config",
    "ARENAS",
    "make_body",
    "BODIES",
    "check_body",
    "ENGINES",
    "Engine",
    "EngineOptions",
    "Streaming",
    "engine_for",
    "check_engine",
    # the networks
    "Controller",
    "FixedController",
    "NeuralController",
    "check_controller",
    "Observation",
    "SensoryParams",
    "simulate",
    "ACTUATORS",
    "LEGS",
]
