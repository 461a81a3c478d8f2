"""Shared machinery of Fig. 3 (static network) and Fig. 5 (plastic network): dead ends and long runs.

* Outcome table: every network (plastic from zero and from the paper's Fig. 4 start, static,
  Braitenberg) in the simple deadlock and in the narrow passage (default geometry, and gap and
  funnel angle changed by ±20%), ``seeds`` seeds each, 5000 control steps.
* Example runs (seed 0): the figure's network in both dead ends, with neural traces.
* Long runs in the original arenas (``cluttered``, ``difficult``): trajectories, trapping, coverage, and
  the periods the robot stayed wedged (:func:`neurowalk.metrics.wedged_periods`: its trunk centre within
  0.3 m for more than 100 s), with their causes.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import numpy as np

from neurowalk import metrics
from neurowalk.arenas import arena_options
from neurowalk.arenas.spec import WALL_HEIGHT
from neurowalk.experiments import Result
from neurowalk.experiments.stores import run_store, store_folder
from neurowalk.runners.local import run_many
from neurowalk.runners.specs import normalize, spec_key, to_config
from neurowalk.sim.config import DEFAULT_ENGINE
from neurowalk.sim.engines import engine_for
from neurowalk.sim.episode import EngineOptions, Episode, EpisodeConfig, RunInterruptedError, run_episode

NETWORKS: dict[str, dict[str, Any]] = {
    "plastic": {"controller": "plastic"},
    "plastic, start b=2.4 q=3.5": {"controller": "plastic", "b0": 2.4, "q0": 3.5},
    "static": {"controller": "static"},
    "braitenberg": {"controller": "braitenberg"},
}
_NP = arena_options("narrow-passage")
VARIANTS: dict[str, tuple[str, dict[str, float]]] = {
    "simple-deadlock": ("simple-deadlock", {}),
    "narrow-passage": ("narrow-passage", {}),
    **{
        f"narrow-passage {k} {sign}20%": ("narrow-passage", {k: round(_NP[k] * f, 6)})
        for k in ("gap", "funnel")
        for sign, f in (("-", 0.8), ("+", 1.2))
    },
}
TRAP_STEPS = 5000  # control steps in a dead end (paper: 5000 time steps)
LONG_STEPS, QUICK_LONG_STEPS = 30000, 10000  # control steps of the long runs in the original arenas
TRACES = ("pose", "inputs", "outputs", "b", "q")


def keep_traces(ep: Episode) -> dict[str, Any]:
    """Summary plus the traces a figure draws (pose, inputs, outputs, b, q)."""
    tr = ep.trajectory
    return {"summary": ep.summary, "pose": tr.pose, "inputs": tr.inputs, "outputs": tr.outputs, "b": tr.b, "q": tr.q}


def _episode(spec: dict[str, Any]) -> Episode:
    try:
        return run_episode(to_config(normalize(spec)))
    except RunInterruptedError:
        raise KeyboardInterrupt from None  # a half run is not a result


def outcome_of(spec: dict[str, Any]) -> dict[str, Any]:
    """:func:`keep_outcome` of the run of ``spec`` (what the result store keeps of a dead-end run)."""
    return keep_outcome(_episode(spec))


def traces_of(spec: dict[str, Any]) -> dict[str, Any]:
    """:func:`keep_traces` of the run of ``spec``, its arrays as lists (what the store keeps of an example run)."""
    return {k: v.tolist() if isinstance(v, np.ndarray) else v for k, v in keep_traces(_episode(spec)).items()}


def _spec(cfg: EpisodeConfig) -> dict[str, Any]:
    """The run spec of ``cfg`` (its fields; the store keys it after normalising)."""
    return {f.name: getattr(cfg, f.name) for f in dataclasses.fields(cfg)}


def stored_runs(
    configs: list[EpisodeConfig],
    folder: Path | None,
    name: str,
    workers: int,
    progress: bool,
    desc: str,
    traces: bool,
    device: str | None = None,
) -> list[dict[str, Any]]:
    """Outcomes (or, ``traces``, traces) of ``configs``: through the store ``folder/name`` (resumable), or, without a
    folder or on a many-worlds engine such as MuJoCo Warp (its runs are the worlds of one model, on ``device``), all
    at once."""
    if folder is None or any(engine_for(c).many_worlds for c in configs):
        keep = keep_traces if traces else keep_outcome
        options = EngineOptions(device=device)
        return run_many(configs, workers=workers, progress=progress, keep=keep, desc=desc, options=options)
    specs = [_spec(c) for c in configs]
    results, _ = run_store(specs, folder, workers, fn=traces_of if traces else outcome_of, name=name)
    want = "pose" if traces else "direction_switches"
    if any(want not in r for r in results.values()):
        raise RuntimeError(
            f"{folder / name} holds other runs than this figure's (another figure's or sweep's "
            "store); use a fresh output folder"
        )
    out = [results[spec_key(s)] for s in specs]
    if traces:
        out = [{**r, **{k: np.asarray(r[k], dtype=float) for k in TRACES}} for r in out]
    return out


def keep_outcome(ep: Episode) -> dict[str, Any]:
    """Outcome of a dead-end run: escaped, trapped, direction switches, turning episodes."""
    tr = ep.trajectory
    eps = metrics.avoidance_episodes(tr.outputs, tr.pose)
    return {
        "escaped": ep.summary["escaped"],
        "trapped": ep.summary["trapped"],
        "direction_switches": metrics.direction_switches(tr.outputs),
        "max_turn_deg": max((abs(e["turn_deg"]) for e in eps), default=0.0),
    }


def outcome_table(
    seeds: int,
    *,
    first_seed: int = 0,
    variants: dict | None = None,
    workers: int = 2,
    progress: bool = True,
    body: str = "amosii",
    climbing: bool = False,
    variant: str = "paper",
    gait: str = "wave",
    engine: str = DEFAULT_ENGINE,
    device: str | None = None,
    folder: Path | None = None,
) -> dict:
    """Escape counts per variant and network over seeds ``first_seed`` ... ``first_seed + seeds - 1``.

    ``climbing``: run with the leg reflexes and backbone control switched on. ``variant``: the networks'
    variant (``paper`` or ``original``; see :mod:`neurowalk.neural.variants`). ``engine``: ``mujoco`` or ``warp``
    (the runs as the worlds of one MuJoCo Warp model). ``folder``: the runs go through the resumable store
    ``folder/results.sqlite`` (default: all at once, nothing kept).

    ``runs`` lists every run as [variant, network, seed, escaped, trapped].
    """
    variants = variants or VARIANTS
    keys, configs = [], []
    for vname, (arena, opts) in variants.items():
        for nname, net in NETWORKS.items():
            for seed in range(first_seed, first_seed + seeds):
                keys.append((vname, nname))
                configs.append(
                    EpisodeConfig(
                        arena=arena,
                        arena_opts=opts,
                        steps=TRAP_STEPS,
                        seed=seed,
                        body=body,
                        reflexes=climbing,
                        backbone=climbing,
                        variant=variant,
                        gait=gait,
                        engine=engine,
                        **net,
                    )
                )
    results = stored_runs(
        configs, folder, "results.sqlite", workers, progress, f"dead ends ({body})", traces=False, device=device
    )
    table: dict[str, dict[str, dict[str, Any]]] = {}
    runs = []
    for (vname, nname), r, cfg in zip(keys, results, configs, strict=True):
        runs.append([vname, nname, cfg.seed, bool(r["escaped"]), bool(r["trapped"])])
        cell = table.setdefault(vname, {}).setdefault(nname, {"runs": 0, "escaped": 0, "trapped": 0, "switches": []})
        cell["runs"] += 1
        cell["escaped"] += int(bool(r["escaped"]))
        cell["trapped"] += int(r["trapped"])
        cell["switches"].append(r["direction_switches"])
    for row in table.values():
        for cell in row.values():
            cell["median_direction_switches"] = float(np.median(cell.pop("switches")))
    described = {k: {"arena": a, "options": o} for k, (a, o) in variants.items()}
    return {
        "seeds": seeds,
        "first_seed": first_seed,
        "steps": TRAP_STEPS,
        "body": body,
        "climbing": climbing,
        "variants": described,
        "network_variant": variant,
        "gait": gait,
        "engine": engine,
        "counts": table,
        "runs": runs,
        "rule": "escaped: the trunk centre reached the exit region behind the trap's mouth within the steps; "
        "trapped: the last 3000 steps stayed within a disc of radius 0.5 m",
    }


def example_and_long_runs(
    network: str,
    long_runs: dict[str, dict[str, Any]],
    long_steps: int,
    *,
    seed: int = 0,
    workers: int = 2,
    progress: bool = True,
    climbing: bool = False,
    variant: str = "paper",
    gait: str = "wave",
    engine: str = DEFAULT_ENGINE,
    device: str | None = None,
    folder: Path | None = None,
) -> dict[str, dict[str, Any]]:
    """Traces of ``network`` in both dead ends, and the long runs {name: config kwargs}, all with ``seed``.

    ``climbing``: leg reflexes and backbone control on; the original arenas' boxes are then raised to
    :data:`~neurowalk.arenas.spec.WALL_HEIGHT` (their 0.10 m boxes would be climbable steps). ``folder``: the runs
    go through the resumable store ``folder/traces.sqlite``.
    """
    net = {
        **NETWORKS[network],
        "reflexes": climbing,
        "backbone": climbing,
        "variant": variant,
        "gait": gait,
        "engine": engine,
    }
    runs = {
        "simple-deadlock": EpisodeConfig(arena="simple-deadlock", steps=TRAP_STEPS, seed=seed, **net),
        "narrow-passage": EpisodeConfig(arena="narrow-passage", steps=TRAP_STEPS, seed=seed, **net),
    }
    for k, v in long_runs.items():
        opts = {"height": WALL_HEIGHT} if climbing else {}
        runs[k] = EpisodeConfig(
            steps=long_steps,
            seed=seed,
            arena_opts=opts,
            reflexes=climbing,
            backbone=climbing,
            variant=variant,
            gait=gait,
            engine=engine,
            **v,
        )
    out = stored_runs(
        list(runs.values()), folder, "traces.sqlite", workers, progress, "example runs", traces=True, device=device
    )
    return dict(zip(runs, out, strict=True))


def build(
    name: str,
    network: str,
    long_runs: dict,
    *,
    quick: bool,
    seed: int,
    seeds: int | None,
    climbing: bool = False,
    variant: str = "paper",
    gait: str = "wave",
    engine: str = DEFAULT_ENGINE,
    device: str | None = None,
    out: Path | None = None,
) -> Result:
    """Shared by Fig. 3 and Fig. 5: outcome table, example runs, long runs (``climbing``: modules of Fig. 10 on).

    ``variant``: every network runs as this variant (``paper`` or ``original``). ``engine``: mujoco or warp.
    ``out``: the runs go through resumable stores there (``results.sqlite``: the outcome table, ``traces.sqlite``:
    the example and long runs), so that an interrupted figure goes on from its finished runs.
    """
    n_seeds = seeds if seeds is not None else (3 if quick else 10)
    if n_seeds < 1:
        raise ValueError(f"seeds must be >= 1, got {n_seeds}")
    long_steps = QUICK_LONG_STEPS if quick else LONG_STEPS
    with store_folder(out) as folder:
        table = outcome_table(
            n_seeds,
            first_seed=seed,
            climbing=climbing,
            variant=variant,
            gait=gait,
            engine=engine,
            device=device,
            folder=folder,
        )
        runs = example_and_long_runs(
            network,
            long_runs,
            long_steps,
            seed=seed,
            climbing=climbing,
            variant=variant,
            gait=gait,
            engine=engine,
            device=device,
            folder=folder,
        )
    arrays = {f"{k}/{field}": v[field] for k, v in runs.items() for field in TRACES}
    summary = {
        "network": network,
        "variant": variant,
        "gait": gait,
        "engine": engine,
        "seed": seed,
        "climbing": climbing,
        "table": table,
        "long_steps": long_steps,
        "runs": {k: v["summary"] for k, v in runs.items()},
        "wedged": wedged_counts({k: runs[k]["summary"] for k in long_runs}),
    }
    return Result(name, summary, arrays)


def wedged_counts(summaries: dict[str, dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """Per long run: number of wedged periods, the longest (s), counts by cause, and time wedged in all (s)."""
    return {
        k: {
            "periods": s["wedged_periods"],
            "longest_s": s["longest_wedged_s"],
            "causes": s["wedged_causes"],
            "total_s": float(sum(p["duration_s"] for p in s["wedged"])),
            "rule": f"trunk centre within {metrics.WEDGE_RADIUS} m of its mean for more than {metrics.WEDGE_MIN_S:g} s",
        }
        for k, s in summaries.items()
    }
