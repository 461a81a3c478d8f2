"""Two counts compared exactly: Boschloo's test of two proportions, and the difference it can detect.

A count of the paper's (49 of 50 environments) and one of neurowalk's (953 of 1000) are two samples, each with its
own sampling error. Boschloo's exact test asks whether the two underlying rates could be equal: its statistic is
Fisher's exact p-value of each 2x2 table, and its p-value the largest probability, over the common rate ``pi`` (the
nuisance parameter) under the null, of a table at least as extreme. It is uniformly more powerful than Fisher's
test and exact at every sample size. Two-sided, the p-value is twice the smaller one-sided p-value, capped at 1
(as ``scipy.stats.boschloo_exact`` defines it; the tests check against it, scipy is not needed to run).

:func:`detectable` answers the other half of a verdict: how large a shortfall (or excess) the two samples could
have shown, as the difference in rate at which the test, at level ``alpha``, rejects with probability ``power``.
With the paper's 50 environments that difference is a few points above and several below, whatever neurowalk's n.

All probabilities are computed in logs from a table of log-factorials; the supremum over ``pi`` is taken on a grid
of :data:`GRID` points refined by golden-section search around the best (the p-value is a smooth function of pi,
with one or few maxima; the refinement settles it to 1e-9 in pi).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

GRID = 201
"""Points of the first grid over the nuisance rate pi in [0, 1]."""


@dataclass(frozen=True)
class Comparison:
    """Two counts compared: ``k1`` of ``n1`` against ``k2`` of ``n2``.

    Attributes:
        p_value: two-sided Boschloo p-value (0-1).
        less: one-sided p-value that sample 1's rate is below sample 2's.
        greater: one-sided p-value that it is above.
    """

    k1: int
    n1: int
    k2: int
    n2: int
    p_value: float
    less: float
    greater: float


def _log_fact(n: int) -> np.ndarray:
    """(n + 1,) log k! for k = 0..n."""
    return np.concatenate([[0.0], np.cumsum(np.log(np.arange(1, n + 1, dtype=float)))])


@lru_cache(maxsize=32)
def fisher_less(n1: int, n2: int) -> np.ndarray:
    """(n1 + 1, n2 + 1) Fisher's one-sided p-value of every table: P(sample 1 has <= a successes | both margins),
    for a of n1 and b of n2 successes (the hypergeometric lower tail). Read-only."""
    lf = _log_fact(n1 + n2)
    out = np.empty((n1 + 1, n2 + 1))
    a = np.arange(n1 + 1)
    for total in range(n1 + n2 + 1):
        lo, hi = max(0, total - n2), min(n1, total)
        j = a[lo : hi + 1]
        log_pmf = lf[total] + lf[n1 + n2 - total] - lf[n1 + n2] + lf[n1] + lf[n2] - lf[j] - lf[n1 - j]
        log_pmf -= lf[total - j] + lf[n2 - total + j]
        cdf = np.minimum(np.cumsum(np.exp(log_pmf)), 1.0)
        out[j, total - j] = cdf
    out.setflags(write=False)
    return out


def _binom(n: int, p: float) -> np.ndarray:
    """(n + 1,) binomial pmf of 0..n successes at rate p (0 <= p <= 1)."""
    k = np.arange(n + 1)
    if p <= 0.0 or p >= 1.0:
        return (k == (0 if p <= 0.0 else n)).astype(float)
    lf = _log_fact(n)
    return np.exp(lf[n] - lf[k] - lf[n - k] + k * math.log(p) + (n - k) * math.log1p(-p))


def _sup(region: np.ndarray) -> float:
    """max over pi of the probability of the tables in ``region`` ((n1 + 1, n2 + 1) bool) when both rates are pi."""
    n1, n2 = region.shape[0] - 1, region.shape[1] - 1
    weight = region.astype(float)

    def prob(pi: float) -> float:
        return float(_binom(n1, pi) @ weight @ _binom(n2, pi))

    grid = np.linspace(0.0, 1.0, GRID)
    values = [prob(p) for p in grid]
    i = int(np.argmax(values))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, GRID - 1)]
    best = values[i]
    golden = (math.sqrt(5.0) - 1.0) / 2.0
    c, d = hi - golden * (hi - lo), lo + golden * (hi - lo)
    fc, fd = prob(c), prob(d)
    while hi - lo > 1e-9:
        if fc >= fd:
            hi, d, fd = d, c, fc
            c = hi - golden * (hi - lo)
            fc = prob(c)
        else:
            lo, c, fc = c, d, fd
            d = lo + golden * (hi - lo)
            fd = prob(d)
    return min(1.0, max(best, fc, fd))


def _at_most(stat: np.ndarray, t: float) -> np.ndarray:
    """Tables whose statistic is at most ``t``, with a relative slack of 1e-9 for ties computed two ways."""
    return stat <= t * (1.0 + 1e-9)


def boschloo(k1: int, n1: int, k2: int, n2: int) -> Comparison:
    """Boschloo's exact test of ``k1`` successes of ``n1`` against ``k2`` of ``n2``.

    Raises:
        ValueError: counts outside 0 <= k <= n, or an empty sample.
    """
    for k, n in ((k1, n1), (k2, n2)):
        if not 0 <= k <= n or n < 1:
            raise ValueError(f"need 0 <= k <= n and n >= 1, got {k} of {n}")
    less_stat = fisher_less(n1, n2)
    greater_stat = fisher_less(n1, n2)[::-1, ::-1]  # sample 1's upper tail: the lower tail of its failures
    less = _sup(_at_most(less_stat, less_stat[k1, k2]))
    greater = _sup(_at_most(greater_stat, greater_stat[k1, k2]))
    return Comparison(k1, n1, k2, n2, min(1.0, 2.0 * min(less, greater)), less, greater)


@lru_cache(maxsize=32)
def _rejection(n1: int, n2: int, alpha: float) -> np.ndarray:
    """(n1 + 1, n2 + 1) bool: the tables the two-sided test rejects at ``alpha`` (p-value below it).

    The one-sided p-value is non-decreasing in the table's Fisher statistic, so each side rejects the tables whose
    statistic lies below a threshold, found by bisection over the sorted statistics."""
    out = np.zeros((n1 + 1, n2 + 1), dtype=bool)
    for stat in (fisher_less(n1, n2), fisher_less(n1, n2)[::-1, ::-1]):
        values = np.unique(stat)
        lo, hi = -1, len(values) - 1  # values[lo] rejected (or none), values[hi] not
        if 2.0 * _sup(_at_most(stat, values[hi])) < alpha:
            lo = hi
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if 2.0 * _sup(_at_most(stat, values[mid])) < alpha:
                lo = mid
            else:
                hi = mid
        if lo >= 0:
            out |= _at_most(stat, values[lo])
    out.setflags(write=False)
    return out


def power(p1: float, n1: int, p2: float, n2: int, alpha: float = 0.05) -> float:
    """Probability that the two-sided test at ``alpha`` rejects, when the samples' true rates are p1 and p2."""
    return float(_binom(n1, p1) @ _rejection(n1, n2, alpha).astype(float) @ _binom(n2, p2))


def detectable(rate: float, n_fixed: int, n_other: int, alpha: float = 0.05, want: float = 0.8) -> dict:
    """The smallest differences from ``rate`` (of the sample of ``n_fixed``, the paper's) that a sample of
    ``n_other`` would show with probability ``want`` at ``alpha``: ``{"below": d or None, "above": d or None}``,
    each in rate units (0-1), None where even a rate of 0 (or 1) would not be detected so often."""
    out: dict[str, float | None] = {}
    for side, end in (("below", 0.0), ("above", 1.0)):
        if power(end, n_other, rate, n_fixed, alpha) < want:
            out[side] = None
            continue
        near, far = rate, end  # power(near) < want <= power(far)
        while abs(far - near) > 1e-4:
            mid = (near + far) / 2.0
            if power(mid, n_other, rate, n_fixed, alpha) >= want:
                far = mid
            else:
                near = mid
        out[side] = abs(far - rate)
    return out
