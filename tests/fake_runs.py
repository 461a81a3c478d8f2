"""A study's runs without running them: what it asks the runner for (:func:`planned`), and its measure of stand-in
runs of the right shape (:func:`fake_measure`), for tests of a figure's settings, numbers and picture."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from neurowalk.experiments import FIGURES, Plan, Result, Settings
from neurowalk.experiments.figures import ablation
from neurowalk.experiments.study import planned, resolve
from neurowalk.experiments.study_runs import Kept
from neurowalk.experiments.suites import long_runs
from neurowalk.sim.config import EpisodeConfig
from neurowalk.sim.run_summary import RunSummary


def plan(name: str, s: Settings) -> list[Plan]:
    """The runs figure ``name`` asks for with settings ``s``: each a Plan (its config with the settings applied)."""
    study = FIGURES[name]
    study.check(s)
    return planned(study, resolve(study, s))


def summary_of(cfg: EpisodeConfig, **over: Any) -> dict[str, Any]:
    """A run's summary of the right shape for ``cfg`` (it escaped, was not trapped; ``over`` sets any key)."""
    return {
        "arena": cfg.arena, "arena_opts": dict(cfg.arena_opts), "controller": cfg.controller, "body": cfg.body,
        "steps": cfg.steps, "seed": cfg.seed, "control_hz": cfg.control_hz, "escaped": True, "trapped": False,
        "exit_step": 10, "coverage": 0.1, "wedged_periods": 0, "longest_wedged_s": 0.0, "wedged_causes": {},
        "held_periods": 0, "longest_held_s": 0.0, "turning_periods": 0,
        "wedged": [], "direction_switches": 1, "max_turn_deg": 90.0, "final_pose": [0.0, 0.0, 0.0],
        "final_weights": None, "max_z_m": 0.1, "final_z_m": 0.1, "end_turn_share": 0.0, "end_blind_share": 0.0,
        "ever_trapped": False, "ever_held_up_1000s": False, "path_length_m": 1.0, "min_up_z": 1.0,
        "simulation_warnings": {}, **over,
    }  # fmt: skip


def kept_of(cfg: EpisodeConfig, names: list[str]) -> dict[str, Any]:
    """Stand-ins of what terms ``names`` keep of a run of ``cfg``."""
    n = cfg.steps
    traces = {"pose": np.zeros((n, 3)), "inputs": np.zeros((n, 2)), "outputs": np.zeros((n, 2)), "b": np.ones((n, 2)),
              "q": np.ones((n, 2))}  # fmt: skip
    out: dict[str, Any] = {}
    for name in names:
        if name == "long":
            step = long_runs.sample_steps(n, long_runs.LONG_STRIDE)
            m = len(step)
            out[name] = {"step": step, **{k: v[:m] for k, v in traces.items()}, "coverage": np.linspace(0, 0.1, m)}
        elif name == "traces":
            out[name] = traces
        elif name == "path":
            out[name] = {"path": np.zeros((max(2, n // 10), 2)), "seen_step": None}
        elif name == "example":
            out[name] = {"t": np.arange(n) / cfg.control_hz, "qpos": np.zeros((n, 26)), **traces}
        elif name == "run lengths":  # every length a long run keeps (ablation.keep_lengths), all successes
            lengths = sorted({*ablation.LENGTHS_S, *ablation.QUICK_LENGTHS_S})
            out[name] = {
                "lengths_s": lengths,
                "success": [True] * len(lengths),
                "success_coverage": [True] * len(lengths),
            }
        elif name == "latch":
            out[name] = {}  # what a run that does not end in a latched spin keeps
        else:
            raise KeyError(f"no stand-in for term {name!r}")
    return out


def fake_measure(
    name: str, s: Settings, summary: Callable[[EpisodeConfig], dict[str, Any]] = summary_of
) -> tuple[list[EpisodeConfig], Result]:
    """The configs figure ``name`` runs with ``s``, and its measure of stand-ins (``summary(config)`` each)."""
    runs = plan(name, s)
    grouped: dict[Any, list[Kept]] = {}
    for p in runs:
        kept = kept_of(p.config, [t.name for t in p.terms])
        grouped.setdefault(p.label, []).append(Kept(RunSummary.from_dict(summary(p.config)), kept, p))
    return [p.config for p in runs], FIGURES[name].measure(s, grouped)  # type: ignore[misc]


def dead_end_table(s: Settings, variants: dict[str, tuple[str, dict]]) -> dict[str, Any]:
    """The dead-end outcome table of ``variants`` with settings ``s``, its runs really run (in a temporary store)."""
    from neurowalk.experiments.study_runs import run_all
    from neurowalk.experiments.suites.deadends import table_counts, table_runs

    plans = list(table_runs(s, variants))
    runs = run_all([s.apply(p.config) for p in plans], workers=s.workers or 2, progress=False)
    grouped: dict[Any, list[Kept]] = {}
    for p, r in zip(plans, runs, strict=True):
        grouped.setdefault(p.label, []).append(r)
    return table_counts(s, grouped)
