"""A study: an experiment declared in one place (its runs, its measure, its picture), run by :func:`run_study`.

.. code-block:: text

    Study.runs(settings) ─► Plan(label, config, terms) ... ─► settings applied ─► result store (resume) ─► pool | Ray
                                                                                           │ one summary per run
    NAME.png ◄─ Study.plot ◄─ NAME.json, NAME.npz ◄─ Study.measure(settings, {label: [Kept(summary, kept, plan)]}) ◄┘
                                  ▲ Study.render(result): snapshots of recorded poses; Study.videos: with --video

Every paper figure is a study (:data:`neurowalk.experiments.FIGURES`), and so is a user's own
(``neurowalk study FILE.py``). One frozen :class:`Settings` is shared by all; a study declares in ``takes`` which of
its optional settings it honours, and the command line offers and accepts only those. ``measure`` computes numbers
only; a study of the network alone plans no run and computes its numbers in ``measure``.
"""

from __future__ import annotations

import dataclasses
import itertools
import json
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from neurowalk import fingerprint, profiling
from neurowalk.experiments.plan import Label, Plan
from neurowalk.sim.config_values import FrozenDict

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from neurowalk.experiments.study_runs import Term
    from neurowalk.sim.config import EpisodeConfig
    from neurowalk.sim.run_summary import RunSummary

#: The optional settings, in the order the command line lists them (quick, seed and out every study takes).
OPTIONAL = ("seeds", "body", "climbing", "variant", "params", "gait", "video", "size", "engine", "control_hz",
            "workers", "backend")  # fmt: skip
#: The settings a study of runs takes unless it says otherwise.
RUNS_TAKE = ("seeds", "workers", "backend")
MAX_SEEDS = 100_000  # the most environments or seeds a study takes (``seeds``)


@dataclass(frozen=True, kw_only=True)
class Settings:
    """How a study is run, the same for every study (the flags of ``neurowalk figure`` and ``neurowalk study``).

    None means the study's own default; a study takes the optional ones it names in ``Study.takes``.

    Attributes:
        quick: a first look: the study's quick version (fewer seeds or environments, shorter runs, as it defines).
        seed: the seed every run's seed derives from (0 to 2**63 - 1).
        seeds: seeds (or environments) per condition, 1 to :data:`MAX_SEEDS`.
        body: the robot of every run (``neurowalk bodies``).
        climbing: leg reflexes and backbone control on (the modules of the paper's Fig. 10).
        variant: the network of every run: ``paper``, ``original`` (the authors' code) or ``tuned``.
        params: SensoryParams fields set on top of the variant, or a params file's path (``--params FILE``: its
            fields, and its base variant where ``variant`` names none, read as the settings are resolved), or None.
        gait: the locomotion network's gait by name (``neurowalk.neural.cpg.GAITS``).
        video: also write the example runs' videos.
        size: box side of random environments, m.
        engine: physics engine: ``mujoco`` (the CPU loop) or ``warp`` (MuJoCo Warp).
        device: engine ``warp``'s device (``cuda`` or ``cpu``).
        control_hz: every run's control rate, Hz (in (0, 1000]).
        workers: processes of the local pool, or CPUs of a local Ray instance.
        backend: where the runs run: ``local`` (a process pool) or ``ray``.
        address: the Ray cluster to join (with backend ``ray``), e.g. ``"10.0.0.1:6379"``.
        out: the output folder (default ``out/NAME``): NAME.json, NAME.npz, NAME.png and the result store.
        shared_runs: the folder whose result store keeps the runs instead of ``out``'s (``--shared-runs``): shared
            by many studies, a run one of them made is taken by another that asks for the same config.
    """

    quick: bool = False
    seed: int = 0
    seeds: int | None = None
    body: str | None = None
    climbing: bool = False
    variant: str | None = None
    params: Mapping[str, float] | Path | str | None = None
    gait: str | None = None
    video: bool = False
    size: float | None = None
    engine: str = "mujoco"
    device: str | None = None
    control_hz: float | None = None
    workers: int | None = None
    backend: str = "local"
    address: str | None = None
    out: Path | str | None = None
    shared_runs: Path | str | None = None

    def __post_init__(self) -> None:
        if isinstance(self.params, str | Path):
            object.__setattr__(self, "params", Path(self.params))
        elif self.params is not None:
            object.__setattr__(self, "params", FrozenDict(self.params))
        for name in ("out", "shared_runs"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, Path(getattr(self, name)))
        if not isinstance(self.seed, int) or not 0 <= self.seed < 2**63:
            raise ValueError(f"seed must be from 0 to 2**63 - 1, got {self.seed!r}")
        if self.seeds is not None and not 1 <= self.seeds <= MAX_SEEDS:
            raise ValueError(f"seeds must be in [1, {MAX_SEEDS:,}], got {self.seeds:,}")
        if self.control_hz is not None and not 0 < self.control_hz <= 1000:  # also NaN
            raise ValueError(f"control_hz must be a number in (0, 1000] Hz, got {self.control_hz}")
        if self.workers is not None and self.workers < 1:
            raise ValueError(f"workers must be >= 1, got {self.workers}")
        if self.backend not in ("local", "ray"):
            raise ValueError(f"unknown backend {self.backend!r}; expected local or ray")

    def given(self) -> list[str]:
        """The optional settings set away from their defaults (device goes with engine, address with backend)."""
        out = [n for n in OPTIONAL if getattr(self, n) != _DEFAULTS[n]]
        out += ["engine"] * (self.device is not None) + ["backend"] * (self.address is not None)
        return list(dict.fromkeys(out))

    @property
    def rate(self) -> float:
        """Every run's control rate, Hz: ``control_hz`` where given, else the paper's
        (:data:`~neurowalk.experiments.suites.timing.SIM_HZ`)."""
        from neurowalk.experiments.suites.timing import SIM_HZ  # not at import: listing the figures imports none

        return self.control_hz if self.control_hz is not None else SIM_HZ

    def n(self, full: int, quick: int = 1) -> int:
        """Seeds per condition: ``seeds`` where given, else ``quick`` with ``quick``, else ``full``."""
        return self.seeds if self.seeds is not None else quick if self.quick else full

    def seed_range(self, full: int, quick: int = 1) -> range:
        """The seeds of each condition: :meth:`n` of them from ``seed`` on."""
        return range(self.seed, self.seed + self.n(full, quick))

    def apply(self, cfg: EpisodeConfig, fixed: Iterable[str] = ()) -> EpisodeConfig:
        """``cfg`` with the run settings that are given (body, climbing, variant, params, gait, engine, rate), but
        those ``fixed`` (names of settings a run fixes itself: a table row's own variant, say)."""
        changes: dict[str, Any] = {
            "body": self.body,
            "variant": self.variant,
            "params": self.params,
            "gait": self.gait,
            "control_hz": self.control_hz,
        }
        fixed = set(fixed)
        changes = {k: v for k, v in changes.items() if v is not None and k not in fixed}
        if self.engine != _DEFAULTS["engine"] and "engine" not in fixed:
            changes["engine"] = self.engine
        if self.climbing and "climbing" not in fixed:
            changes.update(reflexes=True, backbone=True)
        return dataclasses.replace(cfg, **changes) if changes else cfg  # plain fields: checked as a new config is

    def replace(self, **changes: Any) -> Settings:
        """A copy with ``changes``."""
        return dataclasses.replace(self, **changes)


@dataclass
class Result:
    """Numbers behind a figure: ``summary`` goes to NAME.json, ``arrays`` to NAME.npz; ``code``: the fingerprint of
    the code that computed them (:func:`neurowalk.fingerprint.code`, with a study's own file), NAME.json's ``code``;
    ``quick``: a quick result (``--quick``), NAME.json's ``quick``."""

    name: str
    summary: dict[str, Any]
    arrays: dict[str, np.ndarray] = field(default_factory=dict)
    code: str | None = None
    quick: bool | None = None


_DEFAULTS = {f.name: f.default for f in dataclasses.fields(Settings)}
Runs = Callable[[Settings], Iterable[Plan]]
Measure = Callable[[Settings, Mapping[Label, list[Any]]], "Result | dict[str, Any]"]


@dataclass(frozen=True)
class Study:
    """An experiment: what it runs, what it measures, what it draws.

    Args:
        name: its name (the files NAME.json, NAME.npz, NAME.png; the default folder ``out/NAME``).
        title: one line saying what it shows.
        plot: ``plot(result) -> Figure``: the picture of the measured result (not of the runs: a redraw needs no
            run).
        runs: ``runs(settings)`` yields a :class:`Plan` per run (its label, config and terms; none for a study of
            the network alone); :meth:`Settings.apply` is applied to each config.
        measure: ``measure(settings, {label: [Kept, ...]})`` -> :class:`Result` or a JSON-able dict (its summary):
            the numbers the picture shows, from the runs (in the order ``runs`` gave them; each
            :class:`~neurowalk.experiments.study_runs.Kept` has its summary, what its terms kept and its :class:`Plan`).
            It computes numbers only: it renders, writes and reads no file.
        render: ``render(result) -> {name: array}``: pictures made from the result's own arrays (MuJoCo snapshots
            of recorded poses), added to its arrays (NAME.npz) by the runner after ``measure``.
        videos: ``videos(settings, runs, folder) -> [path]``: with ``--video``, the runner writes the runs' videos
            into the output folder (recorded as ``videos`` in NAME.json).
        takes: the optional settings (:data:`OPTIONAL`) it honours; quick, seed and out it always takes.
        body: the body its runs have where ``--body`` names none (for the checks of settings that need a body).
        records_physics: its json says the physics its runs stepped (``physics_settings``, :func:`physics_of`) and,
            where they are kept in a store outside its folder (shared stores), that store (``store``): the figures
            do; a user's study's summary is what its ``measure`` returns, nothing added.
        claims: ``claims(summary, quick) -> [Claim]``: its results judged against a reference
            (:mod:`neurowalk.experiments.reproduce.claims`) from its saved numbers; ``neurowalk reproduce`` runs and
            judges every study that has them.
    """

    name: str
    title: str
    plot: Callable[[Result], Figure]
    runs: Runs
    measure: Measure
    render: Callable[[Result], dict[str, np.ndarray]] | None = None
    videos: Callable[[Settings, Mapping[Label, list[Any]], Path], list[str]] | None = None
    takes: Iterable[str] = RUNS_TAKE
    body: str | None = field(default=None, compare=False)  # the body its runs have unless --body says
    claims: Callable[[dict[str, Any], bool], list[Any]] | None = None
    records_physics: bool = False

    def __post_init__(self) -> None:
        unknown = set(self.takes) - set(OPTIONAL)
        object.__setattr__(self, "takes", tuple(n for n in OPTIONAL if n in set(self.takes)))
        if unknown:
            raise ValueError(f"study {self.name!r}: unknown settings {sorted(unknown)}; settings: {OPTIONAL}")
        missing = [part for part in ("plot", "runs", "measure") if not callable(getattr(self, part))]
        if missing:
            raise ValueError(f"study {self.name!r} needs {', '.join(missing)} (functions)")

    def check(self, settings: Settings) -> None:
        """ValueError naming the settings given that this study does not take, and those it does."""
        refused = [n for n in settings.given() if n not in self.takes]
        if refused:
            takes = ", ".join(self.takes) or "none but quick, seed and out"
            raise ValueError(f"study {self.name} takes no {', '.join(refused)}; it takes: {takes}")


def compute(study: Study, settings: Settings) -> Result:
    """The study's result (its runs run, or taken from its stores in ``settings.out``, and measured); ``settings``
    resolved (:func:`resolve`: :func:`run_study` and the commands resolve them).

    Raises ValueError on a setting the study does not take or a bad value (before any run), RuntimeError where runs
    failed; when stopped, :class:`~neurowalk.experiments.study_runs.RunsStopped` (a KeyboardInterrupt) with the finished
    runs it keeps (a stop before its runs began: a plain KeyboardInterrupt).
    """
    from neurowalk.experiments.study_runs import Kept, RunsStopped, run_store, store_folder, store_path
    from neurowalk.runners.specs import code_of
    from neurowalk.sim.engine_interface import EngineOptions

    study.check(settings)
    plans = planned(study, settings)
    grouped: dict[Label, list[Kept]] = {}
    kept: dict[Path, int] | None = None  # what a stop after the runs keeps (None: the study runs no episode)
    files = study_files(study, plans)
    if plans:
        with store_folder(settings.shared_runs or settings.out) as folder:
            results = run_store(
                [(p.config, p.terms) for p in plans],
                folder,
                settings.workers or 2,
                options=EngineOptions(device=settings.device),
                backend=settings.backend,
                address=settings.address,
                desc=study.name,
                files=files,
            )
            store = store_path(folder)
        for plan, r in zip(plans, results, strict=True):
            grouped.setdefault(plan.label, []).append(Kept.of(r, plan))
        kept = {store: len({p.config for p in plans})} if settings.shared_runs or settings.out else {}
    try:
        result = _measured(study, settings, grouped)
    except KeyboardInterrupt as e:
        raise RunsStopped(kept) from e
    result.code, result.quick = code_of([p.config for p in plans], files), settings.quick
    if study.records_physics and plans:
        result.summary["physics_settings"] = physics_of([k.summary for runs in grouped.values() for k in runs])
        if settings.shared_runs is not None:  # the runs are elsewhere: the json names their store
            result.summary["store"] = str(store)
    return result


def _measured(study: Study, settings: Settings, grouped: dict[Label, list[Any]]) -> Result:
    """The study's measure of its runs, with what its render and (with ``--video``) videos add."""
    measured = study.measure(settings, grouped)
    result = measured if isinstance(measured, Result) else Result(study.name, dict(measured))
    if study.render is not None:
        with profiling.part("drawing"):
            result.arrays.update(study.render(result))
    if study.videos is not None and settings.video:
        result.summary["videos"] = study.videos(settings, grouped, Path(settings.out or Path("out") / study.name))
    return result


def physics_of(summaries: Iterable[RunSummary]) -> list[dict[str, Any]]:
    """The physics the runs stepped, each distinct one once: ``{"body", "control_hz", **physics}`` (a run's
    ``physics``: the step as it ran, its substeps, integrator, solver, cone, ...); a planar body's none."""
    seen: dict[str, dict[str, Any]] = {}
    for r in summaries:
        if r.physics is None:
            continue
        rec = {"body": r.body, "control_hz": r.control_hz, **dict(r.physics)}
        seen.setdefault(json.dumps(rec, sort_keys=True), rec)
    return list(seen.values())


def grid(
    base: EpisodeConfig, seeds: Iterable[int], terms: Iterable[Term] = (), **axes: Iterable[Any]
) -> Iterator[Plan]:
    """A sweep declared in a line: ``base`` with every combination of the ``axes`` (config fields; a dotted name
    such as ``arena_opts.gap`` sets one option; the last axis varies fastest), each for every seed of ``seeds``;
    a :class:`Plan` per run, labelled by the axes' values (a tuple), each keeping ``terms``.

    ``grid(EpisodeConfig(arena="narrow-passage"), s.seed_range(10), controller=["static", "plastic"],
    **{"arena_opts.gap": [0.2, 0.3]})`` gives 40 runs, labels ``("static", 0.2)`` ... ``("plastic", 0.3)``.
    """
    names = list(axes)
    for values in itertools.product(*axes.values()):
        cfg = base.replace(**dict(zip(names, values, strict=True)))
        for seed in seeds:
            yield Plan(values, cfg.replace(seed=seed), tuple(terms))


def planned(study: Study, settings: Settings) -> list[Plan]:
    """The runs ``study`` asks for with ``settings`` (resolved), the settings applied to each config (but those the
    plan fixes: :meth:`Settings.apply`); TypeError naming the study where ``runs`` yields anything but a
    :class:`Plan`."""
    out = []
    for plan in study.runs(settings):
        if not isinstance(plan, Plan):
            raise TypeError(f"study {study.name!r}: runs must yield Plan(label, config, terms), got {plan!r:.80}")
        out.append(dataclasses.replace(plan, config=settings.apply(plan.config, plan.fixed)))
    return out


def resolve(study: Study, s: Settings) -> Settings:
    """``s`` as the runs take it: where the study takes a body and ``s`` names none, the body its other settings
    need (a legged one to climb, one the engine runs, one that runs at the control rate); a params file read (its
    fields, and its base variant where ``s`` names none). ValueError where the body it names is none of the
    registry's, or cannot; or where the params file cannot be read."""
    from neurowalk.body.registry import BODIES
    from neurowalk.neural.variants import params_variant, read_params_file
    from neurowalk.sim.config import EpisodeConfig

    body = s.body
    if "body" in study.takes:
        if body is not None and body not in BODIES:
            raise ValueError(f"unknown body {body!r}; expected one of {', '.join(BODIES)}")
        if s.climbing:
            climbers = [name for name, info in BODIES.items() if info.climbs]
            if (body or climbers[0]) not in climbers:
                raise ValueError(f"--climb needs --body {climbers[0]} (the {body!r} body has no legs)")
            body = body or climbers[0]
        if s.engine != _DEFAULTS["engine"]:
            runs = [name for name, info in BODIES.items() if s.engine in info.engines]
            if runs and (body or runs[0]) not in runs:
                raise ValueError(f"--engine {s.engine} runs --body {runs[0]}, got --body {body!r}")
            body = body or (runs[0] if runs else None)
        if s.control_hz is not None:
            try:  # a planar surrogate runs at its calibration's rate only
                EpisodeConfig(body=body or study.body or "amosii", control_hz=s.control_hz)
            except ValueError as e:
                raise ValueError(f"--control-hz {s.control_hz:g}: {e} (add --body amosii)") from None
    if isinstance(s.params, Path):
        data = read_params_file(s.params)
        return s.replace(body=body, variant=params_variant(s.params, data, s.variant), params=data["params"])
    return s.replace(body=body) if body != s.body else s


def study_files(study: Study, plans: Iterable[Plan] = ()) -> list[Path]:
    """The user's files a study's runs come from: the source files of its functions and of its plans' terms that lie
    outside the package (a study file; none for the package's figures). Their contents are part of the code its
    runs are kept under (:func:`neurowalk.fingerprint.code`)."""
    fns: list[Any] = [study.runs, study.measure, study.plot, study.render, study.videos, study.claims]
    for plan in plans:
        fns += [f for t in plan.terms for f in (t.keep, t.stream)]
    return fingerprint.user_files(*fns)


def kept_runs(study: Study, settings: Settings) -> dict[Path, int] | None:
    """The finished runs of the study's own runs with these settings that its command would go on from, by store
    file (none: empty; None: the study plans no run, the network alone)."""
    from neurowalk.experiments.study_runs import store_path
    from neurowalk.runners.specs import code_of
    from neurowalk.runners.store import count_finished

    if settings.out is None:
        return {}
    try:
        plans = planned(study, resolve(study, settings))
    except ValueError:  # settings the study refuses: it runs nothing, and says why
        return {}
    keys = {p.config.key() for p in plans}
    if not keys:
        return None
    path = store_path(settings.shared_runs or settings.out)
    n = count_finished(path, keys, code_of([p.config for p in plans], study_files(study, plans)))
    return {path: n} if n else {}


def run_study(study: Study, settings: Settings | None = None) -> tuple[Result, dict[str, Path]]:
    """Run ``study`` with ``settings`` and write NAME.json (NAME.npz) and NAME.png into ``settings.out`` (default
    ``out/NAME``); return the result and the files written.

    Its runs are kept in ``out/results.sqlite`` as they finish: stopped (Ctrl-C, SIGTERM: KeyboardInterrupt), the
    same call goes on from them and gives the same result, bit for bit.
    """
    settings = settings or Settings()
    if settings.out is None:
        settings = settings.replace(out=Path("out") / study.name)
    from neurowalk.experiments.output import write

    result = compute(study, resolve(study, settings))
    return result, write(study, result, Path(settings.out))
