"""``neurowalk optimize``: CMA-ES over the sensory network's learning parameters, on the surrogate body.

The paper says the learning parameters "could be found by evolutionary algorithms"; this is that search.

* Candidates: SensoryParams fields (default ``mu_b, mu_q, gamma_b, gamma_q, k``) on top of a base variant
  (default ``original``), searched in a normalised space (log scale for the rates; see :mod:`.space`).
* Objective: Table 2 success rate on training environments (the Table 2 generator, 1 m boxes, table seed
  :data:`~.settings.TRAIN_SEED`); constraint: every dead end of the Fig. 5 escape suite (simple deadlock, narrow
  passage, its gap and funnel ±20%, plastic network, :data:`~neurowalk.experiments.suites.deadends.TRAP_STEPS`
  steps) escaped; :data:`~.space.FITNESS_RULE` ranks the infeasible below the feasible.
* Every run goes through the sweep engine into ``DIR/results.sqlite``; the search's record (its settings, and
  each generation's candidates and scores) is written to ``DIR/cmaes.json`` after each generation. A killed
  search is resumed by replaying that record into a fresh CMA-ES of the same seed (its samples are checked to be
  the recorded ones), so it goes on with nothing recomputed and ends as an uninterrupted one would (same seed,
  same result). Nothing is pickled: a results folder cannot run code.
* Then the best candidate, the base variant and the paper variant walk held-out environments (table seed
  :data:`~.settings.HELDOUT_SEED`, Table 2's own), with Wilson 95% intervals; written by :mod:`.report`.

Sizes and seeds: :mod:`.settings`.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import asdict, dataclass, replace
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

from neurowalk.experiments import cma_record
from neurowalk.experiments.cma_record import import_cma
from neurowalk.experiments.optimize import report
from neurowalk.experiments.optimize.report import Search
from neurowalk.experiments.optimize.settings import (
    BODY,
    CMA_MISSING,
    FULL,
    HELDOUT_SEED,
    OLD_STATE_FILE,
    QUICK,
    SIGMA0,
    STATE_FILE,
    TRAIN_SEED,
    Sizes,
    check_seeds,
    check_sizes,
)
from neurowalk.experiments.optimize.space import Dim, decode, fitness, make_space, start_point
from neurowalk.experiments.study_runs import run_store, store_path
from neurowalk.experiments.suites import deadends, random_envs
from neurowalk.fileio import make_writable_folder
from neurowalk.runners import ray_backend
from neurowalk.runners.specs import code_of
from neurowalk.runners.stopping import deferred
from neurowalk.runners.store import count_finished
from neurowalk.sim.config import EpisodeConfig


def deadend_specs(variant: str, params: Mapping[str, float] | None, seeds: int) -> list[dict[str, Any]]:
    """Run specs of the escape suite: every Fig. 5 dead-end geometry x seeds 0..``seeds``-1, plastic, surrogate."""
    out = []
    for arena, opts in deadends.VARIANTS.values():
        for s in range(seeds):
            spec: dict[str, Any] = {
                "arena": arena,
                "arena_opts": dict(opts),
                "controller": "plastic",
                "body": BODY,
                "steps": deadends.TRAP_STEPS,
                "seed": s,
                "variant": variant,
            }
            if params:
                spec["params"] = dict(params)
            out.append(spec)
    return out


def train_specs(
    variant: str, params: Mapping[str, float] | None, envs: Sequence[dict[str, Any]], steps: int
) -> list[dict[str, Any]]:
    """Run specs of one network on the given random environments (Table 2's spec, surrogate body)."""
    return [
        random_envs.spec(e, "plastic", steps, BODY, variant=variant, params=dict(params) if params else None)
        for e in envs
    ]


@dataclass
class Runner:
    """Runs specs through the one runner (:func:`~neurowalk.experiments.study_runs.run_store`) on the resumable store
    ``folder/results.sqlite``, on a backend; counts what it computed and what it took from the store."""

    folder: Path
    backend: str
    workers: int
    address: str | None
    progress: bool
    computed: int = 0
    skipped: int = 0

    def __call__(self, specs: list[dict[str, Any]]) -> list[dict[str, Any]]:
        """The results of ``specs`` (summaries, in order), computing only those not in the store."""
        configs = [EpisodeConfig.from_spec(s) for s in specs]
        keys = {c.key() for c in configs}
        before = count_finished(store_path(self.folder), keys, code_of(configs))
        results = run_store([(c, ()) for c in configs], self.folder, self.workers, backend=self.backend,
                            address=self.address, desc="optimize", progress=self.progress)  # fmt: skip
        self.skipped += before
        self.computed += len(keys) - before
        return results


def load_state(path: Path, settings: dict[str, Any], space: Sequence[Dim]) -> dict[str, Any]:
    """The search recorded at ``path`` replayed into a fresh CMA-ES (:func:`new_state`), or a fresh one if there is
    none.

    Raises:
        ValueError (one line naming the file): damaged, foreign or newer, of a search with other settings, or an
        older neurowalk's pickled state (which is never read; the finished runs in results.sqlite are reused).
    """

    def generations(saved: dict[str, Any]) -> list[tuple[Any, list[float]]]:
        if not isinstance(saved.get("records"), list):
            raise ValueError("no generations")
        return [(r["x"], [f["score"] for f in r["fitness"]]) for r in saved["records"]]

    fresh = partial(new_state, space, settings)
    state, saved = cma_record.resume(path, settings, OLD_STATE_FILE, "the search state", fresh, generations)
    if saved is not None:
        state["records"] = saved["records"]
        if saved.get("stopped") is not None:
            state["stopped"] = saved["stopped"]
    return state


def new_state(space: Sequence[Dim], settings: dict[str, Any]) -> dict[str, Any]:
    """A fresh search of ``settings``: a CMA-ES started at the base variant's values, within the normalised space's
    bounds (:func:`~neurowalk.experiments.cma_record.start`: seeded ``seed + 1``, its samples drawn as a replay draws
    them)."""
    cma = import_cma(CMA_MISSING)
    state: dict[str, Any] = {"settings": settings, "records": [], "rng": None}
    x0 = start_point(space, settings["variant"])
    cma_record.start(cma, state, x0, settings["sigma0"], settings["seed"], settings["population"], bounds=[0.0, 1.0])
    return state


def run(
    *,
    out: Path | str = Path("out/optimize"),
    quick: bool = False,
    variant: str = "original",
    fields: Sequence[str] | None = None,
    bounds: Mapping[str, tuple[float, float] | None] | None = None,
    sizes: Mapping[str, int] | None = None,
    seed: int = 0,
    train_seed: int = TRAIN_SEED,
    heldout_seed: int = HELDOUT_SEED,
    sigma0: float = SIGMA0,
    backend: str = "local",
    workers: int = 2,
    address: str | None = None,
    progress: bool = True,
    log: Callable[[str], None] | None = None,
) -> Search:
    """Run (or resume) a search in ``out``, validate its best candidate, write best.json, heldout.json, plots.

    Args:
        out: output folder: results.sqlite, cmaes.json, best.json, heldout.json, history.json, convergence.png.
        quick: the :data:`~.settings.QUICK` sizes instead of :data:`~.settings.FULL`; ``sizes`` overrides single
            ones by name.
        variant: base variant ('paper' or 'original'); fields/bounds: see :func:`.space.make_space`.
        seed: CMA-ES seed; train_seed/heldout_seed: table seeds of the training and held-out environments.
        sigma0: initial step size in the normalised space (0, 1].
        backend, workers, address: the sweep engine's (local process pool or Ray).
        log: called with one line per generation and at the end (e.g. ``print``).

    Raises:
        ValueError: a bad name, bound, size or seed, or an output folder holding a search with other settings.
        CmaMissingError: the ``cma`` package is not installed.
        KeyboardInterrupt: interrupted; the finished runs and generations are kept and a rerun resumes.
    """
    base_sizes = QUICK if quick else FULL  # checked before any work
    unknown = sorted(set(sizes or {}) - set(asdict(base_sizes)))
    if unknown:
        raise ValueError(f"unknown size {unknown[0]!r}; sizes: {', '.join(asdict(base_sizes))}")
    sz = replace(base_sizes, **(sizes or {}))
    check_sizes(sz)
    check_seeds(seed, train_seed, heldout_seed, sz)
    if not (isinstance(sigma0, int | float) and 0 < sigma0 <= 1):
        raise ValueError(f"sigma0 must be in (0, 1] (the normalised space), got {sigma0!r}")
    space = make_space(variant, fields, bounds)
    import_cma(CMA_MISSING)  # CmaMissingError before any work
    if backend not in ("local", "ray"):
        raise ValueError(f"unknown backend {backend!r}; expected local or ray")
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ValueError(f"workers must be a whole number >= 1, got {workers!r}")
    folder = Path(out)
    make_writable_folder(folder)  # ValueError naming what is wrong
    say = log or (lambda line: None)
    settings = {
        "variant": variant,
        "space": [asdict(d) for d in space],
        "population": sz.population,
        "environments": sz.environments,
        "steps": sz.steps,
        "deadend_seeds": sz.deadend_seeds,
        "seed": seed,
        "train_seed": train_seed,
        "sigma0": float(sigma0),
    }
    path = folder / STATE_FILE
    state = load_state(path, settings, space)
    runner = Runner(folder, backend, workers, address, progress)
    with _ray(backend, workers, address):  # one Ray instance for every generation
        base_fit = _train(state, space, sz, runner, path, say)
        search, best = _heldout(state, space, sz, runner, base_fit, heldout_seed)
    kept = {k: settings[k] for k in ("seed", "train_seed", "sigma0", "variant")}
    search.best = report.best_json(search, best, sz, stopped=state.get("stopped"), **kept)
    with deferred():
        report.write(search, folder)
    say(report.final_line(search, folder))
    return search


@contextmanager
def _ray(backend: str, workers: int, address: str | None) -> Iterator[None]:
    """With ``backend`` 'ray': a Ray instance started for the block and stopped after it (if it was started here)."""
    started = False
    if backend == "ray":
        started = ray_backend.start(workers=workers, address=address)
    try:
        yield
    finally:
        if started:
            ray_backend.stop()


def _train(
    state: dict[str, Any], space: Sequence[Dim], sz: Sizes, runner: Runner, path: Path, say: Callable[[str], None]
) -> dict[str, Any]:
    """The generations of the search ``state`` not yet recorded, each saved to ``path`` and told to ``say``, until
    ``sz.generations`` or a CMA-ES stop; returns the base variant's fitness on the training environments (the
    variant and the environments' seed are those of the state's settings)."""
    variant = state["settings"]["variant"]
    envs = random_envs.environments(sz.environments, state["settings"]["train_seed"])

    def evaluate(vname: str, params: Mapping[str, float] | None) -> list[dict[str, Any]]:
        return train_specs(vname, params, envs, sz.steps) + deadend_specs(vname, params, sz.deadend_seeds)

    n = len(envs)
    base_runs = runner(evaluate(variant, None))
    base_fit = fitness(base_runs[:n], base_runs[n:])
    records = state["records"]
    while len(records) < sz.generations and not state.get("stopped"):
        t0 = time.perf_counter()
        done_before = runner.computed
        xs = cma_record.ask(state)
        cands = [decode(space, x) for x in xs]
        specs = [s for c in cands for s in evaluate(variant, c)]
        results = runner(specs)
        per = len(specs) // len(cands)
        fits = [
            fitness(results[i * per : i * per + n], results[i * per + n : (i + 1) * per]) for i in range(len(cands))
        ]
        stop = cma_record.tell(state, xs, [f["score"] for f in fits])
        es = state["es"]
        records.append(
            {
                "generation": len(records) + 1,
                "x": [x.tolist() for x in xs],
                "params": cands,
                "fitness": fits,
                "mean_x": np.clip(es.mean, 0, 1).tolist(),
                "mean": decode(space, es.mean),
                "sigma": float(es.sigma),
            }
        )
        if stop:
            state["stopped"] = {"generation": len(records), "reason": stop}
        with deferred():  # a generation is saved whole: a Ctrl-C now stops the search after it
            cma_record.write(path, {k: state.get(k) for k in ("settings", "records", "stopped")})
        say(
            report.generation_line(
                records, sz.generations, base_fit, runner.computed - done_before, time.perf_counter() - t0
            )
        )
    return base_fit


def _heldout(
    state: dict[str, Any], space: Sequence[Dim], sz: Sizes, runner: Runner, base_fit: dict[str, Any], heldout_seed: int
) -> tuple[Search, dict[str, Any]]:
    """The search's result less its best.json, and its best candidate: the history of ``sz.generations`` at most,
    and the best candidate, the base variant and the paper variant on the held-out environments of
    ``heldout_seed``."""
    history = state["records"][: sz.generations]
    best = report.best_candidate(history)
    held = random_envs.environments(sz.heldout, heldout_seed)
    rows = report.heldout_rows(state["settings"]["variant"], best["params"])
    held_runs = {name: runner(train_specs(v, p, held, sz.steps)) for name, (v, p) in rows.items()}
    search = Search(
        best={},
        heldout=report.heldout_table(rows, held, held_runs, heldout_seed, sz.steps),
        history=history,
        base_training=base_fit,
        space=space,
        runs_computed=runner.computed,
        runs_skipped=runner.skipped,
    )
    return search, best
