"""A study's runs: the one run function and the one result store they are kept in.

.. code-block:: text

    (config, terms) ... ─► run_store ─► store.sqlite: one row per run spec (its key), the run's summary and
                                         │ "kept": {term: what the term keeps}   (rows lacking a term: run again)
                              run_kept ◄─┘ (pool | Ray; MuJoCo Warp: the worlds of shared calls, kept the same way)

A :class:`Term` is what a study keeps of a run beside its summary (a recorder term: a path every second, the traces a
figure draws, a streamed long run's rows, ...). :func:`run_kept` is the one function that runs a spec and keeps its
terms; :func:`run_store` runs configs through the store of a folder, each run stored as it finishes, so that a stopped
study keeps its finished runs and the same call again runs only the others.

A store's folder may be shared by many studies (``Settings.shared_runs``, ``neurowalk figure --shared-runs DIR``;
``neurowalk reproduce`` shares one across its figures): a run one figure made is taken by another that asks for the
same config (the same config gives the same result, bit for bit), not run again.
"""

from __future__ import annotations

import contextlib
import functools
import tempfile
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from neurowalk import fingerprint
from neurowalk.body.registry import physics_settings
from neurowalk.experiments.plan import Plan
from neurowalk.runners.specs import code_of, config_of, episode_of, result_of
from neurowalk.runners.stopping import deferred
from neurowalk.runners.store import ResultStore
from neurowalk.runners.sweep import Kind, run_sweep
from neurowalk.sim.config import EpisodeConfig
from neurowalk.sim.engine_interface import EngineOptions, Streaming
from neurowalk.sim.episode import Episode
from neurowalk.sim.run_summary import RunSummary

STORE = "results.sqlite"  # a study's store in its folder (and in a shared folder)


@dataclass(frozen=True)
class Term:
    """What a study keeps of a run beside its summary.

    Attributes:
        name: its name (the key of what it keeps in a stored run's ``kept``).
        keep: ``keep(episode) -> dict`` of JSON-able values or numpy arrays (a module-level function: it runs in
            the pool's workers).
        arrays: the kept entries read back as numpy arrays, by name: their dtype (``"float64"``, ``"int64"``).
        stream: for a run too long to hold in memory: ``stream(config) -> (Streaming, finish)``; the run streams
            its rows to the Streaming's sink and ``finish(episode)`` gives what it keeps (``keep`` serves an
            episode held in memory: a many-worlds engine's).
    """

    name: str
    keep: Callable[[Episode], dict[str, Any]]
    arrays: Mapping[str, str] = field(default_factory=dict)
    stream: Callable[[EpisodeConfig], tuple[Streaming, Callable[[Episode], dict[str, Any]]]] | None = None


class RunsStopped(KeyboardInterrupt):
    """A stop (SIGINT, SIGTERM) while a study's runs ran, or after they had: ``kept``, its finished runs by store file
    (empty: none had finished; None: the study runs no episode)."""

    def __init__(self, kept: dict[Path, int] | None) -> None:
        super().__init__("stopped")
        self.kept = kept


class RunsFailedError(RuntimeError):
    """Runs of a batch failed: how many, the first one's error (one line), and the store that keeps the others."""

    def __init__(self, failed: int, first: str, store: Path | None) -> None:
        self.failed, self.first, self.store = failed, first, store
        kept = f"; the finished runs are kept in {store}: rerun to retry the failed" if store is not None else ""
        super().__init__(f"{failed} runs failed, the first with {first}{kept}")


@dataclass(frozen=True)
class Kept:
    """A finished run, as a study's measure gets it: ``r.escaped`` reads its summary's attribute.

    Attributes:
        summary: the run's :class:`~neurowalk.sim.run_summary.RunSummary`.
        kept: what its terms kept, by term name: {name: {key: value}}, the arrays a term declares as numpy arrays.
        plan: the :class:`~neurowalk.experiments.plan.Plan` it ran (its config with the settings applied).
    """

    summary: RunSummary
    kept: Mapping[str, dict[str, Any]]
    plan: Plan

    @classmethod
    def of(cls, result: Mapping[str, Any], plan: Plan) -> Kept:
        """A run as :func:`run_store` gives it back (its summary and ``kept``), with the plan it ran."""
        summary = RunSummary.from_dict({k: v for k, v in result.items() if k != "kept"})
        return cls(summary, result.get("kept", {}), plan)

    @property
    def config(self) -> EpisodeConfig:
        """The config it ran (its plan's)."""
        return self.plan.config

    def __getattr__(self, name: str) -> Any:
        if name in ("summary", "kept", "plan"):  # not yet set (while unpickling)
            raise AttributeError(name)
        return getattr(self.summary, name)


def run_kept(terms: Sequence[Term], spec: dict[str, Any] | EpisodeConfig) -> dict[str, Any]:
    """The one run function: run ``spec`` to its end; its summary (JSON-safe, without the machine's keys) and, with
    ``terms``, ``kept``: what each term keeps. A term that streams (:attr:`Term.stream`) runs alone."""
    streamed = [t for t in terms if t.stream is not None]
    if streamed:
        if len(terms) > 1:
            raise ValueError(f"term {streamed[0].name!r} streams its run: it is kept alone")
        stream, finish = streamed[0].stream(config_of(spec))  # type: ignore[misc]
        ep = episode_of(spec, stream)
        return {**result_of(ep), "kept": {streamed[0].name: finish(ep)}}
    return kept_of(terms, episode_of(spec))


def kept_of(terms: Sequence[Term], ep: Episode) -> dict[str, Any]:
    """What :func:`run_kept` stores of an episode held in memory."""
    out = result_of(ep)
    if terms:
        out["kept"] = {t.name: t.keep(ep) for t in terms}  # arrays as they are: the store writes them as JSON
    return out


def store_path(folder: Path) -> Path:
    """Where :func:`run_store` keeps the runs of a store's folder: ``folder/results.sqlite``."""
    return Path(folder) / STORE


def run_store(
    runs: Sequence[tuple[EpisodeConfig, Sequence[Term]]],
    folder: Path,
    workers: int,
    options: EngineOptions | None = None,
    backend: str = "local",
    address: str | None = None,
    desc: str = "runs",
    progress: bool = True,
    files: Sequence[Path] = (),
) -> list[dict[str, Any]]:
    """Run each (config, terms) through the store of ``folder`` (:func:`store_path`); each run's stored result, in
    order, its kept arrays as numpy arrays.

    The store takes a run as done only where the same code made it (:func:`~neurowalk.runners.specs.code_of`: the
    package, its libraries, the user's ``files``, e.g. a study's, and a user's body file); runs it holds of other
    code run again, and a line says how many.

    A config asked for twice runs once, keeping every term asked for; a stored run lacking a term now asked for runs
    again (keeping its old terms too), and so does one stored with another physics than its config steps today
    (``summary.json``'s ``physics``: a store of an older neurowalk; its key names the options given, not the
    defaults). Each run is stored as it finishes: a stopped study (KeyboardInterrupt, raised here once the store is
    closed) keeps its finished runs, and the next call says it goes on from them. ``options``: how the engines run
    (MuJoCo Warp's device); ``backend``, ``address``: a process pool (``local``) or Ray (and the cluster to join);
    ``desc``: the progress bar's label (``progress``: shown). RuntimeError where runs failed, naming the first
    failure; :class:`RunsStopped` (a KeyboardInterrupt) when stopped, with the finished runs it keeps.
    """
    path = store_path(folder)
    keys = [cfg.key() for cfg, _ in runs]
    wanted: dict[str, dict[str, Term]] = {}
    specs: dict[str, dict[str, Any]] = {}
    configs: dict[str, EpisodeConfig] = {}
    for key, (cfg, terms) in zip(keys, runs, strict=True):
        wanted.setdefault(key, {}).update({t.name: t for t in terms})
        specs.setdefault(key, cfg.spec())
        configs.setdefault(key, cfg)
    path.parent.mkdir(parents=True, exist_ok=True)
    with deferred():  # opened whole (its lock, its tables), or not at all
        store = ResultStore(path, code_of(configs.values(), files))
    with store:
        held = store.results(keys=wanted)
        if held and progress:
            print(f"{desc}: going on from the {len(held)} finished runs kept in {path.parent} ({len(held)} in {STORE})")
        if progress and (line := store.other_code_line(wanted, desc)):
            print(line)

        def stale(key: str) -> bool:
            """A stored run of another physics than its config's today (an older neurowalk's): it runs again."""
            cfg = configs[key]
            return held[key].get("physics") != physics_settings(cfg.body, cfg.body_opts, cfg.control_hz)

        def amend(key: str, result: dict[str, Any]) -> dict[str, Any]:
            """A run kept again keeps what it kept before (of the same physics) beside what it keeps now."""
            old = held.get(key, {}).get("kept", {}) if key in held and not stale(key) else {}
            return {**result, "kept": {**old, **result.get("kept", {})}} if old else result

        groups: dict[tuple[str, ...], list[str]] = {}
        for key, terms in wanted.items():
            groups.setdefault(tuple(sorted(terms)), []).append(key)
        ran: list[str] = []

        def _run_group(names: tuple[str, ...], group: list[str]) -> bool:
            """Run the group's runs lacking in the store (or stale, or lacking a term); whether it was stopped."""
            terms_ = tuple(wanted[group[0]][n] for n in names)
            redo = [k for k in group if k in held and (set(names) - set(held[k].get("kept", {})) or stale(k))]
            ran.extend([k for k in group if k not in held] + redo)
            report = run_sweep(
                [configs[k] for k in group],
                store,
                workers=workers,
                options=options,
                backend=backend,
                address=address,
                desc=desc,
                progress=progress,
                fn=functools.partial(run_kept, terms_),
                carry=True,  # run_kept takes the configs themselves
                world_fn=functools.partial(kept_of, terms_),
                redo=redo,
                amend=amend,
            )
            return report.interrupted

        stopped = False
        try:
            for names, group in groups.items():
                stopped = _run_group(names, group)
                if stopped:
                    break
        except KeyboardInterrupt:  # a stop between the sweeps' own handling of it
            stopped = True
        results = {**held, **store.results(keys=ran)}
        missing = [k for k in wanted if k not in results]
        failed = store.rows("error", missing[:1]) if missing else []
    if stopped:
        raise RunsStopped({path: len(results)} if results else {})
    if missing:
        raise RunsFailedError(len(missing), failed[0]["error"] if failed else "unknown", path)
    arrays = {n: t.arrays for terms in wanted.values() for n, t in terms.items()}
    return [_read(results[k], arrays) for k in keys]


def _read(result: dict[str, Any], arrays: Mapping[str, Mapping[str, str]]) -> dict[str, Any]:
    """A stored result with its terms' arrays as numpy arrays."""
    if "kept" not in result:
        return result
    kept = {
        n: {k: np.asarray(v, dtype=arrays.get(n, {})[k]) if k in arrays.get(n, {}) else v for k, v in d.items()}
        for n, d in result["kept"].items()
    }
    return {**result, "kept": kept}


def run_all(
    configs: Sequence[EpisodeConfig],
    terms: Sequence[Term] = (),
    *,
    workers: int = 2,
    folder: Path | None = None,
    options: EngineOptions | None = None,
    progress: bool = True,
    desc: str = "runs",
) -> list[Kept]:
    """Run every config through the one runner (:func:`run_store`: the pool, or MuJoCo Warp's shared calls), in the
    result store of ``folder`` (a stopped call goes on from the runs it finished) or of a temporary folder; each run
    as a :class:`Kept` (its summary, what ``terms`` keep of it, its plan), in the configs' order.

    E.g. ``[r.escaped for r in run_all([EpisodeConfig(arena="box", seed=s) for s in range(4)])]``. RuntimeError
    naming the first failure where runs failed (the others are kept in ``folder``'s store).
    """
    with store_folder(folder) as where:
        try:
            results = run_store([(c, tuple(terms)) for c in configs], where, workers, options=options, desc=desc,
                                progress=progress)  # fmt: skip
        except RunsFailedError as e:
            if folder is None:  # a temporary store: nothing is kept
                raise RunsFailedError(e.failed, e.first, None) from None
            raise
    return [Kept.of(r, Plan(k, c, terms)) for k, (c, r) in enumerate(zip(configs, results, strict=True))]


def run_jobs(
    fn: Callable[[dict[str, Any]], dict[str, Any]],
    specs: Sequence[dict[str, Any]],
    kind: Kind,
    *,
    folder: Path | None = None,
    workers: int = 2,
    progress: bool = True,
    desc: str = "jobs",
    files: Sequence[Path] = (),
) -> list[dict[str, Any]]:
    """``[fn(spec) for spec in specs]`` for jobs that are not episodes (``kind``: a
    :func:`~neurowalk.runners.sweep.job_kind`), through the one runner: the process pool (``workers``; 1 runs them
    here) and the result store of ``folder`` (of a temporary folder where None), each result kept as it finishes. A
    stopped call (KeyboardInterrupt, raised once the store is closed) keeps its finished jobs, and the same call again
    runs only the others, saying so; jobs kept by other code (:func:`neurowalk.fingerprint.code` of the package and
    the user's ``files``) run again, and a line says how many. ``fn``: a module-level function returning a JSON-able
    dict (floats come back bit for bit). :class:`RunsFailedError` naming the first failure.
    """
    with store_folder(folder) as where:
        path = store_path(where)
        path.parent.mkdir(parents=True, exist_ok=True)
        with deferred():
            store = ResultStore(path, fingerprint.code(files))
        with store:
            keys = [kind.key(kind.canonical(s)) for s in specs]
            held = store.results(keys=keys)
            if held and progress:
                print(f"{desc}: going on from the {len(held)} finished jobs kept in {where} ({len(held)} in {STORE})")
            if progress and (line := store.other_code_line(keys, desc)):
                print(line)
            report = run_sweep(specs, store, workers=workers, progress=progress, desc=desc, fn=fn, kind=kind)
            results = store.results(keys=keys)
            missing = [k for k in keys if k not in results]
            failed = store.rows("error", missing[:1]) if missing else []
        if report.interrupted:
            raise KeyboardInterrupt
        if missing:
            first = failed[0]["error"] if failed else "unknown"
            raise RunsFailedError(len(set(missing)), first, path if folder is not None else None)
    return [results[k] for k in keys]


@contextlib.contextmanager
def store_folder(out: Path | None) -> Iterator[Path]:
    """The folder of a study's store: ``out``, or (a study run from Python without one) a temporary folder, removed
    afterwards."""
    if out is not None:
        yield Path(out)
        return
    with tempfile.TemporaryDirectory(prefix="neurowalk-") as tmp:
        yield Path(tmp)
