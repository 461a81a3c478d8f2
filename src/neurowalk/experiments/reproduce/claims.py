"""A reproduced result, paper against neurowalk: :class:`Claim`, and the rules that give it a verdict.

Each rule is stated in the claim's ``rule`` so the report says how a verdict was reached:

* :func:`outcome`: the paper shows one run with an outcome (escaped, trapped, climbed); neurowalk runs several
  seeds. Reproduced where at least two thirds of them end that way, partly where some do, not where none does
  (the Wilson 95% interval of the share is reported beside it).
* :func:`rate`: the paper gives a count of a number (49 of 50). Reproduced where the paper's rate lies inside the
  measured 95% interval, partly where the two rates are within 10 points, not otherwise.
* :func:`timing`: the paper gives the time of an event on the real robot. Reproduced within a factor of 1.5,
  partly within a factor of 3, not otherwise (the simulated robot's body and floor differ from the real ones).
* :func:`value`: a number of the paper's (a fixed point, a threshold) against the measured one, with a tolerance.
* :func:`holds`: a property the paper states in words (the weights settle; the robot turns left) and whether it
  holds in the run.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

from neurowalk.experiments.suites.random_envs import wilson

VERDICTS: tuple[str, ...] = ("reproduced", "partly", "not")


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
    """

    what: str
    paper: Any
    measured: Any
    verdict: str
    rule: str
    interval: tuple[float, float] | None = None
    unit: str = ""

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
        "where two thirds or more do, partly where some do, not where none does"
    )
    return Claim(what, paper, f"{k}/{n}", verdict, rule, (lo, hi), unit="runs")


def rate(what: str, paper_k: int, paper_n: int, k: int, n: int, of: str = "environments") -> Claim:
    """The paper counts ``paper_k`` of ``paper_n``; neurowalk ``k`` of ``n`` (``of``: what both count)."""
    lo, hi = wilson(k, n)
    p0, p = paper_k / paper_n, (k / n if n else 0.0)
    verdict = "reproduced" if lo <= p0 <= hi else "partly" if abs(p - p0) <= 0.10 else "not"
    rule = (
        f"paper {p0:.0%} against {p:.0%} (95% interval {lo:.0%}-{hi:.0%}): reproduced where the paper's rate is "
        "inside the interval, partly within 10 points"
    )
    return Claim(what, f"{paper_k}/{paper_n}", f"{k}/{n}", verdict, rule, (lo, hi), unit=of)


def timing(what: str, paper_s: float, measured_s: float | None, context: str = "") -> Claim:
    """The real robot took ``paper_s`` seconds; the simulated one ``measured_s`` (None: the event never came)."""
    if measured_s is None or not math.isfinite(measured_s):
        return Claim(what, paper_s, None, "not", f"the event did not happen in the run{context}", unit="s")
    factor = max(measured_s / paper_s, paper_s / measured_s) if measured_s > 0 else math.inf
    verdict = "reproduced" if factor <= 1.5 else "partly" if factor <= 3 else "not"
    rule = (
        f"{measured_s:.0f} s against the real robot's {paper_s:.0f} s, a factor of {factor:.1f}{context}: "
        "reproduced within 1.5, partly within 3"
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
