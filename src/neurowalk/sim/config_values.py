"""The values of a run's config (:class:`~neurowalk.sim.config.EpisodeConfig`): options frozen once made
(:class:`FrozenDict`), and numbers read in any spelling (``2``, ``2.0``, ``"2"``) with an error naming the field.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from neurowalk.arenas import arena_options

__all__ = ["FrozenDict", "freeze", "real", "typed_arena_opts", "whole"]


class FrozenDict(dict):
    """A dict that cannot change once made, so that a config holding it can be hashed: a config's options.

    It reads as a dict (``json.dumps``, ``==`` with a dict, ``**`` into a call); every change raises TypeError.
    Nested dicts and lists are frozen too (into FrozenDicts and tuples).
    """

    __slots__ = ()

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        for k, v in dict.items(self):
            dict.__setitem__(self, k, freeze(v))

    def _refuse(self, *args: object, **kwargs: object) -> None:
        raise TypeError("a config's options cannot change once it is made; make another with EpisodeConfig.replace")

    __setitem__ = __delitem__ = clear = pop = popitem = setdefault = update = __ior__ = _refuse  # type: ignore[assignment]

    def __hash__(self) -> int:  # type: ignore[override]
        return hash(tuple(sorted(self.items())))

    def __reduce__(self) -> tuple[Any, ...]:  # pickle's default for a dict subclass would set the items one by one
        return (FrozenDict, (dict(self),))

    def __copy__(self) -> FrozenDict:
        return self

    def __deepcopy__(self, memo: dict[int, object]) -> FrozenDict:
        return self


def freeze(v: Any) -> Any:
    """``v`` with its dicts made FrozenDicts and its lists tuples, at any depth."""
    if isinstance(v, FrozenDict):
        return v
    if isinstance(v, Mapping):
        return FrozenDict(v)
    if isinstance(v, list | tuple):
        return tuple(freeze(x) for x in v)
    return v


def typed_arena_opts(arena: str, opts: Mapping[str, Any]) -> dict[str, Any]:
    """``opts`` of ``arena`` each as its option's type (a whole number, a finite number, ...), in any spelling;
    ValueError names an unknown arena or option, or a value of the wrong kind."""
    known = arena_options(arena)  # raises on an unknown arena
    out: dict[str, Any] = {}
    for key, value in opts.items():
        if key not in known:
            raise ValueError(f"arena {arena!r} has no option {key!r}; options: {', '.join(known) or 'none'}")
        kind = type(known[key])
        try:
            out[key] = whole(value, key) if kind is int else real(value, key) if kind is float else kind(value)
        except (TypeError, ValueError, OverflowError):
            out[key] = None
        if out[key] is None or (kind is float and not math.isfinite(out[key])):
            what = "a whole number" if kind is int else "a finite number" if kind is float else f"a {kind.__name__}"
            raise ValueError(f"arena {arena!r}: option {key}={value!r} must be {what}")
    return out


def whole(value: Any, name: str) -> int:
    """``value`` as an int (a whole number or its spelling: ``2``, ``2.0``, ``"2"``); ValueError naming ``name``."""
    if isinstance(value, int) and not isinstance(value, bool):
        return value  # as it is: float() would round a large one (and name another number than the one given)
    try:
        x = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{name} must be a whole number, got {value!r}") from None
    if isinstance(value, bool) or not math.isfinite(x) or x != int(x):
        raise ValueError(f"{name} must be a whole number, got {value!r}")
    return int(x)


def real(value: Any, name: str) -> float:
    """``value`` as a float (a number or its spelling); a bool is not a number here."""
    if isinstance(value, bool):
        raise ValueError(f"{name} must be a number, got {value!r}")
    return float(value)
