"""What one run is (:class:`EpisodeConfig`), what it gives (:class:`Episode`) and how it is built.

The config is checked when made (one ``ValueError`` naming the field, the value and what is allowed); the
run's Generators (body noise, controller, arena layout) are spawned from its one seed.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from neurowalk.arenas import ArenaSpec, arena_options, make_arena
from neurowalk.body.registry import BODIES as REGISTRY
from neurowalk.body.registry import body_files, body_info, check_body_opts, make_body
from neurowalk.body.surrogate import Surrogate, load_calibration
from neurowalk.body.world import Body
from neurowalk.controller import (
    CONTROLLERS,
    Controller,
    is_user_controller,
    load_controller,
    make_controller,
)
from neurowalk.fileio import to_jsonable, user_file
from neurowalk.neural.cpg import GAITS, CpgParams
from neurowalk.neural.motor import LocomotionParams
from neurowalk.neural.variants import check_overrides, get_variant
from neurowalk.progress import Progress
from neurowalk.sim.config_values import FrozenDict, real, typed_arena_opts, whole
from neurowalk.sim.run_summary import RunSummary
from neurowalk.sim.trajectory import Trajectory

BODIES: tuple[str, ...] = tuple(REGISTRY)  # the registry's names (neurowalk.body.registry)
DEFAULT_ENGINE = "mujoco"  # the CPU loop (sim/engines.py)


@dataclass(frozen=True, kw_only=True)
class EpisodeConfig:
    """One run: where, with which controller and body, how long, which seed.

    Immutable and hashable: its options are :class:`FrozenDict` s, ``steer`` a tuple. :meth:`key` names the run
    (the same in any process and version: the result store's key), :meth:`replace` makes a changed copy,
    :meth:`from_spec` reads a run spec (a JSON object) and :meth:`spec` writes its canonical one.

    Attributes:
        arena: the arena's name (``neurowalk arenas``).
        arena_opts: the arena's options (name -> value; ``neurowalk arenas`` lists them with their defaults).
        controller: plastic | static | braitenberg | fixed, or a user's ``FILE.py:NAME``
            (:func:`~neurowalk.controller.load_controller`).
        steer: (O1, O2) in [-1, 1], the constant steering of controller ``fixed`` (None for the others).
        body: the robot (``neurowalk bodies``).
        steps: control steps of the run.
        seed: the seed of every random draw of the run (sensor noise, controller, a random arena's layout).
        control_hz: control steps per second (Hz).
        noise: strength of the coloured sensor noise, in [0, 1].
        b0: the plastic network's start self weights (None: the variant's, 0 by default).
        q0: its start inhibition magnitudes (None: the variant's, 0 by default).
        reflexes: local leg control (forward models, searching and elevation reflexes).
        backbone: backbone joint control and the climbable-step decision (obstacle-height sensor).
        variant: the network: ``paper`` (Eq. 1-6 as printed), ``original`` (the authors' code), ``tuned``.
        params: SensoryParams fields set on top of the variant (a params file), or None.
        gait: the CPG's modulatory input by name (``neurowalk.neural.cpg.GAITS``).
        body_opts: the body's options (name -> number; ``neurowalk bodies``).
        engine: physics engine: ``mujoco`` (CPU MuJoCo) | ``warp`` (MuJoCo Warp, many worlds, GPU or CPU).
        until: ``"escaped"``: the run may stop at the first control step whose trunk centre is in the arena's exit
            region (its outcome is decided: :data:`UNTIL`); None (default): it runs all its steps. The CPU loop
            stops there; the other engines, and an arena without an exit region, run in full.
    """

    arena: str = "open"
    arena_opts: Mapping[str, Any] = field(default_factory=dict)
    controller: str = "plastic"
    steer: tuple[float, float] | None = None  # for controller "fixed": (O1, O2)
    body: str = "amosii"
    steps: int = 1000  # control steps
    seed: int = 0
    control_hz: float = 10.0
    noise: float = 0.02  # strength of the coloured sensor noise
    b0: float | None = None  # plastic controller: start self weights (default 0)
    q0: float | None = None  # plastic controller: start inhibition magnitudes (default 0)
    reflexes: bool = False  # local leg control: forward models, searching and elevation reflexes
    backbone: bool = False  # backbone joint control and the climbable-step decision (obstacle-height sensor)
    variant: str = "paper"  # the network: paper (Eq. 1-6 as printed), original (the authors' code), tuned
    params: Mapping[str, float] | None = None  # SensoryParams fields set on top of the variant (a params file)
    gait: str = "wave"  # the CPG's modulatory input by name (neurowalk.neural.cpg.GAITS)
    body_opts: Mapping[str, Any] = field(default_factory=dict)  # the body's options (neurowalk.body.registry)
    engine: str = DEFAULT_ENGINE  # physics engine: mujoco (CPU MuJoCo) | warp (MuJoCo Warp, many worlds, GPU or CPU)
    until: str | None = None  # "escaped": stop once the trunk is in the exit region (outcome decided); None: all steps

    def __post_init__(self) -> None:
        body_opts, params = self._check()
        canonical = {
            "arena_opts": FrozenDict(typed_arena_opts(self.arena, self.arena_opts)),
            # the body's options and the parameters as given (checked): a run's summary shows them as they came
            "body_opts": FrozenDict(self.body_opts),
            "params": None if self.params is None else FrozenDict(self.params),
            "steer": None if self.steer is None else tuple(float(v) for v in self.steer),
            "steps": int(self.steps),
            "seed": int(self.seed),
            "control_hz": float(self.control_hz),
            "noise": float(self.noise),
            "b0": None if self.b0 is None else float(self.b0),
            "q0": None if self.q0 is None else float(self.q0),
        }
        for name, value in canonical.items():
            object.__setattr__(self, name, value)
        # the canonical spec's parts of the options (spec()), made once: every arena option filled in (JSON text),
        # the body's options as numbers or names, the parameters checked
        parts = {
            "arena_opts": json.dumps(to_jsonable({**arena_options(self.arena), **self.arena_opts})),
            "body_opts": body_opts,
            "params": params if self.params else None,
        }
        object.__setattr__(self, "_spec_parts", parts)

    def _check(self) -> tuple[dict[str, Any], dict[str, Any] | None]:
        """Every field's value, each against the others (ValueError naming the field, the value, what is allowed);
        the body's options and the parameters as they check out (numbers, a named option as its name)."""
        for name in ("arena", "controller", "body", "variant", "gait", "engine"):
            if not isinstance(getattr(self, name), str):
                raise ValueError(f"{name} must be a name, got {getattr(self, name)!r}")
        for name in ("reflexes", "backbone"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"{name} must be true or false, got {getattr(self, name)!r}")
        for name in ("arena_opts", "body_opts"):
            if not isinstance(getattr(self, name), Mapping):
                raise ValueError(f"{name} must be an object of option values, got {getattr(self, name)!r}")
        if is_user_controller(self.controller):
            load_controller(self.controller)  # the file runs once here: an error names the file and its line
            if self.reflexes or self.backbone:
                raise ValueError("reflexes and backbone control go with the built-in controllers")
        elif self.controller not in CONTROLLERS:
            raise ValueError(
                f"unknown controller {self.controller!r}; expected one of {', '.join(CONTROLLERS)}, or FILE.py:NAME"
            )
        info = body_info(self.body)  # raises on an unknown body
        body_opts = check_body_opts(self.body, dict(self.body_opts))
        params = check_overrides(self.params) if self.params is not None else None
        if not _whole(self.steps) or not 1 <= self.steps <= MAX_STEPS:
            raise ValueError(f"steps must be a whole number from 1 to {MAX_STEPS:,}, got {self.steps!r}")
        if not _whole(self.seed) or not 0 <= self.seed < 2**63:
            raise ValueError(f"seed must be a whole number from 0 to 2**63 - 1, got {self.seed!r}")
        if not _number(self.control_hz) or not 0 < self.control_hz <= 1000:
            raise ValueError(f"control_hz must be a number in (0, 1000] Hz, got {self.control_hz!r}")
        if not _number(self.noise) or not 0 <= self.noise <= 1:
            raise ValueError(f"noise must be a number in [0, 1] (strength of the sensor noise), got {self.noise!r}")
        for name in ("b0", "q0"):
            v = getattr(self, name)
            if v is not None and (not _number(v) or v < 0):
                raise ValueError(f"{name} must be a number >= 0 (a start weight), got {v!r}")
        if self.steer is not None and (
            len(self.steer) != 2 or not all(_number(v) and -1 <= v <= 1 for v in self.steer)
        ):
            raise ValueError(f"steer must be two numbers O1, O2 in [-1, 1], got {list(self.steer)!r}")
        if (self.b0 is not None or self.q0 is not None) and self.controller != "plastic":
            raise ValueError("start weights b0/q0 go with controller 'plastic' only")
        if (self.controller == "fixed") != (self.steer is not None):
            raise ValueError("--steer O1,O2 goes with controller 'fixed' (and only with it)")
        if (self.reflexes or self.backbone) and not info.climbs:
            raise ValueError(f"reflexes and backbone control need body 'amosii' (legs and terrain), got {self.body!r}")
        get_variant(self.variant, self.params)  # raises on an unknown variant or a bad parameter
        if self.gait not in GAITS:
            raise ValueError(f"unknown gait {self.gait!r}; expected one of {', '.join(GAITS)}")
        if self.engine not in (names := engine_names()):
            raise ValueError(f"unknown engine {self.engine!r}; expected one of {', '.join(names)}")
        if self.until is not None and (not isinstance(self.until, str) or self.until not in UNTIL):
            raise ValueError(f"until must be one of {', '.join(UNTIL)} or none, got {self.until!r}")
        climbing = self.reflexes or self.backbone
        if self.engine not in info.engines or (climbing and self.engine not in info.climbs_on):
            raise ValueError(engine_refusal(self.engine, self.body, climbing))
        if not info.physics and self.control_hz != (hz := load_calibration(body=self.body).control_hz):
            raise ValueError(f"body {self.body!r} is calibrated at {hz} Hz, got control_hz {self.control_hz!r}")
        info.check_gait(self.gait)
        return body_opts, params

    @property
    def climbing(self) -> bool:
        """The controller climbs: local leg control or backbone joint control is on."""
        return self.reflexes or self.backbone

    def replace(self, **changes: Any) -> EpisodeConfig:
        """A copy with ``changes``; a dotted name changes one entry of an option field, e.g.
        ``cfg.replace(seed=3, **{"arena_opts.gap": 0.6, "params.mu_b": 0.01})`` (checked as a new config is)."""
        fields: dict[str, Any] = {}
        for name, value in changes.items():
            top, dot, entry = name.partition(".")
            if dot:
                if top not in ("arena_opts", "body_opts", "params"):
                    raise ValueError(f"{name!r}: only arena_opts, body_opts and params have entries to change")
                base = fields.get(top, getattr(self, top)) or {}
                fields[top] = {**base, entry: value}
            else:
                fields[name] = value
        unknown = sorted(set(fields) - set(FIELDS))
        if unknown:
            raise ValueError(f"unknown config field {unknown[0]!r}; fields: {', '.join(FIELDS)}")
        return dataclasses.replace(self, **fields)

    def spec(self) -> dict[str, Any]:
        """The canonical run spec: JSON values, the arena's options all filled in, and the fields added after the
        first stores (:data:`LATER`) only where they differ from their defaults, so that older keys stay valid."""
        parts = self._spec_parts  # type: ignore[attr-defined]
        out: dict[str, Any] = {
            "arena": self.arena,
            "arena_opts": json.loads(parts["arena_opts"]),
            "controller": self.controller,
            "steer": None if self.steer is None else list(self.steer),
            "body": self.body,
            "steps": self.steps,
            "seed": self.seed,
            "control_hz": self.control_hz,
            "noise": self.noise,
            "b0": self.b0,
            "q0": self.q0,
        }
        for name in LATER:
            value = parts[name] if name in ("body_opts", "params") else getattr(self, name)
            if value and value != DEFAULTS[name]:
                out[name] = to_jsonable(value)
        return out

    def files(self) -> tuple[Path, ...]:
        """The user's files the run reads (a user's MJCF body, controller or learning rule): their bytes are part of its
        fingerprint (:func:`neurowalk.fingerprint.code`)."""
        found = (user_file(self.controller), user_file(self.variant))
        return (*body_files(self.body), *(f for f in found if f is not None))

    def key(self) -> str:
        """The run's name: SHA-256 (64 hex digits) of its canonical spec's JSON (equal runs, equal keys, in any
        process)."""
        text = json.dumps(self.spec(), sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()

    @classmethod
    def from_spec(cls, spec: Mapping[str, Any]) -> EpisodeConfig:
        """The config of a run spec: a JSON object of the fields that differ from the defaults, numbers in any
        spelling (``"0.3"``, ``0.3``; ``2``, ``2.0``). ValueError names an unknown field or a bad value."""
        if not isinstance(spec, Mapping):
            raise ValueError(f"a run spec is a JSON object of {', '.join(FIELDS)}; got {spec!r}")
        unknown = sorted(set(spec) - set(FIELDS))
        if unknown:
            raise ValueError(f"unknown spec field {unknown[0]!r}; fields: {', '.join(FIELDS)}")
        s = dict(spec)
        try:
            for name in ("steps", "seed"):
                if name in s:
                    s[name] = whole(s[name], name)
            for name in ("control_hz", "noise", "b0", "q0"):
                if s.get(name) is not None:
                    s[name] = real(s[name], name)
            if s.get("steer") is not None:
                s["steer"] = tuple(real(v, "steer") for v in s["steer"])
        except (TypeError, ValueError, OverflowError) as e:
            raise ValueError(f"bad run spec {dict(spec)!r}: {e}") from None
        for name in ("arena_opts", "body_opts"):
            if s.get(name) is None:
                s.pop(name, None)
        return cls(**s)


def engine_refusal(engine: str, body: str, climbing: bool) -> str:
    """Why ``engine`` cannot run ``body`` (with climbing controls if ``climbing``): the bodies it runs, in words."""
    runs = [name for name, info in REGISTRY.items() if engine in info.engines]
    climbs = any(engine in REGISTRY[name].climbs_on for name in runs)
    return (
        f"engine {engine!r} runs body {', '.join(repr(n) for n in runs)}"
        + ("" if climbs else " without --reflexes/--backbone")
        + f", got body {body!r}"
        + (" with climbing controls" if climbing else "")
    )


def engine_names() -> tuple[str, ...]:
    """The engines a config may name: those the bodies run on (their ``BodyInfo.engines``), in the registry's order.
    The engines themselves are the one table :data:`neurowalk.sim.engines.ENGINES` (the suite holds the two equal)."""
    return tuple(dict.fromkeys(name for info in REGISTRY.values() for name in info.engines))


#: The config's fields, in order.
FIELDS: tuple[str, ...] = tuple(f.name for f in dataclasses.fields(EpisodeConfig))
#: Every field's default.
DEFAULTS: dict[str, Any] = {
    f.name: f.default if f.default_factory is dataclasses.MISSING else f.default_factory()
    for f in dataclasses.fields(EpisodeConfig)
}
#: Fields kept out of the canonical spec at their defaults (they came after stores were written).
LATER: tuple[str, ...] = ("reflexes", "backbone", "variant", "params", "gait", "body_opts", "engine", "until")
#: What may end a run before its steps (``EpisodeConfig.until``): name -> the rule, in words.
UNTIL: dict[str, str] = {
    "escaped": "the run stops at the first control step whose trunk centre is in the arena's exit region (escaped: "
    "the outcome is decided; later steps could not change it)",
}
MAX_STEPS = 100_000_000  # control steps of one run (about 116 days simulated at 10 Hz)


def _number(v: object) -> bool:
    """A finite real number (not a bool)."""
    return isinstance(v, int | float) and not isinstance(v, bool) and (isinstance(v, int) or math.isfinite(v))


def _whole(v: object) -> bool:
    """A finite whole number (not a bool)."""
    return isinstance(v, int | float) and _number(v) and (isinstance(v, int) or float(v) == int(v))


@dataclass
class Episode:
    """A finished run.

    Attributes:
        config: the run's config.
        arena: the arena it ran in, built (boxes, start pose, exit region).
        trajectory: its rows (:class:`~neurowalk.sim.trajectory.Trajectory`: pose, inputs, outputs, weights, joints).
        summary: the dict of ``summary.json`` (:attr:`result` reads it by attribute).
        row_stride: the trajectory holds every ``row_stride``-th control step (1: all; a streamed run keeps fewer).
    """

    config: EpisodeConfig
    arena: ArenaSpec
    trajectory: Trajectory
    summary: dict[str, Any]
    row_stride: int = 1  # the trajectory holds every row_stride-th control step (1: all; see run_episode)

    @property
    def result(self) -> RunSummary:
        """The summary, typed: ``ep.result.escaped``, ``ep.result.exit_s``, ``ep.result.wedged_periods``, ..."""
        return RunSummary.from_dict(self.summary)


def seeds(cfg: EpisodeConfig) -> tuple[np.random.Generator, np.random.Generator, np.random.Generator]:
    """Generators of the body (sensor noise), the controller and the arena layout, from the run's seed."""
    body, ctrl, arena = (np.random.default_rng(s) for s in np.random.SeedSequence(cfg.seed).spawn(3))
    return body, ctrl, arena


def build(cfg: EpisodeConfig, *, pad_boxes: int | None = None) -> tuple[ArenaSpec, Body | Surrogate, Controller]:
    """Arena, body (see :mod:`neurowalk.body.registry`) and controller of a config (raises ValueError on bad input).

    ``pad_boxes``: build AMOSII's model with that many obstacle slots (``AmosII(pad_boxes=...)``), the model
    :mod:`neurowalk.sim.batch` runs; None (default) for the plain model.
    """
    arena = make_arena(cfg.arena, rng=seeds(cfg)[2], **cfg.arena_opts)
    body = make_body(
        cfg.body,
        arena,
        cfg.body_opts,
        control_hz=cfg.control_hz,
        noise=cfg.noise,
        climbing=cfg.climbing,
        pad_boxes=pad_boxes,
    )
    return arena, body, build_controller(cfg)


def build_controller(cfg: EpisodeConfig) -> Controller:
    """The controller of a config (its network variant, gait, climbing modules, start weights)."""
    weights = {k: v for k, v in (("b0", cfg.b0), ("q0", cfg.q0)) if v is not None}
    climbing = {k: True for k in ("reflexes", "backbone") if getattr(cfg, k)}
    v = get_variant(cfg.variant, cfg.params)
    gait = LocomotionParams(cpg=CpgParams.for_gait(cfg.gait))
    kwargs: dict[str, Any] = {**weights, **climbing, "locomotion": v.locomotion(gait)}
    if is_user_controller(cfg.controller):
        return make_controller(cfg.controller)
    if cfg.controller != "fixed":
        kwargs["sensory"] = v.sensory
        if v.rule is not None:
            kwargs["rule"] = v.rule
    return make_controller(cfg.controller, steer=cfg.steer, **kwargs)


class RunInterruptedError(Exception):
    """A run stopped part-way (e.g. Ctrl-C); ``episode`` holds the steps it completed."""

    def __init__(self, episode: Episode) -> None:
        super().__init__(f"run stopped after {episode.summary['steps']} of {episode.config.steps} steps")
        self.episode = episode


def progress_bar(total: int, on: bool, desc: str = "episode", initial: int = 0) -> Progress | None:
    """A bar over ``total`` control steps, ``initial`` of them done before (a resumed run), or None when ``on`` is
    false. Its rate and time left count from its first update on (:class:`~neurowalk.progress.Progress`): the first
    steps carry the kernels' compile on a cold cache."""
    if not on:
        return None
    return Progress(total=total, initial=initial, unit="step", desc=desc, mininterval=0.5, smoothing=0.1)
