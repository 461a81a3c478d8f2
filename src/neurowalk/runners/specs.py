"""Run specs: one run as a JSON-able dict of :class:`~neurowalk.sim.episode.EpisodeConfig` fields.

A spec names only what differs from the defaults, e.g. ``{"arena": "box", "controller": "static", "seed": 3}``.
:meth:`EpisodeConfig.from_spec <neurowalk.sim.config.EpisodeConfig.from_spec>` reads one (the one validator of a
run), and :meth:`~neurowalk.sim.config.EpisodeConfig.spec` writes its canonical form, every default filled in and
every value of canonical type, so that equal runs get equal keys (:func:`spec_key`) whatever the dict order, the
omitted defaults or the spelling of a number (``"0.3"``, ``0.3``; ``2``, ``2.0``). The switches added later
(:data:`LATER`) appear in the canonical form only where they differ from their defaults, so the keys of earlier
stores stay valid.
"""

from __future__ import annotations

import itertools
import json
from collections.abc import Iterable
from dataclasses import replace
from pathlib import Path
from typing import Any

from neurowalk import fingerprint
from neurowalk.arenas import ARENAS, arena_options, make_arena
from neurowalk.fileio import to_jsonable
from neurowalk.runners.stopping import stop_requested
from neurowalk.sim.config import DEFAULTS, FIELDS, LATER
from neurowalk.sim.episode import Episode, EpisodeConfig, RunInterruptedError, Streaming, run_episode

__all__ = ["DEFAULTS", "FIELDS", "LATER", "MACHINE_KEYS", "Spec", "check_specs", "code_of", "config_of", "describe",
           "episode_of", "grid", "read_jsonl", "result_of", "run_spec", "spec_key"]  # fmt: skip

Spec = dict[str, Any]

#: Summary keys that depend on the machine, not on the run: kept out of the compared result.
MACHINE_KEYS: tuple[str, ...] = ("wall_time_s", "real_time_factor")


def spec_key(spec: Spec) -> str:
    """Key of a run: :meth:`EpisodeConfig.key` of the spec's config (SHA-256 of its canonical spec)."""
    return EpisodeConfig.from_spec(spec).key()


def code_of(configs: Iterable[EpisodeConfig], files: Iterable[Path | str] = ()) -> str:
    """The fingerprint (:func:`neurowalk.fingerprint.code`) a store keeps the runs of ``configs`` under: the package,
    its libraries, the user's ``files`` (a study's) and the files the runs read (a user's MJCF robot, a user's
    controller: :meth:`EpisodeConfig.files`)."""
    found = [Path(f) for f in files]
    for cfg in configs:
        found += cfg.files()
    return fingerprint.code(found)


def config_of(spec: Spec | EpisodeConfig) -> EpisodeConfig:
    """The config of a run: a spec's, made and checked here (it crossed a process or store boundary as JSON), or a
    config carried as it is (a run in the process that made it)."""
    return spec if isinstance(spec, EpisodeConfig) else EpisodeConfig.from_spec(spec)


def episode_of(spec: Spec | EpisodeConfig, stream: Streaming | None = None) -> Episode:
    """Run one spec (or config) to the end (``stream``: streamed, as :func:`~neurowalk.sim.episode.run_episode`); a stop
    (Ctrl-C) raises KeyboardInterrupt, for a half run is not a result. The run asks :func:`stop_requested` as it
    goes unless ``stream`` asks something else (a stop whose KeyboardInterrupt a library swallowed)."""
    stream = stream or Streaming()
    if stream.stop is None:
        stream = replace(stream, stop=stop_requested)
    try:
        return run_episode(config_of(spec), stream=stream)
    except RunInterruptedError:
        raise KeyboardInterrupt from None


def run_spec(spec: Spec | EpisodeConfig) -> dict[str, Any]:
    """Run one spec (or config) to the end and return its summary (JSON-safe, without :data:`MACHINE_KEYS`).

    The result depends only on the spec (every random draw comes from its seed), so it is the same on every
    backend and worker count; the sweep measures the wall time itself and stores it beside the result.
    """
    return result_of(episode_of(spec))  # Ctrl-C stops the sweep


def result_of(ep: Episode) -> dict[str, Any]:
    """A run's stored result: its summary, JSON-safe, without :data:`MACHINE_KEYS`."""
    summary = to_jsonable(ep.summary)
    for k in MACHINE_KEYS:
        summary.pop(k, None)
    return summary


def grid(base: Spec, **axes: list[Any]) -> list[Spec]:
    """Cartesian product of ``axes`` over ``base``: one spec per combination, the last axis varying fastest.

    An axis named ``arena_opts.KEY`` (``body_opts.KEY``) sets one arena (body) option, e.g.
    ``grid({"arena": "box"}, seed=[0, 1], **{"arena_opts.gap": [0.3, 0.4]})`` gives 4 specs.
    """
    names = list(axes)
    out = []
    for values in itertools.product(*(axes[n] for n in names)):
        s = {**base, "arena_opts": dict(base.get("arena_opts", {}))}
        if "body_opts" in base or any(n.startswith("body_opts.") for n in names):
            s["body_opts"] = dict(base.get("body_opts", {}))
        for name, value in zip(names, values, strict=True):
            group, dot, key = name.partition(".")
            if dot and group in ("arena_opts", "body_opts"):
                s[group][key] = value
            else:
                s[name] = value
        out.append(s)
    return out


def read_jsonl(path: Path) -> list[Spec]:
    """Specs from a JSON-lines file (one object per line; blank lines and ``#`` lines skipped).

    Raises:
        ValueError: unreadable file or a line that is not a JSON object (names the file and line).
    """
    try:
        lines = Path(path).read_text().splitlines()
    except (OSError, UnicodeDecodeError) as e:
        raise ValueError(f"cannot read specs file {str(path)!r}: {e}") from None
    specs = []
    for n, line in enumerate(lines, 1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        try:
            spec = json.loads(line)
        except json.JSONDecodeError as e:
            raise ValueError(f"{path}:{n}: not JSON ({e.msg})") from None
        except RecursionError:
            raise ValueError(f"{path}:{n}: not a spec (JSON nested too deeply)") from None
        if not isinstance(spec, dict):
            raise ValueError(f"{path}:{n}: a spec is a JSON object, got {line.strip()[:60]!r}")
        specs.append(spec)
    return specs


def describe(spec: Spec) -> str:
    """A short human description of a spec, e.g. ``box gap=0.3 plastic amosii seed=3 steps=300``."""
    s = {**DEFAULTS, **spec}
    defaults = arena_options(s["arena"]) if s["arena"] in ARENAS else {}
    given = {k: v for k, v in (spec.get("arena_opts") or {}).items() if k not in defaults or defaults[k] != v}
    opts = " ".join(f"{k}={v}" for k, v in given.items())
    variant = "" if s.get("variant", "paper") == "paper" else f"variant={s['variant']}"
    parts = [s["arena"], opts, s["controller"], variant, s["body"], f"seed={s['seed']}", f"steps={s['steps']}"]
    return " ".join(p for p in parts if p)


def check_specs(specs: list[Spec]) -> None:
    """:func:`check_spec` every spec, building each distinct arena once; raises ValueError on the first bad one."""
    built: set[str] = set()
    for spec in specs:
        s = EpisodeConfig.from_spec(spec).spec()
        arena = json.dumps([s["arena"], s["arena_opts"]], sort_keys=True)
        if arena not in built:
            make_arena(s["arena"], **s["arena_opts"])
            built.add(arena)
