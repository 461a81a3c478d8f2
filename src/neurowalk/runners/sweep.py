"""Resumable sweeps: many run specs into one :class:`~neurowalk.runners.store.ResultStore`.

.. code-block:: text

    specs ─ normalise, dedup by key ─ drop keys already 'ok' in the store (resume) ─► backend (local | ray)
                                                                                        │ results as they finish
    store ◄── one transaction per run (driver only) ◄────────────────────────────────────┘

A run that raises is stored with status 'error' and its one-line message, and the sweep goes on; so is a run
whose worker process died (not rerun unless ``retries`` says so). Rerunning the same sweep recomputes only what is
missing or failed. Each run is seeded by its own spec, so the stored results do not depend on the backend or the
number of workers.
"""

from __future__ import annotations

import hashlib
import json
import sys
import time
from collections.abc import Callable, Collection, Generator, Iterable, Iterator, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

from neurowalk.progress import Progress
from neurowalk.runners import ray_backend
from neurowalk.runners.jobs import JobResult
from neurowalk.runners.local import run_unordered
from neurowalk.runners.specs import Spec, describe, result_of, run_spec, spec_key
from neurowalk.runners.stopping import deferred
from neurowalk.runners.store import ResultStore
from neurowalk.sim.config import EpisodeConfig
from neurowalk.sim.engine_interface import Engine, EngineOptions
from neurowalk.sim.engines import call_groups, engine_for
from neurowalk.sim.episode import Episode

BACKENDS = ("local", "ray")


@dataclass(frozen=True)
class Kind:
    """What the specs of a sweep are: how one is made canonical (ValueError naming a bad value), keyed (its row of
    the store) and named in a line. :data:`EPISODES` (EpisodeConfig specs) by default; :func:`job_kind` for jobs of
    another kind (a calibration's drives, a baseline's scoring)."""

    name: str
    canonical: Callable[[Spec], Spec]
    key: Callable[[Spec], str]
    describe: Callable[[Spec], str]


def _episode_spec(spec: Spec) -> Spec:
    return EpisodeConfig.from_spec(spec).spec()


EPISODES = Kind("episode", _episode_spec, spec_key, describe)


def job_kind(name: str) -> Kind:
    """Jobs called ``name`` whose specs are JSON objects, canonical as they are; each keyed by the SHA-256 of its
    canonical JSON with ``name`` (so no job of another kind has its key)."""

    def canonical(spec: Spec) -> Spec:
        if not isinstance(spec, dict):
            raise ValueError(f"a {name} job's spec must be a JSON object, got {type(spec).__name__}")
        return json.loads(json.dumps(spec, sort_keys=True, allow_nan=False))

    def key(spec: Spec) -> str:
        return hashlib.sha256(json.dumps([name, spec], sort_keys=True).encode()).hexdigest()

    return Kind(name, canonical, key, lambda spec: f"{name} {json.dumps(spec, sort_keys=True)[:80]}")


@dataclass
class Failure:
    """A run that ended in an error."""

    key: str
    spec: Spec
    error: str  # one line: "ExceptionType: message"
    what: str  # the spec in words (its kind's ``describe``)

    def line(self) -> str:
        """``3f2a9c1b0d4e box gap=0.3 plastic amosii seed=3 steps=300: ValueError: ...``"""
        return f"{self.key[:12]} {self.what}: {self.error}"


@dataclass
class SweepReport:
    """What a sweep did: counts of this invocation, and the store's totals afterwards."""

    total: int = 0  # specs given
    unique: int = 0  # distinct runs among them
    duplicates: int = 0  # specs that repeated another one (run once)
    skipped: int = 0  # already 'ok' in the store: not recomputed
    ok: int = 0  # run now, without error
    error: int = 0  # run now, with an error (see failures)
    failures: list[Failure] = field(default_factory=list)
    wall_time_s: float = 0.0  # of the whole sweep
    interrupted: bool = False  # stopped early (Ctrl-C); the finished runs are stored

    def counts(self) -> dict[str, Any]:
        """The numbers (no failure details), for sweep.json."""
        keys = ("total", "unique", "duplicates", "skipped", "ok", "error", "wall_time_s", "interrupted")
        return {k: getattr(self, k) for k in keys}


def prepare(
    specs: Iterable[Spec | EpisodeConfig], kind: Kind = EPISODES
) -> tuple[list[tuple[str, Spec]], int, dict[str, EpisodeConfig]]:
    """Normalise and key the specs (of ``kind``), dropping repeats (first one kept): ([(key, spec)], number of specs
    given, {key: config} of the episodes).

    An episode is given as a spec (checked here, where it enters: one config made of it) or as an
    :class:`EpisodeConfig` (checked when it was made: taken as it is). Raises ValueError (naming the value) on a bad
    spec, before any run.
    """
    seen: dict[str, Spec] = {}
    configs: dict[str, EpisodeConfig] = {}
    n = 0
    for spec in specs:
        n += 1
        if kind is EPISODES:
            cfg = spec if isinstance(spec, EpisodeConfig) else EpisodeConfig.from_spec(spec)
            key, s = cfg.key(), cfg.spec()
            configs.setdefault(key, cfg)
        elif isinstance(spec, EpisodeConfig):
            raise ValueError(f"a {kind.name} job's spec must be a JSON object, got an EpisodeConfig")
        else:
            s = kind.canonical(spec)
            key = kind.key(s)
        seen.setdefault(key, s)
    return list(seen.items()), n, configs


def run_sweep(
    specs: Iterable[Spec | EpisodeConfig],
    store: ResultStore,
    *,
    backend: str = "local",
    workers: int = 2,
    address: str | None = None,
    progress: bool = True,
    fn: Callable[..., object] = run_spec,
    retries: int = 0,
    options: EngineOptions | None = None,
    desc: str = "sweep",
    world_fn: Callable[[Episode], dict[str, Any]] | None = None,
    redo: Collection[str] = (),
    amend: Callable[[str, dict[str, Any]], dict[str, Any]] | None = None,
    kind: Kind = EPISODES,
    carry: bool = False,
) -> SweepReport:
    """Run every spec not yet done into ``store``; return the counts.

    Args:
        specs: run specs (dicts of EpisodeConfig fields; see :mod:`neurowalk.runners.specs`), or the configs.
        store: where each result is written as soon as it arrives (this process writes, workers only compute).
        backend: 'local' (process pool; workers=1 runs here) or 'ray'.
        workers: processes (local) or CPUs of the local Ray instance.
        address: Ray cluster to join (backend 'ray' only).
        progress: show a progress bar (unit "run", with rate and time left) on stderr.
        fn: computes one run's result (a JSON-able dict) from its normalised spec; a module-level function.
        carry: ``fn`` takes a run's EpisodeConfig as well as its spec (:func:`run_spec` does): where the runs cross no
            process boundary (backend 'local', workers 1) it gets each config as it is, made once, not its spec.
        retries: how many more times a run whose worker process died is run before it is stored as failed
            (default 0: stored at once as ``WorkerDiedError``).
        options: how the engines run (e.g. MuJoCo Warp's device).
        desc: the progress bar's label.
        world_fn: what ``fn`` keeps, from an episode held in memory: with it (or with ``fn`` the default), the runs
            of a many-worlds engine (MuJoCo Warp) run here as the worlds of shared calls; without it, on the pool.
        redo: keys run again though the store holds them (e.g. rows that lack something now kept).
        amend: ``amend(key, result) -> result``: a finished run's result as it is stored, made here in the driver
            (e.g. what the row it replaces kept, added).
        kind: what the specs are (:data:`EPISODES`; a :func:`job_kind`'s are run by ``fn`` on the backend).

    Raises:
        ValueError: bad spec, backend or worker count (before any run).
        RayMissingError, RayStartError: backend 'ray' without ray installed, or Ray failing to start.
    """
    if backend not in BACKENDS:
        raise ValueError(f"unknown backend {backend!r}; expected one of {', '.join(BACKENDS)}")
    if int(workers) != workers or workers < 1:
        raise ValueError(f"workers must be a positive integer, got {workers!r}")
    if int(retries) != retries or retries < 0:
        raise ValueError(f"retries must be a whole number >= 0, got {retries!r}")
    if address and backend != "ray":
        raise ValueError("an address goes with backend 'ray'")
    t0 = time.perf_counter()
    if kind is not EPISODES and (fn is run_spec or world_fn is not None):
        raise ValueError(f"{kind.name} jobs are not episodes: give their fn, and no world_fn")
    keyed, total, configs = prepare(specs, kind)
    done = store.done_keys()
    redo = set(redo)
    todo = [(k, s) for k, s in keyed if k not in done or k in redo]
    report = SweepReport(total=total, unique=len(keyed), duplicates=total - len(keyed), skipped=len(keyed) - len(todo))
    results = bar = None
    try:
        if todo:
            keep = world_fn if world_fn is not None else (result_of if fn is run_spec else None)
            here = kind is EPISODES and backend == "local" and workers == 1 and (carry or fn is run_spec)
            items = [configs[k] if here else s for k, s in todo]
            cfgs = [configs[k] for k, _ in todo] if keep is not None else []
            results = _backend(backend, fn, keep, items, cfgs, workers, address, retries, options or EngineOptions())
            bar = Progress(
                total=len(todo), unit="run", desc=desc, disable=not progress, mininterval=0.5, file=sys.stderr
            )
            for d in results:
                key, spec = todo[d.index]
                if amend is not None and d.error is None and isinstance(d.value, dict):
                    d = replace(d, value=amend(key, d.value))
                with deferred():  # a run is stored whole, or not at all
                    _store(store, key, spec, d, report, kind)
                bar.update(1)
                if report.error:
                    bar.set_postfix(errors=report.error, refresh=False)
    except KeyboardInterrupt:
        report.interrupted = True
    finally:
        with deferred():  # the workers are ended and reaped, whatever comes now
            if results is not None:
                results.close()
            if bar is not None:
                bar.close()
    report.wall_time_s = time.perf_counter() - t0
    return report


def _backend(
    backend: str,
    fn: Callable[..., object],
    keep: Callable[[Episode], dict[str, Any]] | None,
    items: list[Spec | EpisodeConfig],
    configs: list[EpisodeConfig],
    workers: int,
    address: str | None,
    retries: int,
    options: EngineOptions,
) -> Generator[JobResult, None, None]:
    """Results (:class:`JobResult`, any order) of ``fn`` on ``items``: runs of a many-worlds engine (MuJoCo Warp) as the
    worlds of shared calls, in this process (``keep`` of each episode; None: every run on the backend); the others
    on the backend. ``configs``: the items' configs (none where ``keep`` is None)."""
    shared = list(world_groups(configs, options)) if keep is not None else []
    done = {i for group, _ in shared for i in group}
    others = [i for i in range(len(items)) if i not in done]

    def chained() -> Generator[JobResult, None, None]:
        if shared:
            yield from world_runs(configs, shared, options, keep or result_of)
        if others:
            inner = _pool(backend, fn, [items[i] for i in others], workers, address, retries)
            try:
                for d in inner:
                    yield JobResult(others[d.index], d.value, d.error, d.wall_time_s)
            finally:
                inner.close()

    return chained()  # the shared calls' runs (none without a many-worlds engine), then the others on the backend


def world_groups(
    configs: Sequence[EpisodeConfig], options: EngineOptions, worlds: int | None = None
) -> Iterator[tuple[list[int], Engine]]:
    """The :func:`~neurowalk.sim.engines.call_groups` of many-worlds engines (``mujoco.batch``, MuJoCo Warp): runs
    that share one call. Configs of an engine that runs one world at a time are left out (they go to a pool)."""
    many = [i for i, cfg in enumerate(configs) if engine_for(cfg).many_worlds]
    for group, engine in call_groups([configs[i] for i in many], options, worlds=worlds):
        yield [many[j] for j in group], engine


def world_runs(
    configs: list[EpisodeConfig],
    groups: list[tuple[list[int], Engine]],
    options: EngineOptions,
    keep: Callable[[Episode], dict[str, Any]] = result_of,
) -> Iterator[JobResult]:
    """Run the configs of each group (:func:`world_groups`) as the worlds of one call of its
    engine; one :class:`JobResult` per run (``keep`` of its episode), its wall time the call's divided by its worlds.
    A call that raises gives each of its runs that error."""
    for runs, engine in groups:
        t0 = time.perf_counter()
        try:
            eps = engine.run([configs[i] for i in runs], replace(options, progress=False))
        except Exception as e:
            for i in runs:
                yield JobResult(i, error=e)
            continue
        wall = (time.perf_counter() - t0) / len(runs)
        for i, ep in zip(runs, eps, strict=True):
            yield JobResult(i, value=keep(ep), wall_time_s=wall)


def _pool(
    backend: str,
    fn: Callable[..., object],
    items: list[Spec | EpisodeConfig],
    workers: int,
    address: str | None,
    retries: int,
) -> Generator[JobResult, None, None]:
    if backend == "ray":
        ray_backend.import_ray()  # the install hint now, not at the first result
        return ray_backend.run_unordered(fn, items, workers=workers, address=address, retries=retries)
    return run_unordered(fn, items, workers=workers, retries=retries)


def _store(store: ResultStore, key: str, spec: Spec, d: JobResult, report: SweepReport, kind: Kind) -> None:
    """Write one finished run and count it."""
    if d.error is None and isinstance(d.value, dict):
        store.put(key, spec, result=d.value, wall_time_s=d.wall_time_s)
        report.ok += 1
        return
    error = d.error or TypeError(f"a run's result must be a dict, got {type(d.value).__name__}")
    message = one_line(error)
    store.put(key, spec, error=message, wall_time_s=d.wall_time_s)
    report.error += 1
    report.failures.append(Failure(key, spec, message, kind.describe(spec)))


def one_line(e: BaseException) -> str:
    """``"ExceptionType: first line of the message"``."""
    text = str(e).strip()
    return f"{type(e).__name__}: {text.splitlines()[0]}" if text else type(e).__name__
