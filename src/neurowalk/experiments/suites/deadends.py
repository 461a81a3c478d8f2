"""The dead ends of Fig. 3 (static network) and Fig. 5 (plastic network), and the build both figures share.

* Outcome table: every network (plastic from zero and from the paper's Fig. 4 start, static,
  Braitenberg) in the simple deadlock and in the narrow passage (default geometry, and gap and
  funnel angle changed by ±20%), ``seeds`` seeds each, 5000 control steps.
* Example runs (seed 0): the figure's network in both dead ends, with neural traces.
* :func:`stored_runs`: a figure's runs (outcomes, traces, long runs) through its resumable stores.
* :func:`build`: the outcome table, the example runs and the long runs in the original arenas (how those are run
  and kept, and what the paper's "time steps" are: :mod:`.long_runs`).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import numpy as np

from neurowalk import metrics
from neurowalk.arenas import arena_options
from neurowalk.arenas.spec import WALL_HEIGHT
from neurowalk.experiments import Result, Settings
from neurowalk.experiments.stores import as_lists, run_store, store_folder
from neurowalk.experiments.suites.long_runs import (
    LONG_STRIDE,
    LONG_TRACES,
    QUICK_LONG_STEPS,
    TRACES,
    coverage_table,
    keep_long_traces,
    long_traces_of,
    time_step_reading,
    wedged_counts,
)
from neurowalk.experiments.suites.timing import SIM_HZ
from neurowalk.runners.local import run_many
from neurowalk.runners.specs import episode_of, spec_key
from neurowalk.sim.config import DEFAULT_ENGINE, UNTIL
from neurowalk.sim.engines import engine_for
from neurowalk.sim.episode import EngineOptions, Episode, EpisodeConfig

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
QUICK_VARIANTS = ("simple-deadlock", "narrow-passage")  # --quick: the default geometries only
QUICK_SEEDS = 1  # --quick: seeds per cell of the outcome table (unless --seeds is given)
PAPER_TRAP_TIME_STEPS = 5000  # the paper's dead-end runs (Fig. 3, 5: "5000 time steps")
TRAP_STEPS = PAPER_TRAP_TIME_STEPS  # control steps in a dead end (the paper's time steps read as control steps)


def keep_traces(ep: Episode) -> dict[str, Any]:
    """Summary plus the traces a figure draws (pose, inputs, outputs, b, q)."""
    tr = ep.trajectory
    return {"summary": ep.summary, "pose": tr.pose, "inputs": tr.inputs, "outputs": tr.outputs, "b": tr.b, "q": tr.q}


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


def outcome_of(spec: dict[str, Any]) -> dict[str, Any]:
    """:func:`keep_outcome` of the run of ``spec`` (what the result store keeps of a dead-end run)."""
    return keep_outcome(episode_of(spec))


def traces_of(spec: dict[str, Any]) -> dict[str, Any]:
    """:func:`keep_traces` of the run of ``spec``, its arrays as lists (what the store keeps of an example run)."""
    return as_lists(keep_traces(episode_of(spec)))


def _spec(cfg: EpisodeConfig) -> dict[str, Any]:
    """The run spec of ``cfg`` (its fields; the store keys it after normalising)."""
    return {f.name: getattr(cfg, f.name) for f in dataclasses.fields(cfg)}


_KEEP = {
    "outcome": (keep_outcome, outcome_of, "direction_switches", ()),
    "traces": (keep_traces, traces_of, "pose", TRACES),
    "long": (keep_long_traces, long_traces_of, "step", LONG_TRACES),
}


def stored_runs(
    configs: list[EpisodeConfig],
    folder: Path | None,
    name: str,
    workers: int,
    progress: bool,
    desc: str,
    traces: bool | str,
    device: str | None = None,
) -> list[dict[str, Any]]:
    """Outcomes (``traces`` False), traces (True) or streamed long-run traces (``"long"``) of ``configs``: through
    the store ``folder/name`` (resumable), or, without a folder or on a many-worlds engine such as MuJoCo Warp (its
    runs are the worlds of one model, on ``device``), all at once."""
    kind = "long" if traces == "long" else ("traces" if traces else "outcome")
    keep, fn, want, arrays = _KEEP[kind]
    if folder is None or any(engine_for(c).many_worlds for c in configs):
        options = EngineOptions(device=device)
        out = run_many(configs, workers=workers, progress=progress, keep=keep, desc=desc, options=options)
        return [{**r, **{k: np.asarray(r[k], dtype=float) for k in arrays if k != "step"}} for r in out]
    specs = [_spec(c) for c in configs]
    results, _ = run_store(specs, folder, workers, fn=fn, name=name)
    out = [results[spec_key(s)] for s in specs]
    if any(want not in r for r in out):
        raise RuntimeError(
            f"{folder / name} holds other runs than this figure's (another figure's or sweep's "
            "store, or an older version's); use a fresh output folder"
        )
    return [{**r, **{k: np.asarray(r[k], dtype=np.int64 if k == "step" else float) for k in arrays}} for r in out]


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
    control_hz: float = 10.0,
) -> dict:
    """Escape counts per variant and network over seeds ``first_seed`` ... ``first_seed + seeds - 1``.

    ``climbing``: run with the leg reflexes and backbone control switched on. ``variant``: the networks'
    variant (``paper`` or ``original``; see :mod:`neurowalk.neural.variants`). ``engine``: ``mujoco`` or ``warp``
    (the runs as the worlds of one MuJoCo Warp model). ``folder``: the runs go through the resumable store
    ``folder/results.sqlite`` (default: all at once, nothing kept). ``control_hz``: the control rate; every run
    keeps its :data:`TRAP_STEPS` control steps (``seconds`` in the table: steps / rate).

    ``runs`` lists every run as [variant, network, seed, escaped, trapped].
    """
    variants = variants or VARIANTS
    keys, configs = [], []
    for vname, (arena, opts) in variants.items():
        for nname, net in NETWORKS.items():
            for seed in range(first_seed, first_seed + seeds):
                keys.append((vname, nname))
                shared = _shared(seed, climbing, variant, gait, engine, control_hz)
                configs.append(
                    EpisodeConfig(
                        arena=arena, arena_opts=opts, steps=TRAP_STEPS, body=body, until="escaped", **shared, **net
                    )
                )
    results = stored_runs(
        configs, folder, "results.sqlite", workers, progress, f"dead ends ({body})", traces=False, device=device
    )
    table, runs = _count(keys, results, configs)
    described = {k: {"arena": a, "options": o} for k, (a, o) in variants.items()}
    return {
        "seeds": seeds,
        "first_seed": first_seed,
        "steps": TRAP_STEPS,
        "control_hz": control_hz,
        "seconds": TRAP_STEPS / control_hz,
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
        "stop_rule": UNTIL["escaped"] + "; a run that does not escape runs all its steps",
    }


def _shared(seed: int, climbing: bool, variant: str, gait: str, engine: str, control_hz: float) -> dict[str, Any]:
    """The config fields every run of a dead-end figure shares (``climbing``: leg reflexes and backbone control)."""
    return {
        "seed": seed,
        "control_hz": control_hz,
        "reflexes": climbing,
        "backbone": climbing,
        "variant": variant,
        "gait": gait,
        "engine": engine,
    }


def _count(
    keys: list[tuple[str, str]], results: list[dict[str, Any]], configs: list[EpisodeConfig]
) -> tuple[dict[str, dict[str, dict[str, Any]]], list[list[Any]]]:
    """The outcome table's cells {variant: {network: runs, escaped, trapped, median direction switches}} from the
    ``results`` of ``configs`` (their cells ``keys``), and every run as [variant, network, seed, escaped, trapped]."""
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
    return table, runs


def example_and_long_runs(
    network: str, long_runs: dict[str, dict[str, Any]], long_steps: int, s: Settings, folder: Path | None
) -> dict[str, dict[str, Any]]:
    """Traces of ``network`` in both dead ends, and the long runs {name: config kwargs}, all with seed ``s.seed``.

    The dead ends keep every row; the long runs are streamed and keep every :data:`LONG_STRIDE`-th row and the
    last (:class:`LongRunKeeper`). With ``s.climbing`` (leg reflexes and backbone control on) the original arenas'
    boxes are raised to :data:`~neurowalk.arenas.spec.WALL_HEIGHT` (their 0.10 m boxes would be climbable steps).
    ``folder``: the runs go through the resumable store ``folder/traces.sqlite``.
    """
    climbing, device = s.climbing, s.device
    common = _shared(s.seed, climbing, s.variant or "paper", s.gait or "wave", s.engine, s.control_hz or SIM_HZ)
    net = {**NETWORKS[network], **common}
    examples = {
        "simple-deadlock": EpisodeConfig(arena="simple-deadlock", steps=TRAP_STEPS, **net),
        "narrow-passage": EpisodeConfig(arena="narrow-passage", steps=TRAP_STEPS, **net),
    }
    opts = {"height": WALL_HEIGHT} if climbing else {}
    longs = {k: EpisodeConfig(steps=long_steps, arena_opts=opts, **common, **v) for k, v in long_runs.items()}
    ex = stored_runs(
        list(examples.values()), folder, "traces.sqlite", 2, True, "example runs", traces=True, device=device
    )
    lo = stored_runs(list(longs.values()), folder, "traces.sqlite", 2, True, "long runs", traces="long", device=device)
    return {**dict(zip(examples, ex, strict=True)), **dict(zip(longs, lo, strict=True))}


def build(
    name: str,
    network: str,
    long_runs: dict,
    s: Settings,
    *,
    long_steps: int,
    paper_time_steps: dict[str, int],
    mark_step: int | None = None,
) -> Result:
    """Shared by Fig. 3 and Fig. 5: outcome table, example runs, long runs, with the settings ``s``.

    ``long_steps``: control steps of the long runs (``s.quick``: :data:`QUICK_LONG_STEPS` when fewer);
    ``paper_time_steps``: the paper's counts behind them (for ``time_step_reading``); ``mark_step``: a step the
    figure marks on the long runs (Fig. 3: 7,000, the paper's 70,000 time steps). ``s.quick``: also only the
    :data:`QUICK_VARIANTS` and :data:`QUICK_SEEDS` seeds (default 10). Every run takes ``s``'s network variant,
    gait, engine, control rate (the runs keep their control steps; seconds follow the rate) and ``climbing`` (the
    modules of Fig. 10 on). ``s.out``: the runs go through resumable stores there (``results.sqlite``: the outcome
    table, ``traces.sqlite``: the example and long runs), so that an interrupted figure goes on from them.
    """
    quick, seed, climbing, engine = s.quick, s.seed, s.climbing, s.engine
    variant, gait, control_hz = s.variant or "paper", s.gait or "wave", s.control_hz or SIM_HZ
    full_steps = long_steps
    if quick:
        long_steps = min(long_steps, QUICK_LONG_STEPS)
    variants = {k: v for k, v in VARIANTS.items() if k in QUICK_VARIANTS} if quick else VARIANTS
    kw: dict[str, Any] = {"climbing": climbing, "variant": variant, "gait": gait, "engine": engine, "device": s.device}
    with store_folder(s.out) as folder:
        table = outcome_table(
            s.n(full=10, quick=QUICK_SEEDS),
            first_seed=seed,
            variants=variants,
            folder=folder,
            control_hz=control_hz,
            **kw,
        )
        runs = example_and_long_runs(network, long_runs, long_steps, s, folder)
    arrays = {
        f"{k}/{field}": v[field] for k, v in runs.items() for field in (LONG_TRACES if k in long_runs else TRACES)
    }
    long_summaries = {k: runs[k]["summary"] for k in long_runs}
    summary = {
        "network": network,
        "variant": variant,
        "gait": gait,
        "engine": engine,
        "seed": seed,
        "climbing": climbing,
        "quick": quick,
        "control_hz": control_hz,
        "time_step_reading": time_step_reading(
            paper_time_steps, long_steps, control_hz, paper_trap_steps=PAPER_TRAP_TIME_STEPS, trap_steps=TRAP_STEPS
        ),
        "table": table,
        **_long_steps(long_steps, full_steps, control_hz, {k: len(runs[k]["step"]) for k in long_runs}),
        "mark_step": mark_step if mark_step is not None and mark_step < long_steps else None,
        "runs": {k: v["summary"] for k, v in runs.items()},
        "coverage_over_time": {k: coverage_table(runs[k]["step"], runs[k]["coverage"]) for k in long_runs},
        "wedged": wedged_counts(long_summaries, control_hz=control_hz),
    }
    return Result(name, summary, arrays)


def _long_steps(long_steps: int, full_steps: int, control_hz: float, rows: dict[str, int]) -> dict[str, Any]:
    """The long runs' length (``long_steps`` control steps, ``full_steps`` without ``quick``) and the ``rows`` their
    arrays keep (every :data:`LONG_STRIDE`-th step and the last)."""
    return {
        "long_steps": long_steps,
        "long_s": long_steps / control_hz,
        "long_steps_full": full_steps,
        "long_rows": {
            "stride": LONG_STRIDE,
            "rule": f"the long runs' arrays (name/step, /pose, /inputs, /outputs, /b, /q, /coverage) hold every "
            f"{LONG_STRIDE}th control step from step 0, and the last step",
            "rows": rows,
        },
    }
