"""Shared machinery of Fig. 3 (static network) and Fig. 5 (plastic network): dead ends and long runs.

* Outcome table: every network (plastic from zero and from the paper's Fig. 4 start, static,
  Braitenberg) in the simple deadlock and in the narrow passage (default geometry, and gap and
  funnel angle changed by ±20%), ``seeds`` seeds each, 5000 control steps.
* Example runs (seed 0): the figure's network in both dead ends, with neural traces.
* Long runs in the original arenas (``cluttered``, ``difficult``), streamed (:class:`LongRunKeeper`): every
  :data:`LONG_STRIDE`-th row of the path, inputs, outputs and weights (and the last row), the coverage over time,
  trapping, and the periods the robot stayed wedged (:func:`neurowalk.metrics.wedged_periods`: its trunk centre
  within 0.3 m for more than 100 s), with their causes.

What the paper's "time steps" are
---------------------------------
The paper counts every run in "time steps": the dead ends 5000 (Fig. 3A-E, 5A-E), the long run of Fig. 3F/G
70,000 + 330,000 (the green dot of 3G at 70,000), and that of Fig. 5F/G 1,000,000. The authors' simulation
(LPZRobots, original_code_facts.md §1, S4) steps ODE every 0.01 s and calls the controller every
``controlinterval = 10`` physics steps: 100 physics steps and 10 control steps a second. The reading here:

* **Dead ends: control steps.** 5000 control steps are 500 s. As 5000 physics steps they would be 50 s, about
  0.6 m of the wave gait (the authors' own regression run walks 0.95 m in 100 s, §8), too short for Fig. 5B's
  "few turns to and fro" before the escape. The authors' logs of these runs (the network's ``outTezinhib.txt``,
  plotted over "timesteps" by ``hysteresis_plot_t_w.py``, and LPZRobots' track file, written by
  ``Agent::step``) have one row per control step.
* **Long runs: physics steps** (the simulator's step count, as in the group's regression test, which runs
  "10000 physics steps (100 s)", §8): :data:`PHYSICS_PER_CONTROL` = 10 of them make one control step. Fig. 5's
  1,000,000 are 100,000 control steps (10,000 s), Fig. 3's 70,000 + 330,000 are 7,000 + 33,000 control steps
  (4,000 s). Three things point this way. (1) The authors' weight-plotting script draws the weights over "timesteps"
  0 to 99,000 of the network's log, one row per control step: about the 100,000 control steps of a
  1,000,000-physics-step run, not 1,000,000 of them.
  (2) The walked path: at about 1.3 cm/s (this model's wave gait in the difficult arena) 100,000 control steps
  are about 125 m, enough to "explore the whole environment" of 9 x 9 m and still a readable line; 1,000,000
  control steps (28 h simulated) would be some 1,250 m, a solid blot, and Fig. 3F's "initial 70,000" red line
  (9 m here, against 90 m) would not stand apart from the gray. (3) The dead ends cannot be physics steps
  (above), so the paper's one word covers two counts either way: the logs' rows for the short runs drawn
  step by step, the simulator's count for the long ones.

The reading is a judgement: the paper never says which step it counts. The long runs keep their control steps
at any ``control_hz`` (as the dead ends do: the networks' learning and forgetting are per step); seconds are
steps / ``control_hz``. ``time_step_reading`` in the figures' json says all this in numbers.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import numpy as np

from neurowalk import metrics
from neurowalk.arenas import ArenaSpec, arena_options, make_arena
from neurowalk.arenas.spec import WALL_HEIGHT
from neurowalk.experiments import Result
from neurowalk.experiments.stores import run_store, store_folder
from neurowalk.runners.local import run_many
from neurowalk.runners.specs import normalize, spec_key, to_config
from neurowalk.sim.config import DEFAULT_ENGINE
from neurowalk.sim.engines import engine_for
from neurowalk.sim.episode import (
    EngineOptions,
    Episode,
    EpisodeConfig,
    RunInterruptedError,
    Streaming,
    run_episode,
)
from neurowalk.sim.trajectory import Trajectory

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
PHYSICS_PER_CONTROL = 10  # the authors' physics steps per control step (controlinterval 10, 0.01 s ODE steps)
QUICK_LONG_STEPS = 10_000  # control steps of a long run with --quick (1,000 s at 10 Hz)
LONG_STRIDE = 10  # a long run keeps every LONG_STRIDE-th row (1 s at 10 Hz) and its last one
LONG_CHUNK = 10_000  # rows a streamed long run holds at a time
WEDGED_LONG_S = 300.0  # wedged periods longer than this are counted apart ("over 300 s")
TRACES = ("pose", "inputs", "outputs", "b", "q")
LONG_TRACES = ("step", *TRACES, "coverage")  # a long run's arrays: rows at the steps `step`


def control_steps_of(paper_time_steps: int) -> int:
    """Control steps of a long run of the paper's ``paper_time_steps`` (physics steps; see the module's text)."""
    return paper_time_steps // PHYSICS_PER_CONTROL


def time_step_reading(paper: dict[str, int], long_steps: int, control_hz: float) -> dict[str, Any]:
    """The reading of the paper's "time steps" in numbers, for a figure's json.

    ``paper``: the figure's long-run counts as the paper gives them ({what: time steps}).
    """
    return {
        "dead_ends": f"the paper's {PAPER_TRAP_TIME_STEPS} time steps are control steps: {TRAP_STEPS} control "
        f"steps, {TRAP_STEPS / control_hz:g} s at {control_hz:g} Hz",
        "long_runs": "the paper's long-run time steps are physics steps of the authors' simulator (0.01 s, "
        f"{PHYSICS_PER_CONTROL} to a control step at 10 Hz): control steps = time steps / {PHYSICS_PER_CONTROL}",
        "paper_time_steps": paper,
        "control_steps": {k: control_steps_of(v) for k, v in paper.items()},
        "physics_per_control_step": PHYSICS_PER_CONTROL,
        "at_other_rates": "every run keeps its control steps (the networks' step semantics); seconds = steps / "
        "control_hz",
        "this_run_long_steps": long_steps,
        "this_run_long_s": long_steps / control_hz,
        "argument": "neurowalk.experiments.suites.deadends (module text)",
    }


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


class FirstVisits:
    """The first control step at which the trunk centre entered each free cell of an arena (coverage over time).

    The cells and the rule are :func:`neurowalk.metrics.coverage`'s (0.25 m cells of the free area): the curve's
    value at the last step is the run's ``coverage``. Feed rows in step order with :meth:`add`.
    """

    def __init__(self, arena: ArenaSpec, cell: float = 0.25) -> None:
        self.x0, _, self.y0, _ = arena.bounds if arena.bounds is not None else (0.0, 0.0, 0.0, 0.0)
        self.cell = cell
        free = arena.free_cells(cell) if arena.bounds is not None else np.zeros((0, 2))
        self.n_free = len(free)
        keys = np.floor((free - [self.x0, self.y0]) / cell).astype(np.int64)
        self.k0 = keys.min(axis=0) if len(keys) else np.zeros(2, dtype=np.int64)
        self.shape = (keys.max(axis=0) - self.k0 + 1) if len(keys) else np.zeros(2, dtype=np.int64)
        self.flat_free = (keys[:, 0] - self.k0[0]) * self.shape[1] + (keys[:, 1] - self.k0[1])
        self.first = np.full(int(np.prod(self.shape)), np.iinfo(np.int64).max, dtype=np.int64)

    def add(self, pose: np.ndarray, start: int) -> None:
        """Take the rows of steps ``start, start + 1, ...`` (``pose`` (n, >= 2), m)."""
        if self.n_free == 0 or len(pose) == 0:
            return
        with np.errstate(invalid="ignore"):
            fx = np.floor((np.asarray(pose[:, 0], dtype=np.float64) - self.x0) / self.cell) - self.k0[0]
            fy = np.floor((np.asarray(pose[:, 1], dtype=np.float64) - self.y0) / self.cell) - self.k0[1]
        ok = (fx >= 0) & (fx < self.shape[0]) & (fy >= 0) & (fy < self.shape[1])  # NaN: False
        rows = np.flatnonzero(ok)
        if len(rows) == 0:
            return
        flat = fx[rows].astype(np.int64) * self.shape[1] + fy[rows].astype(np.int64)
        cells, at = np.unique(flat, return_index=True)  # each cell's first row in these rows
        self.first[cells] = np.minimum(self.first[cells], start + rows[at])

    def curve(self, steps: np.ndarray) -> np.ndarray:
        """Coverage (share of the free cells visited) after each of ``steps`` (NaN: the arena has no free cells)."""
        steps = np.asarray(steps)
        if self.n_free == 0:
            return np.full(len(steps), np.nan)
        visits = np.sort(self.first[self.flat_free])
        return np.searchsorted(visits, steps, side="right") / self.n_free


def sample_steps(steps: int, stride: int) -> np.ndarray:
    """The steps a long run keeps: 0, stride, 2·stride, ... and the last (steps - 1)."""
    at = np.arange(0, steps, stride)
    return at if at[-1] == steps - 1 else np.append(at, steps - 1)


class LongRunKeeper:
    """The sink of a streamed long run (:class:`~neurowalk.sim.engine.Streaming`): what a figure keeps of it.

    Keeps every ``stride``-th row (and the last) of the path, inputs, outputs and weights, the first visit of every
    free cell (:class:`FirstVisits`), and the positions (qpos) of every step, from which the summary replays the
    obstacle contacts of its wedged periods (:meth:`qpos_rows`; the cause of each). Memory: 8·nq bytes a step
    (about 21 MB for 100,000 steps of AMOSII, nq = 26) plus one chunk of the run.
    """

    def __init__(self, cfg: EpisodeConfig, stride: int = LONG_STRIDE) -> None:
        self.steps, self.stride = cfg.steps, stride
        self.at = sample_steps(cfg.steps, stride)
        self.kept = {k: np.full((len(self.at), 3 if k == "pose" else 2), np.nan) for k in TRACES}
        self.visits = FirstVisits(make_arena(cfg.arena, **cfg.arena_opts))
        self.qpos: np.ndarray | None = None

    def __call__(self, rows: Trajectory, start: int) -> None:
        """Take the rows of steps ``start, start + 1, ...`` (valid during the call only: copied)."""
        n = len(rows)
        if self.qpos is None:
            self.qpos = np.full((self.steps, rows.qpos.shape[1]), np.nan)
        self.qpos[start : start + n] = rows.qpos
        lo, hi = np.searchsorted(self.at, [start, start + n])
        for k in TRACES:
            self.kept[k][lo:hi] = getattr(rows, k)[self.at[lo:hi] - start]
        self.visits.add(rows.pose, start)

    def qpos_rows(self, rows: np.ndarray) -> np.ndarray:
        """The positions of steps ``rows`` (the summary's replay of wedged periods)."""
        assert self.qpos is not None
        return self.qpos[rows]

    def traces(self, done: int) -> dict[str, np.ndarray]:
        """The kept rows of the first ``done`` steps: ``step`` (the rows' steps), the traces, ``coverage``."""
        n = int(np.searchsorted(self.at, done))
        at = self.at[:n]
        return {"step": at, **{k: v[:n] for k, v in self.kept.items()}, "coverage": self.visits.curve(at)}


def keep_long_traces(ep: Episode) -> dict[str, Any]:
    """:class:`LongRunKeeper`'s traces of a run held in memory (the many-worlds engines' path)."""
    keeper = LongRunKeeper(ep.config)
    keeper(ep.trajectory, 0)
    return {"summary": ep.summary, **keeper.traces(len(ep.trajectory))}


def _episode(spec: dict[str, Any]) -> Episode:
    try:
        return run_episode(to_config(normalize(spec)))
    except RunInterruptedError:
        raise KeyboardInterrupt from None  # a half run is not a result


def outcome_of(spec: dict[str, Any]) -> dict[str, Any]:
    """:func:`keep_outcome` of the run of ``spec`` (what the result store keeps of a dead-end run)."""
    return keep_outcome(_episode(spec))


def _lists(d: dict[str, Any]) -> dict[str, Any]:
    return {k: v.tolist() if isinstance(v, np.ndarray) else v for k, v in d.items()}


def traces_of(spec: dict[str, Any]) -> dict[str, Any]:
    """:func:`keep_traces` of the run of ``spec``, its arrays as lists (what the store keeps of an example run)."""
    return _lists(keep_traces(_episode(spec)))


def long_traces_of(spec: dict[str, Any]) -> dict[str, Any]:
    """The run of ``spec``, streamed (:class:`LongRunKeeper`): its summary and kept rows, arrays as lists."""
    cfg = to_config(normalize(spec))
    keeper = LongRunKeeper(cfg)
    stream = Streaming(sink=keeper, chunk=min(LONG_CHUNK, cfg.steps), keep_rows=False, picture_rows=1)
    try:
        ep = run_episode(cfg, stream=stream)
    except RunInterruptedError:
        raise KeyboardInterrupt from None  # a half run is not a result
    return _lists({"summary": ep.summary, **keeper.traces(cfg.steps)})


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
                configs.append(
                    EpisodeConfig(
                        arena=arena,
                        arena_opts=opts,
                        steps=TRAP_STEPS,
                        seed=seed,
                        body=body,
                        control_hz=control_hz,
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
    control_hz: float = 10.0,
) -> dict[str, dict[str, Any]]:
    """Traces of ``network`` in both dead ends, and the long runs {name: config kwargs}, all with ``seed``.

    The dead ends keep every row; the long runs are streamed and keep every :data:`LONG_STRIDE`-th row and the
    last (:class:`LongRunKeeper`). ``climbing``: leg reflexes and backbone control on; the original arenas' boxes
    are then raised to :data:`~neurowalk.arenas.spec.WALL_HEIGHT` (their 0.10 m boxes would be climbable steps).
    ``folder``: the runs go through the resumable store ``folder/traces.sqlite``.
    """
    common = {
        "seed": seed,
        "control_hz": control_hz,
        "reflexes": climbing,
        "backbone": climbing,
        "variant": variant,
        "gait": gait,
        "engine": engine,
    }
    net = {**NETWORKS[network], **common}
    examples = {
        "simple-deadlock": EpisodeConfig(arena="simple-deadlock", steps=TRAP_STEPS, **net),
        "narrow-passage": EpisodeConfig(arena="narrow-passage", steps=TRAP_STEPS, **net),
    }
    opts = {"height": WALL_HEIGHT} if climbing else {}
    longs = {k: EpisodeConfig(steps=long_steps, arena_opts=opts, **common, **v) for k, v in long_runs.items()}
    ex = stored_runs(
        list(examples.values()), folder, "traces.sqlite", workers, progress, "example runs", traces=True, device=device
    )
    lo = stored_runs(
        list(longs.values()), folder, "traces.sqlite", workers, progress, "long runs", traces="long", device=device
    )
    return {**dict(zip(examples, ex, strict=True)), **dict(zip(longs, lo, strict=True))}


def build(
    name: str,
    network: str,
    long_runs: dict,
    *,
    quick: bool,
    seed: int,
    seeds: int | None,
    long_steps: int,
    paper_time_steps: dict[str, int],
    mark_step: int | None = None,
    climbing: bool = False,
    variant: str = "paper",
    gait: str = "wave",
    engine: str = DEFAULT_ENGINE,
    device: str | None = None,
    out: Path | None = None,
    control_hz: float = 10.0,
) -> Result:
    """Shared by Fig. 3 and Fig. 5: outcome table, example runs, long runs (``climbing``: modules of Fig. 10 on).

    ``long_steps``: control steps of the long runs (``quick``: :data:`QUICK_LONG_STEPS` when fewer);
    ``paper_time_steps``: the paper's counts behind them (for ``time_step_reading``); ``mark_step``: a step the
    figure marks on the long runs (Fig. 3: 7,000, the paper's 70,000 time steps). ``quick``: also only the
    :data:`QUICK_VARIANTS` and :data:`QUICK_SEEDS` seeds (unless ``seeds``). ``variant``: every network runs as this
    variant (``paper`` or ``original``). ``engine``: mujoco or warp. ``control_hz``: every run's control rate (the
    runs keep their control steps; seconds follow the rate). ``out``: the runs go through resumable stores there
    (``results.sqlite``: the outcome table, ``traces.sqlite``: the example and long runs), so that an interrupted
    figure goes on from its finished runs.
    """
    n_seeds = seeds if seeds is not None else (QUICK_SEEDS if quick else 10)
    if n_seeds < 1:
        raise ValueError(f"seeds must be >= 1, got {n_seeds}")
    full_steps = long_steps
    if quick:
        long_steps = min(long_steps, QUICK_LONG_STEPS)
    variants = {k: v for k, v in VARIANTS.items() if k in QUICK_VARIANTS} if quick else VARIANTS
    with store_folder(out) as folder:
        table = outcome_table(
            n_seeds,
            first_seed=seed,
            variants=variants,
            climbing=climbing,
            variant=variant,
            gait=gait,
            engine=engine,
            device=device,
            folder=folder,
            control_hz=control_hz,
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
            control_hz=control_hz,
        )
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
        "time_step_reading": time_step_reading(paper_time_steps, long_steps, control_hz),
        "table": table,
        "long_steps": long_steps,
        "long_s": long_steps / control_hz,
        "long_steps_full": full_steps,
        "long_rows": {
            "stride": LONG_STRIDE,
            "rule": f"the long runs' arrays (name/step, /pose, /inputs, /outputs, /b, /q, /coverage) hold every "
            f"{LONG_STRIDE}th control step from step 0, and the last step",
            "rows": {k: len(runs[k]["step"]) for k in long_runs},
        },
        "mark_step": mark_step if mark_step is not None and mark_step < long_steps else None,
        "runs": {k: v["summary"] for k, v in runs.items()},
        "coverage_over_time": {k: coverage_table(runs[k]["step"], runs[k]["coverage"]) for k in long_runs},
        "wedged": wedged_counts(long_summaries, control_hz=control_hz),
    }
    return Result(name, summary, arrays)


def coverage_table(step: np.ndarray, coverage: np.ndarray, points: int = 10) -> dict[str, list]:
    """Coverage at ``points`` evenly spaced kept steps (the last included), for the json (the npz holds all)."""
    idx = np.unique(np.round(np.linspace(0, len(step) - 1, points + 1)).astype(int))
    return {"step": [int(s) for s in step[idx]], "coverage": [float(c) for c in coverage[idx]]}


def wedged_counts(summaries: dict[str, dict[str, Any]], control_hz: float = 10.0) -> dict[str, dict[str, Any]]:
    """Per long run: number of wedged periods, the longest (s), counts by cause, time wedged in all (s), those over
    :data:`WEDGED_LONG_S` (count and causes), and the list of periods (start step and s, duration, cause)."""
    out = {}
    for k, s in summaries.items():
        long = [p for p in s["wedged"] if p["duration_s"] > WEDGED_LONG_S]
        causes: dict[str, int] = {}
        for p in long:
            causes[p["cause"]] = causes.get(p["cause"], 0) + 1
        out[k] = {
            "periods": s["wedged_periods"],
            "longest_s": s["longest_wedged_s"],
            "causes": s["wedged_causes"],
            "total_s": float(sum(p["duration_s"] for p in s["wedged"])),
            f"over_{WEDGED_LONG_S:g}s": {"periods": len(long), "causes": causes},
            "list": [
                {
                    "start_step": int(p["start"]),
                    "start_s": float(p["start"]) / control_hz,
                    "duration_s": float(p["duration_s"]),
                    "cause": p["cause"],
                }
                for p in s["wedged"]
            ],
            "rule": f"trunk centre within {metrics.WEDGE_RADIUS} m of its mean for more than {metrics.WEDGE_MIN_S:g} s",
        }
    return out
