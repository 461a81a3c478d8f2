"""Named arenas: a registry of factories ``name(**options) -> ArenaSpec``.

Options are the factories' keyword arguments (metres and degrees), listed by ``neurowalk arenas``.
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Callable
from functools import cache

import numpy as np

from neurowalk.arenas.spec import ArenaSpec, Box

ArenaFactory = Callable[..., ArenaSpec]
ARENAS: dict[str, ArenaFactory] = {}


def arena(name: str) -> Callable[[ArenaFactory], ArenaFactory]:
    """Register an arena factory under ``name``."""

    def deco(fn: ArenaFactory) -> ArenaFactory:
        ARENAS[name] = fn
        return fn

    return deco


def arena_options(name: str) -> dict[str, float]:
    """Options of arena ``name`` with their defaults."""
    return _defaults(_factory(name))


@cache
def _takes(fn: ArenaFactory) -> dict[str, inspect.Parameter]:
    """A factory's parameters (read once: a signature costs some 10 us, and every run builds its arena)."""
    return dict(inspect.signature(fn).parameters)


def _defaults(fn: ArenaFactory) -> dict[str, float]:
    """A factory's options and their defaults."""
    return {k: p.default for k, p in _takes(fn).items() if k != "rng"}


def _factory(name: str) -> ArenaFactory:
    if name not in ARENAS:
        raise ValueError(f"unknown arena {name!r}; available: {', '.join(sorted(ARENAS))}")
    return ARENAS[name]


def make_arena(name: str, *, rng: np.random.Generator | None = None, **options: object) -> ArenaSpec:
    """Build arena ``name``; unknown or non-finite options or impossible geometry raise ValueError naming them.

    Arenas drawn at random (e.g. ``random``) take their layout from ``rng``.
    """
    known = arena_options(name)
    for key in options:
        if key not in known:
            raise ValueError(f"arena {name!r} has no option {key!r}; options: {', '.join(known) or 'none'}")
    values = {}
    for key, value in options.items():
        try:
            values[key] = type(known[key])(value)
        except (TypeError, ValueError):
            raise ValueError(f"arena {name!r}: option {key}={value!r} is not a {type(known[key]).__name__}") from None
        if isinstance(values[key], float) and not math.isfinite(values[key]):
            raise ValueError(f"arena {name!r}: option {key}={value!r} must be a finite number")
    fn = _factory(name)
    if "rng" in _takes(fn):
        values_rng = {**values, "rng": rng if rng is not None else np.random.default_rng(0)}
        spec = fn(**values_rng)
    else:
        spec = fn(**values)
    return ArenaSpec(**{**spec.__dict__, "options": {**known, **values}})


from neurowalk.arenas import basic, climbing, deadlocks, generated, original  # noqa: E402, F401  (fill the registry)

__all__ = ["ARENAS", "ArenaSpec", "Box", "arena", "arena_options", "make_arena"]
