"""Run specs: one run as a JSON-able dict of :class:`~neurowalk.sim.episode.EpisodeConfig` fields.

A spec names only what differs from the defaults, e.g. ``{"arena": "box", "controller": "static", "seed": 3}``.
:func:`normalize` fills in every default (the config's and the arena's options) and converts the values to their
canonical types, so that equal runs get equal keys (:func:`spec_key`) whatever the dict order, the omitted defaults
or the spelling of a number (``"0.3"``, ``0.3``; ``2``, ``2.0``). The switches added later (:data:`LATER`:
``reflexes``, ``backbone``, ``variant``, ``params``, ``gait``, ``body_opts``, ``engine``) appear in the canonical
form only when they differ from their defaults (off, ``paper``, none, ``wave``, none, ``mujoco``), so the keys of
earlier stores stay valid.
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import json
import math
from pathlib import Path
from typing import Any

from neurowalk.arenas import ARENAS, arena_options, make_arena
from neurowalk.body.registry import check_body_opts
from neurowalk.fileio import to_jsonable
from neurowalk.neural.variants import check_overrides
from neurowalk.sim.episode import Episode, EpisodeConfig, RunInterruptedError, run_episode

Spec = dict[str, Any]

#: Spec fields, in EpisodeConfig order.
FIELDS: tuple[str, ...] = tuple(f.name for f in dataclasses.fields(EpisodeConfig))
#: Summary keys that depend on the machine, not on the run: kept out of the compared result.
MACHINE_KEYS: tuple[str, ...] = ("wall_time_s", "real_time_factor")

_DEFAULTS: Spec = {f: getattr(EpisodeConfig(), f) for f in FIELDS}
#: Every field's default (a stored spec leaves out the :data:`LATER` fields at theirs).
DEFAULTS: Spec = _DEFAULTS
#: Fields kept out of the canonical form at their defaults (they came after stores were written).
LATER: tuple[str, ...] = ("reflexes", "backbone", "variant", "params", "gait", "body_opts", "engine")


def normalize(spec: Spec) -> Spec:
    """The canonical form of ``spec``: every field, defaults filled in, values of canonical type.

    Raises:
        ValueError: unknown field, unknown arena/option/controller/body, or a value of the wrong kind (the
            message names it).
    """
    if not isinstance(spec, dict):
        raise ValueError(f"a run spec is a JSON object of {', '.join(FIELDS)}; got {spec!r}")
    unknown = sorted(set(spec) - set(FIELDS))
    if unknown:
        raise ValueError(f"unknown spec field {unknown[0]!r}; fields: {', '.join(FIELDS)}")
    s = {**_DEFAULTS, **spec}
    try:
        out: Spec = {
            "arena": str(s["arena"]),
            "arena_opts": {},
            "controller": str(s["controller"]),
            "steer": None if s["steer"] is None else [_real(v, "steer") for v in s["steer"]],
            "body": str(s["body"]),
            "steps": _whole(s["steps"], "steps"),
            "seed": _whole(s["seed"], "seed"),
            "control_hz": _real(s["control_hz"], "control_hz"),
            "noise": _real(s["noise"], "noise"),
            "b0": None if s["b0"] is None else _real(s["b0"], "b0"),
            "q0": None if s["q0"] is None else _real(s["q0"], "q0"),
        }
    except (TypeError, ValueError, OverflowError) as e:
        raise ValueError(f"bad run spec {spec!r}: {e}") from None
    if not isinstance(s["arena_opts"], dict):
        raise ValueError(f"arena_opts must be an object of option values, got {s['arena_opts']!r}")
    known = arena_options(out["arena"])  # raises on an unknown arena
    opts = dict(known)
    for key, value in s["arena_opts"].items():
        if key not in known:
            raise ValueError(f"arena {out['arena']!r} has no option {key!r}; options: {', '.join(known) or 'none'}")
        kind = type(known[key])
        try:
            opts[key] = _whole(value, key) if kind is int else _real(value, key) if kind is float else kind(value)
        except (TypeError, ValueError, OverflowError):
            opts[key] = None
        if opts[key] is None or (kind is float and not math.isfinite(opts[key])):
            what = "a whole number" if kind is int else "a finite number" if kind is float else f"a {kind.__name__}"
            raise ValueError(f"arena {out['arena']!r}: option {key}={value!r} must be {what}")
    out["arena_opts"] = to_jsonable(opts)
    for key in ("reflexes", "backbone"):
        if not isinstance(s[key], bool):
            raise ValueError(f"{key} must be true or false, got {s[key]!r}")
        if s[key]:
            out[key] = True
    if not isinstance(s["variant"], str):
        raise ValueError(f"variant must be a name, got {s['variant']!r}")
    if not isinstance(s["engine"], str):
        raise ValueError(f"engine must be a name (mujoco, warp), got {s['engine']!r}")
    if not isinstance(s["gait"], str):
        raise ValueError(f"gait must be a name, got {s['gait']!r}")
    for key in ("variant", "engine", "gait"):  # names: kept where they are not the default
        if s[key] != _DEFAULTS[key]:
            out[key] = s[key]
    if s["params"] is not None:
        params = check_overrides(s["params"])  # raises on a value that is not an object of fields
        if params:
            out["params"] = params
    if not isinstance(s["body_opts"], dict):
        raise ValueError(f"body_opts must be an object of option values, got {s['body_opts']!r}")
    if s["body_opts"]:
        out["body_opts"] = check_body_opts(out["body"], s["body_opts"])  # raises on an unknown body or option
    to_config(out)  # the config's own checks (controller, body, steps, seed, steer, b0/q0)
    return out


def _whole(value: Any, name: str) -> int:
    if isinstance(value, int) and not isinstance(value, bool):
        return value  # as it is: float() would round a large one (and name another number than the one given)
    try:
        x = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{name} must be a whole number, got {value!r}") from None
    if isinstance(value, bool) or not math.isfinite(x) or x != int(x):
        raise ValueError(f"{name} must be a whole number, got {value!r}")
    return int(x)


def _real(value: Any, name: str) -> float:
    """``value`` as a float (a number or its spelling); a bool is not a number here."""
    if isinstance(value, bool):
        raise ValueError(f"{name} must be a number, got {value!r}")
    return float(value)


def to_config(spec: Spec) -> EpisodeConfig:
    """The EpisodeConfig of a (normalised) spec; raises ValueError on bad values."""
    s = dict(spec)
    if s.get("steer") is not None:
        s["steer"] = tuple(s["steer"])
    return EpisodeConfig(**s)


def spec_key(spec: Spec) -> str:
    """Key of a run: SHA-256 (64 hex digits) of the canonical JSON of :func:`normalize` (spec)."""
    text = json.dumps(normalize(spec), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def run_spec(spec: Spec) -> dict[str, Any]:
    """Run one spec to the end and return its summary (JSON-safe, without :data:`MACHINE_KEYS`).

    The result depends only on the spec (every random draw comes from its seed), so it is the same on every
    backend and worker count; the sweep measures the wall time itself and stores it beside the result.
    """
    try:
        ep = run_episode(to_config(normalize(spec)))
    except RunInterruptedError:
        raise KeyboardInterrupt from None  # Ctrl-C stops the sweep; a half run is not a result
    return result_of(ep)


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
    s = {**_DEFAULTS, **spec}
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
        s = normalize(spec)
        arena = json.dumps([s["arena"], s["arena_opts"]], sort_keys=True)
        if arena not in built:
            make_arena(s["arena"], **s["arena_opts"])
            built.add(arena)
