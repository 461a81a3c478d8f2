"""A reproduced result, paper against neurowalk: :class:`Claim`, and the rules that give it a verdict.

Each rule is a stated test, chosen before the run, and its text (the claim's ``rule``, in the report's details)
says what uncertainty it accounts for and gives the numbers compared:

* :func:`outcome`: the paper shows one run with an outcome (escaped, trapped, climbed); neurowalk runs several
  seeds. Reproduced where at least two thirds of them end that way, partly where some do, not where none does
  (the Wilson 95% interval of the share is reported beside it). It accounts for the spread of neurowalk's seeds; the
  paper's one run has no spread to account for: a typical outcome is what one run most likely shows.
* :func:`rate`: the paper gives a count of a number (49 of 50). Boschloo's exact test of the two counts, two-sided
  at alpha = 0.05 (:mod:`.exact`; it accounts for the sampling error of both samples): reproduced where p >= 0.05,
  else partly where the two rates are within 10 points, not beyond. Beside it, the smallest difference from the
  paper's rate the two samples would detect with 80% power.
* :func:`interval`: the paper gives the time between two of its photos of the real robot (obstacle seen, escaped):
  an interval, not a time from the start (where an invented arena puts the robot). Its median over the seeds against
  the paper's, known to +-1 s (the stamps are to the second): reproduced within a factor of 1.5, partly within 3,
  not otherwise (it accounts for the body and floor: the simulated robot's differ from the real ones; not for a
  spread, the paper's interval being one run's).
* :func:`value`: a number of the paper's (a fixed point, a threshold) against the measured one, with a tolerance
  (the claim says what the tolerance stands for: the paper's printed precision, its figure's resolution).
* :func:`holds`: a property the paper states in words (the weights settle; the robot turns left) and whether it
  holds in the run, by the measure its text names.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

from neurowalk.experiments.reproduce.exact import boschloo, detectable
from neurowalk.experiments.suites.random_envs import wilson

VERDICTS: tuple[str, ...] = ("reproduced", "partly", "not")

ALPHA = 0.05
"""Level of :func:`rate`'s test (two-sided)."""

POWER = 0.8
"""Power at which :func:`rate` states the smallest detectable difference."""

PARTLY_POINTS = 0.10
"""A count that differs significantly is still *partly* reproduced within this many rate points (0.10: 10)."""


@dataclass(frozen=True)
class Claim:
    """One of the paper's results, measured.

    Attributes:
        what: the result in words ("plastic network escapes the narrow passage").
        paper: the paper's value, as it states it ("escaped", "49/50", 50.0).
        measured: neurowalk's value (a share, a count "48/50", a time in s, a number).
        verdict: ``reproduced``, ``partly`` or ``not``.
        rule: how the verdict was reached, in words, with the numbers compared.
        interval: 95% interval of ``measured`` where it is a rate, else None.
        unit: unit of ``paper`` and ``measured``, or what a count counts ("s", "%", "m", "runs", "environments";
            "" where the value says it itself, as a word or with its own unit).
        test: the statistical test of a count (:func:`rate`): ``name``, ``p_value``, ``alpha``, ``power`` and
            ``detectable`` (``below``, ``above``: the smallest differences from the paper's rate, 0-1, that the
            two samples would show at that power, None where none would), else None.
        cause: why a claim is not reproduced (:mod:`.causes`): ``kind`` (one of its ``KINDS``) and ``why`` (the
            measurement that shows it); None for a reproduced claim.
    """

    what: str
    paper: Any
    measured: Any
    verdict: str
    rule: str
    interval: tuple[float, float] | None = None
    unit: str = ""
    test: dict[str, Any] | None = None
    cause: dict[str, str] | None = None

    def __post_init__(self) -> None:
        if self.verdict not in VERDICTS:
            raise ValueError(f"verdict must be one of {', '.join(VERDICTS)}, got {self.verdict!r}")

    def to_json(self) -> dict[str, Any]:
        """A JSON-able dict of the claim."""
        d = asdict(self)
        d["interval"] = None if self.interval is None else [float(x) for x in self.interval]
        return d


def outcome(what: str, paper: str, k: int, n: int) -> Claim:
    """The paper's single run ended in ``paper``; ``k`` of neurowalk's ``n`` seeds (runs) end the same way."""
    lo, hi = wilson(k, n)
    verdict = "reproduced" if 3 * k >= 2 * n > 0 else "partly" if k > 0 else "not"
    rule = (
        f"{k} of {n} runs end as the paper's one run did ({paper}; 95% interval {lo:.0%}-{hi:.0%}): reproduced "
        "where two thirds or more do, partly where some do, not where none does (it accounts for the spread of "
        "neurowalk's seeds and reads the paper's one run as its typical outcome)"
    )
    return Claim(what, paper, f"{k}/{n}", verdict, rule, (lo, hi), unit="runs")


def rate(what: str, paper_k: int, paper_n: int, k: int, n: int, of: str = "environments") -> Claim:
    """The paper counts ``paper_k`` of ``paper_n``; neurowalk ``k`` of ``n`` (``of``: what both count).

    Boschloo's exact test, two-sided at :data:`ALPHA`: reproduced where p >= ALPHA, else partly within
    :data:`PARTLY_POINTS` of the paper's rate, not beyond; no runs (n = 0): not."""
    p0 = paper_k / paper_n
    if n == 0:
        return Claim(what, f"{paper_k}/{paper_n}", "0/0", "not", "no run was measured", (0.0, 1.0), unit=of)
    lo, hi = wilson(k, n)
    p = k / n
    test = boschloo(k, n, paper_k, paper_n)
    seen = detectable(p0, paper_n, n, ALPHA, POWER)
    significant = test.p_value < ALPHA
    verdict = "reproduced" if not significant else "partly" if abs(p - p0) <= PARTLY_POINTS + 1e-12 else "not"
    below, above = (f"{100 * d:.1f} points" if d is not None else None for d in (seen["below"], seen["above"]))
    sizes = (
        " or ".join(x for x in (f"{below} below" if below else "", f"{above} above" if above else "") if x)
        or "no difference"
    )
    rule = (
        f"paper {paper_k}/{paper_n} ({p0:.1%}) against {k}/{n} ({p:.1%}; 95% interval {lo:.1%}-{hi:.1%}): "
        f"Boschloo's exact test, two-sided, p = {test.p_value:.3g} (it accounts for the sampling error of both "
        f"counts); reproduced where p >= {ALPHA:g}, else partly within {100 * PARTLY_POINTS:.0f} points of the "
        f"paper's rate, not beyond. These two samples would show a rate {sizes} the paper's with "
        f"{POWER:.0%} power"
    )
    stats = {
        "name": "Boschloo's exact test, two-sided",
        "p_value": _digits(test.p_value),
        "alpha": ALPHA,
        "power": POWER,
        "detectable": {side: None if d is None else _digits(d) for side, d in seen.items()},
    }
    return Claim(what, f"{paper_k}/{paper_n}", f"{k}/{n}", verdict, rule, (lo, hi), unit=of, test=stats)


def _digits(x: float) -> float:
    """``x`` to 12 significant digits, as a record keeps it: numpy's vectorised logs differ in the last bits from
    one CPU type to another (``znver3`` and ``znver4`` gave p-values 2e-17 apart), a record does not."""
    return float(f"{x:.12g}")


#: s: each photo time stamp of the paper is given to the second, so an interval between two is known to +-1 s.
STAMP_S = 1.0


def interval(what: str, paper_s: float, measured_s: float | None, context: str = "") -> Claim:
    """The real robot took ``paper_s`` seconds between two of the paper's photos; the simulated one ``measured_s``
    (None: one of the two events never came). Judged against the nearest end of the paper's
    interval +- :data:`STAMP_S` (its photos' time stamps are to the second): reproduced within a factor of 1.5,
    partly within 3, not otherwise."""
    if measured_s is None or not math.isfinite(measured_s):
        return Claim(what, paper_s, None, "not", f"one of the two events did not happen in the runs{context}", unit="s")
    lo, hi = max(paper_s - STAMP_S, 0.0), paper_s + STAMP_S
    near = min(max(float(measured_s), lo), hi)
    factor = max(measured_s / near, near / measured_s) if measured_s > 0 else math.inf
    verdict = "reproduced" if factor <= 1.5 else "partly" if factor <= 3 else "not"
    rule = (
        f"{measured_s:.0f} s against the real robot's {paper_s:.0f} +- {STAMP_S:g} s between two of its photos (their "
        f"stamps are to the second), a factor of {factor:.1f}{context}: reproduced within 1.5, partly within 3 (it "
        "accounts for the simulated body and floor against the real ones; the paper's interval is one run's)"
    )
    return Claim(what, paper_s, round(float(measured_s), 1), verdict, rule, unit="s")


def value(what: str, paper: float, measured: float, tol: float, unit: str = "", partly: float = 3.0) -> Claim:
    """A number of the paper's against the measured one: reproduced within ``tol``, partly within ``partly * tol``."""
    diff = abs(measured - paper)
    verdict = "reproduced" if diff <= tol else "partly" if diff <= partly * tol else "not"
    rule = (
        f"|{measured:.4g} - {paper:.4g}| = {diff:.3g}{unit}: reproduced within {tol:g}, partly within {partly * tol:g}"
    )
    return Claim(what, paper, round(float(measured), 6), verdict, rule, unit=unit)


def holds(what: str, paper: str, ok: bool, measured: Any, why: str, unit: str = "") -> Claim:
    """A property the paper states in words: reproduced where it holds in the run, not where not; ``unit``: of the
    measured value, or what its counts count."""
    return Claim(what, paper, measured, "reproduced" if ok else "not", why, unit=unit)


def overall(claims: list[Claim]) -> tuple[str, str]:
    """An experiment's verdict from its claims, and its reason: reproduced where all are, not where all are not,
    partly otherwise; the reason counts the claims reproduced and names the others under their verdicts."""
    if not claims:
        return "not", "no result was measured"
    counts = {v: sum(c.verdict == v for c in claims) for v in VERDICTS}
    if counts["reproduced"] == len(claims):
        return "reproduced", f"all {len(claims)} reproduced"
    if counts["not"] == len(claims):
        return "not", f"all {len(claims)} not reproduced: " + "; ".join(c.what for c in claims)
    off = "; ".join(f"{v}: " + "; ".join(c.what for c in claims if c.verdict == v) for v in VERDICTS[1:] if counts[v])
    return "partly", f"{counts['reproduced']} of {len(claims)} reproduced; {off}"
