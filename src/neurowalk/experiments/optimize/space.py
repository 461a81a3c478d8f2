"""The search space and the fitness rule of ``neurowalk optimize`` (CMA-ES over SensoryParams fields).

Search space: each searched field is one coordinate u in [0, 1] (CMA-ES keeps its samples inside by its
bound transform). The learning and scaling rates (``mu_b``, ``mu_q``, ``gamma_b``, ``gamma_q``) map on a log
scale, value = lo * (hi / lo) ** u, so that a step of u is the same factor everywhere; every other field,
and a rate whose lower bound is 0, maps linearly, value = lo + u * (hi - lo). Values are rounded to 6
significant digits before they go into a run spec (the spec, its store key and ``best.json`` agree).

Fitness (maximised) of a candidate, from its runs:

* ``success_rate``: share of the training environments where the robot is not stuck at the end (Table 2 rule);
* feasible: every dead-end run of the escape suite escaped;
* ``fitness`` = success_rate where feasible, else success_rate - 1 - share of dead-end runs not escaped, a
  number in [-2, 0): every infeasible candidate ranks below every feasible one, and among infeasible ones
  fewer missed escapes rank higher.

CMA-ES minimises ``score`` = -(fitness + w * mean coverage of the training runs) with w = 0.5 / max(training
environments, dead-end runs): the coverage only breaks ties between equal counts (it is worth less than one
environment or one escape), so that the search still has a direction on a plateau of equal success counts.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from neurowalk.neural.variants import TUNABLE, get_variant

#: Variants a search can start from (the tuned variant is itself a search's result).
BASES: tuple[str, ...] = ("paper", "original")
#: Fields searched unless others are named: the learning rule's rates and offset (DESIGN §3, Eq. 3-4).
DEFAULT_FIELDS: tuple[str, ...] = ("mu_b", "mu_q", "gamma_b", "gamma_q", "k")
#: Default bounds (lo, hi) of every tunable field, around the paper's values (mu_b 0.0065, mu_q 0.015,
#: gamma 0.0003, k -0.01, a 4.7; the rates span about a factor 6-10 either way).
DEFAULT_BOUNDS: dict[str, tuple[float, float]] = {
    "mu_b": (0.001, 0.04),
    "mu_q": (0.002, 0.1),
    "gamma_b": (3e-5, 3e-3),
    "gamma_q": (3e-5, 3e-3),
    "k": (-0.1, 0.0),
    "a": (2.0, 8.0),
    "reflex_threshold": (-0.9, 0.0),
    "activity_cutoff": (0.0, 0.05),
    "us_near": (0.0, 0.2),
    "b_start": (0.0, 5.0),
    "q_start": (0.0, 8.0),
}
#: Fields searched on a log scale (where their lower bound is > 0).
LOG_FIELDS: tuple[str, ...] = ("mu_b", "mu_q", "gamma_b", "gamma_q")
DIGITS = 6  # significant digits of a candidate's values
FITNESS_RULE = (
    "fitness = share of training environments not stuck at the end (Table 2 rule) where every dead-end run "
    "escaped (feasible); else that share - 1 - share of dead-end runs not escaped (in [-2, 0), below every "
    "feasible one). CMA-ES minimises -(fitness + 0.5/max(environments, dead-end runs) x mean training coverage): "
    "coverage breaks ties only"
)


@dataclass(frozen=True)
class Dim:
    """One searched field: ``name`` in [``lo``, ``hi``] (the field's units), on ``scale`` 'log' or 'linear'."""

    name: str
    lo: float
    hi: float
    scale: str

    def decode(self, u: float) -> float:
        """The field's value at normalised coordinate ``u`` (clipped to [0, 1]), rounded to :data:`DIGITS`."""
        u = min(1.0, max(0.0, float(u)))
        v = self.lo * (self.hi / self.lo) ** u if self.scale == "log" else self.lo + u * (self.hi - self.lo)
        return float(f"{min(self.hi, max(self.lo, v)):.{DIGITS}g}")

    def encode(self, value: float) -> float:
        """Normalised coordinate of ``value`` (clipped into the bounds first)."""
        v = min(self.hi, max(self.lo, float(value)))
        if self.scale == "log":
            return math.log(v / self.lo) / math.log(self.hi / self.lo)
        return (v - self.lo) / (self.hi - self.lo)

    def describe(self) -> dict[str, Any]:
        """JSON-able description: {"lo", "hi", "scale"}."""
        return {"lo": self.lo, "hi": self.hi, "scale": self.scale}


def parse_bounds(text: str) -> tuple[str, tuple[float, float] | None]:
    """``FIELD=LO:HI`` -> (field, (lo, hi)); ``FIELD`` alone -> (field, None): its default bounds.

    Raises:
        ValueError: no field name, or bounds that are not two numbers ``LO:HI`` (names the text).
    """
    name, sep, rest = str(text).partition("=")
    name = name.strip()
    if not name:
        raise ValueError(f"--param expects FIELD=LO:HI, got {text!r}")
    if not sep:
        return name, None
    lo_text, colon, hi_text = rest.partition(":")
    try:
        if not colon:
            raise ValueError
        return name, (float(lo_text), float(hi_text))
    except ValueError:
        raise ValueError(f"--param {text!r}: bounds must be two numbers LO:HI, e.g. {name}=0.001:0.03") from None


def make_space(
    base: str, fields: Sequence[str] | None = None, bounds: Mapping[str, tuple[float, float] | None] | None = None
) -> tuple[Dim, ...]:
    """The searched fields: ``fields`` (default :data:`DEFAULT_FIELDS`) plus those given ``bounds``, in that order.

    Args:
        base: the base variant ('paper' or 'original'); each bound must be a value its parameters accept.
        fields: names of :data:`~neurowalk.neural.variants.TUNABLE` fields.
        bounds: {field: (lo, hi)} overriding :data:`DEFAULT_BOUNDS` (None: the default bounds).

    Raises:
        ValueError: unknown field or variant, lo >= hi, a non-finite bound, or a bound the parameters refuse
            (e.g. a negative rate); the message names the value.
    """
    if base not in BASES:
        raise ValueError(f"base variant must be {' or '.join(map(repr, BASES))}, got {base!r}")
    names = list(DEFAULT_FIELDS if fields is None else fields)
    for name in bounds or {}:
        if name not in names:
            names.append(name)
    if not names:
        raise ValueError("no fields to search: name at least one SensoryParams field")
    dims = []
    for name in names:
        if name not in TUNABLE:
            raise ValueError(f"unknown field {name!r}; tunable fields: {', '.join(TUNABLE)}")
        if names.count(name) > 1:
            raise ValueError(f"field {name!r} is named twice")
        given = (bounds or {}).get(name)
        lo, hi = (float(v) for v in (given if given is not None else DEFAULT_BOUNDS[name]))
        if not (math.isfinite(lo) and math.isfinite(hi)):
            raise ValueError(f"bounds of {name} must be finite numbers, got {lo:g}:{hi:g}")
        if lo >= hi:
            raise ValueError(f"bounds of {name} need lo < hi, got {lo:g}:{hi:g}")
        for v in (lo, hi):
            try:
                get_variant(base, {name: v})
            except ValueError as e:
                raise ValueError(f"bounds of {name} ({lo:g}:{hi:g}): {e}") from None
        dims.append(Dim(name, lo, hi, "log" if name in LOG_FIELDS and lo > 0 else "linear"))
    return tuple(dims)


def decode(space: Sequence[Dim], x: Sequence[float] | np.ndarray) -> dict[str, float]:
    """Field values {name: value} of a normalised point ``x``, shape (len(space),)."""
    return {d.name: d.decode(u) for d, u in zip(space, np.asarray(x, dtype=float), strict=True)}


def start_point(space: Sequence[Dim], base: str) -> np.ndarray:
    """Normalised coordinates, shape (len(space),), of the base variant's own values (clipped into the bounds)."""
    sensory = get_variant(base).sensory
    out = []
    for d in space:
        v = getattr(sensory, d.name)
        out.append(d.encode(v if v is not None else d.lo))  # b_start/q_start None: start at lo
    return np.array(out)


def fitness(train: Sequence[Mapping[str, Any]], deadends: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """A candidate's fitness from the summaries of its training runs and its dead-end runs (see module doc).

    Returns:
        {"fitness", "score" (what CMA-ES minimises), "feasible", "success", "environments", "success_rate",
        "escaped", "deadend_runs", "mean_coverage"}.
    """
    n, m = len(train), len(deadends)
    success = sum(not r["trapped"] for r in train)
    escaped = sum(bool(r["escaped"]) for r in deadends)
    rate = success / n if n else 0.0
    feasible = escaped == m
    fit = rate if feasible else rate - 1.0 - (m - escaped) / m
    cover = float(np.mean([r["coverage"] for r in train])) if n else 0.0
    score = -(fit + 0.5 / max(n, m, 1) * cover)
    return {
        "fitness": fit,
        "score": score,
        "feasible": feasible,
        "success": success,
        "environments": n,
        "success_rate": rate,
        "escaped": escaped,
        "deadend_runs": m,
        "mean_coverage": cover,
    }
