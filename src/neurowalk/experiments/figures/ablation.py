"""Beyond the paper: what each of the authors' code's options costs, on Table 2's environments.

The paper's reading of the plastic network (``paper``: Eq. 1-6 as printed) fails Table 2 more often than the
authors' code (``original``). The two differ in the 10 options of :data:`~neurowalk.neural.variants.CODE_OPTIONS`.
This study switches each option alone, both ways, on Table 2's first 1000 environments (quick: 100) on the planar
surrogate, at the table's 2000 s (quick: 500 s):

- ``paper + OPTION``: the paper's reading with that one option set as the code sets it;
- ``original - OPTION``: the code's reading with that one option set as the paper reads it;
- ``paper + all``: the paper's reading with every option set as the code's: the code's reading by another road,
  which must give the code's counts run for run (a claim; it checks that the options are all there is to it);
- ``paper`` and ``original`` themselves, run for twice as long (4000 s; quick: 1000 s), their outcomes read at
  every run length of :data:`LENGTHS_S` from one run (a run's first T seconds are a run of T seconds): success
  against run length, the table's 2000 s among them.

The planar surrogate has no CPG, so the PCPG's ``pcpg_first_partial`` (the tenth option) acts on physics only and is
not switched here. Each arm's successes by both of Table 2's rules (not stuck; coverage) and its failures' classes.

On physics AMOSII, on Table 2's 50 environments (quick: 5), both readings and the two options that moved the
surrogate's count most (:data:`PHYSICS_OPTIONS`), each switched alone both ways, at 2000 s (quick: 500 s).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.reproduce.claims import Claim, holds
from neurowalk.experiments.study_runs import Kept, Term
from neurowalk.experiments.suites.random_envs import (
    FAILURE_CLASSES,
    coverage_threshold,
    environments,
    failure_class,
    spec,
    wilson,
)
from neurowalk.metrics import coverage, trapped
from neurowalk.neural.variants import CODE_OPTIONS
from neurowalk.plotting.style import LINE, legend_outside, letter_panels, pyplot, styled
from neurowalk.sim.config import EpisodeConfig
from neurowalk.sim.episode import Episode
from neurowalk.sim.summarize import STUCK_S

if TYPE_CHECKING:
    from matplotlib.figure import Figure

NAME = "ablation"
HZ = 10.0  # the surrogate's calibrated rate
DURATION_S, QUICK_DURATION_S = 2000.0, 500.0  # Table 2's run length (quick: its quick one)
LENGTHS_S = (500.0, 1000.0, 2000.0, 3000.0, 4000.0)
"""Run lengths (s) at which the two readings' long runs are judged; the longest is their run's length."""
QUICK_LENGTHS_S = (500.0, 750.0, 1000.0)
SWITCHED = tuple(o for o in CODE_OPTIONS if o != "pcpg_first_partial")  # the options the surrogate can feel
PHYSICS_OPTIONS = ("b_start", "q_start")
"""The options also switched on physics AMOSII, on Table 2's 50 environments: the two that moved the surrogate's
count most, both ways, in the committed surrogate ablation (the start weights: +40 and -120, -32 and -50)."""
PHYSICS_ENVS, QUICK_PHYSICS_ENVS = 50, 5


def physics_arms() -> dict[str, tuple[str, dict[str, Any] | None]]:
    """The physics arms: both readings, and each of :data:`PHYSICS_OPTIONS` switched alone both ways."""
    out: dict[str, tuple[str, dict[str, Any] | None]] = {"paper": ("paper", None), "original": ("original", None)}
    for o in PHYSICS_OPTIONS:
        out[f"paper + {o}"] = ("paper", {o: CODE_OPTIONS[o][1]})
        out[f"original - {o}"] = ("original", {o: CODE_OPTIONS[o][0]})
    return out


def arms() -> dict[str, tuple[str, dict[str, Any] | None]]:
    """The 2000 s arms: name -> (variant, params): each option switched alone both ways, and all together."""
    out: dict[str, tuple[str, dict[str, Any] | None]] = {}
    for o in SWITCHED:
        out[f"paper + {o}"] = ("paper", {o: CODE_OPTIONS[o][1]})
    for o in SWITCHED:
        out[f"original - {o}"] = ("original", {o: CODE_OPTIONS[o][0]})
    out["paper + all"] = ("paper", {o: CODE_OPTIONS[o][1] for o in SWITCHED})
    return out


def keep_lengths(ep: Episode) -> dict[str, Any]:
    """A long run's outcome at each of its run lengths: ``lengths_s``, ``success`` (not stuck over the last 300 s of
    the first T s) and ``success_coverage`` (coverage of the first T s at least the rule's threshold for T)."""
    pose, hz = ep.trajectory.pose, ep.config.control_hz
    window = round(STUCK_S * hz)
    lengths = [t for t in (*LENGTHS_S, *QUICK_LENGTHS_S) if round(t * hz) <= len(pose)]
    lengths = sorted(set(lengths))
    ok, ok_cov = [], []
    for t in lengths:
        head = pose[: round(t * hz)]
        ok.append(not trapped(head, window=window))
        c = coverage(head, ep.arena)
        ok_cov.append(c is not None and c >= coverage_threshold(t))
    return {"lengths_s": lengths, "success": ok, "success_coverage": ok_cov}


LENGTHS = Term("run lengths", keep_lengths)


def _setup(s: Settings) -> tuple[list[dict[str, Any]], float, tuple[float, ...]]:
    """The environments (1000; quick 100; ``seeds`` sets their number), the arms' run length and the long runs'."""
    envs = environments(s.n(full=1000, quick=100), s.seed)
    return envs, (QUICK_DURATION_S if s.quick else DURATION_S), (QUICK_LENGTHS_S if s.quick else LENGTHS_S)


def _physics_envs(s: Settings, envs: list[dict[str, Any]]) -> int:
    """How many of the environments the physics arms run: the first 50 (quick 5), or all where fewer are given."""
    return min(len(envs), QUICK_PHYSICS_ENVS if s.quick else PHYSICS_ENVS)


def runs(s: Settings) -> Iterator[Plan]:
    """Every arm in every environment on the surrogate; the two readings' long runs."""
    envs, duration, lengths = _setup(s)
    fixed = ("variant", "params", "body", "control_hz")
    for name, (variant, params) in arms().items():
        for i, e in enumerate(envs):
            one = spec(e, "plastic", round(duration * HZ), "surrogate", variant=variant, params=params)
            yield Plan((name, i), EpisodeConfig.from_spec(one), (), fixed)
    for variant in ("paper", "original"):
        for i, e in enumerate(envs):
            one = spec(e, "plastic", round(lengths[-1] * HZ), "surrogate", variant=variant)
            yield Plan((f"{variant} (long)", i), EpisodeConfig.from_spec(one), (LENGTHS,), fixed)
    for name, (variant, params) in physics_arms().items():
        for i, e in enumerate(envs[: _physics_envs(s, envs)]):
            one = spec(e, "plastic", round(duration * HZ), "amosii", variant=variant, params=params)
            yield Plan(("physics", name, i), EpisodeConfig.from_spec(one), (), fixed)


def _counts(ok: list[bool], ok_cov: list[bool], classes: list[str | None] | None) -> dict[str, Any]:
    """One arm's counts over the environments: successes by both rules, their Wilson intervals, failure classes."""
    n = len(ok)
    out: dict[str, Any] = {
        "environments": n,
        "success": int(sum(ok)),
        "success_95ci": list(wilson(int(sum(ok)), n)),
        "success_coverage": int(sum(ok_cov)),
        "success_coverage_95ci": list(wilson(int(sum(ok_cov)), n)),
        "outcomes": [int(a) + 2 * int(b) for a, b in zip(ok, ok_cov, strict=True)],  # bit 0 not stuck, 1 coverage
    }
    if classes is not None:
        out["failure_classes"] = {c: classes.count(c) for c in FAILURE_CLASSES}
    return out


def _arm(runs: list[Sequence[Kept]], threshold: float, variant: str, params: dict[str, Any] | None) -> dict[str, Any]:
    """One arm's :func:`_counts` from its ``runs`` (one per environment; coverage rule: ``threshold``), its variant
    and params."""
    sums = [rs[0].summary.to_dict() for rs in runs]
    ok_cov = [r["coverage"] is not None and r["coverage"] >= threshold for r in sums]
    counts = _counts([not r["trapped"] for r in sums], ok_cov, [failure_class(r) for r in sums])
    return {**counts, "variant": variant, "params": params}


def measure(s: Settings, runs: Mapping[tuple, Sequence[Kept]]) -> Result:
    """Each arm's counts; the two readings at every run length (the table's length among them, as arms)."""
    envs, duration, lengths = _setup(s)
    n = len(envs)
    threshold = coverage_threshold(duration)
    table = {name: _arm([runs[(name, i)] for i in range(n)], threshold, *arm) for name, arm in arms().items()}
    curve: dict[str, dict[str, Any]] = {}
    for variant in ("paper", "original"):
        kept = [runs[(f"{variant} (long)", i)][0].kept["run lengths"] for i in range(n)]
        curve[variant] = {}
        for t in lengths:
            j = kept[0]["lengths_s"].index(t)
            ok, ok_cov = [k["success"][j] for k in kept], [k["success_coverage"][j] for k in kept]
            curve[variant][f"{t:g}"] = _counts(ok, ok_cov, None)
        long_sums = [runs[(f"{variant} (long)", i)][0].summary.to_dict() for i in range(n)]
        at = curve[variant][f"{duration:g}"]
        table[variant] = {**at, "variant": variant, "params": None, "read_from": f"its {lengths[-1]:g} s runs",
                          "failure_classes_at_end": {c: [failure_class(r) for r in long_sums].count(c)
                                                     for c in FAILURE_CLASSES}}  # fmt: skip
    n_phys = _physics_envs(s, envs)
    physics = {
        name: _arm([runs[("physics", name, i)] for i in range(n_phys)], threshold, *arm)
        for name, arm in physics_arms().items()
    }
    summary = {
        "environments": n,
        "seed": s.seed,
        "duration_s": duration,
        "lengths_s": list(lengths),
        "options": {o: list(CODE_OPTIONS[o]) for o in CODE_OPTIONS},
        "switched": list(SWITCHED),
        "not_switched": {"pcpg_first_partial": "the planar surrogate has no CPG: it acts on physics only"},
        "arms": table,
        "run_length": curve,
        "physics": {"body": "amosii", "environments": n_phys, "options": list(PHYSICS_OPTIONS), "arms": physics},
    }
    return Result(NAME, summary, {})


def effects(s: dict[str, Any]) -> list[dict[str, Any]]:
    """Each option's effect on the not-stuck successes, both ways, largest first: ``option``, ``on_paper`` (paper +
    option minus paper) and ``off_original`` (original - option minus original), in environments."""
    a = s["arms"]
    rows = [
        {
            "option": o,
            "on_paper": a[f"paper + {o}"]["success"] - a["paper"]["success"],
            "off_original": a[f"original - {o}"]["success"] - a["original"]["success"],
        }
        for o in s["switched"]
    ]
    return sorted(rows, key=lambda r: -(abs(r["on_paper"]) + abs(r["off_original"])))


@styled
def plot(res: Result) -> Figure:
    """A: each option's effect on the successes (not stuck), switched on in the paper's reading and off in the code's,
    with the two readings' gap marked; B: success against run length for both readings and both rules."""
    plt = pyplot()
    s = res.summary
    a, n = s["arms"], s["environments"]
    fig, (ax, cx, bx) = plt.subplots(
        1, 3, figsize=(20, 6.5), layout="constrained", gridspec_kw={"width_ratios": [1.3, 0.8, 1]}
    )
    rows = effects(s)
    y = np.arange(len(rows))
    gap = a["original"]["success"] - a["paper"]["success"]
    ax.barh(y + 0.2, [r["on_paper"] for r in rows], height=0.4, color="tab:blue",
            label="paper + option (minus paper)")  # fmt: skip
    ax.barh(y - 0.2, [r["off_original"] for r in rows], height=0.4, color="tab:orange",
            label="original - option (minus original)")  # fmt: skip
    ax.axvline(gap, color="tab:blue", ls="--", lw=LINE["trace"], label=f"the gap: original - paper = {gap:+d}")
    ax.axvline(-gap, color="tab:orange", ls="--", lw=LINE["trace"], label=f"its mirror: {-gap:+d}")
    ax.axvline(0, color="0.3", lw=LINE["thin"])
    ax.set_yticks(y, [r["option"] for r in rows])
    ax.set_ylabel("option of the authors' code")
    ax.invert_yaxis()
    allin = a["paper + all"]["success"]
    ax.set(xlabel=f"change in environments not stuck at {s['duration_s']:g} s (of {n})",
           title=f"one option at a time (paper {a['paper']['success']}, original {a['original']['success']}, "
                 f"paper + all {allin})")  # fmt: skip
    legend_outside(ax, side="below", ncol=2)
    lengths = s["lengths_s"]
    for variant, colour in (("paper", "tab:blue"), ("original", "tab:orange")):
        c = s["run_length"][variant]
        for key, ls, rule in (("success", "-", "not stuck"), ("success_coverage", ":", "coverage")):
            rate = [c[f"{t:g}"][key] / n for t in lengths]
            lo_hi = np.array([c[f"{t:g}"][f"{key}_95ci"] for t in lengths])
            bx.plot(lengths, rate, ls=ls, marker="o", color=colour, label=f"{variant}, {rule}")
            bx.fill_between(lengths, lo_hi[:, 0], lo_hi[:, 1], color=colour, alpha=0.12)
    bx.axhline(49 / 50, color="0.3", ls="--", lw=LINE["trace"], label="paper's 49/50")
    bx.axvline(s["duration_s"], color="0.5", lw=LINE["thin"], label="Table 2's run length")
    bx.set(xlabel="run length (s)", ylabel="success rate (Wilson 95% interval)", ylim=(0, 1.02),
           title="success against run length")  # fmt: skip
    legend_outside(bx, side="below", ncol=2)
    _physics_panel(cx, s)
    letter_panels([ax, cx, bx])
    fig.suptitle(
        f"The authors' code's options, one at a time: {n} Table 2 environments on the planar surrogate (A, C), "
        f"{s['physics']['environments']} on physics AMOSII (B)"
    )
    return fig


def _physics_panel(ax: Any, s: dict[str, Any]) -> None:
    """The physics arms' not-stuck counts, both readings and each start weight switched both ways."""
    ph = s["physics"]
    names = list(ph["arms"])
    counts = [ph["arms"][k]["success"] for k in names]
    colours = ["tab:blue" if k.startswith("paper") else "tab:orange" for k in names]
    y = np.arange(len(names))
    ax.barh(y, counts, color=colours, height=0.6)
    for yi, c in zip(y, counts, strict=True):
        ax.text(c, yi, f" {c}", va="center")
    ax.set_yticks(y, names)
    ax.invert_yaxis()
    ax.axvline(49 / 50 * ph["environments"], color="0.3", ls="--", lw=LINE["trace"], label="paper's 49/50")
    ax.set(xlim=(0, ph["environments"] * 1.12), xlabel=f"environments not stuck (of {ph['environments']})",
           ylabel="arm", title=f"physics AMOSII, {s['duration_s']:g} s")  # fmt: skip
    legend_outside(ax, side="below", ncol=1)


def claims(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Beyond the paper: the options are the whole difference (all on gives the code's outcomes, run for run); which
    one closes the gap; how the paper's reading fails."""
    a = s["arms"]
    same = a["paper + all"]["outcomes"] == a["original"]["outcomes"]
    gap = a["original"]["success"] - a["paper"]["success"]
    top = effects(s)[0]
    f = a["paper"]["failure_classes_at_end"]
    fails = sum(f.values())
    ph = s["physics"]["arms"]
    toward = [o for o in s["physics"]["options"] if ph[f"paper + {o}"]["success"] >= ph["paper"]["success"]
              and ph[f"original - {o}"]["success"] <= ph["original"]["success"]]  # fmt: skip
    return [
        holds(
            "all of the code's options set in the paper's reading give the code's outcomes",
            "beyond the paper",
            same,
            f"{a['paper + all']['success']}, {a['original']['success']} of {s['environments']} not stuck",
            f"the {len(s['switched'])} options the surrogate feels, all set as the code sets them, against the code's "
            f"reading: each environment's two outcomes (not stuck, coverage) compared at {s['duration_s']:g} s",
            unit="environments",
        ),
        holds(
            "one of the code's options alone moves half the gap between the two readings or more",
            "beyond the paper",
            gap > 0 and (top["on_paper"] >= gap / 2 or -top["off_original"] >= gap / 2),
            f"{top['option']}: {top['on_paper']:+d} on, {top['off_original']:+d} off (gap {gap:+d})",
            f"the option that moves the not-stuck count most, switched alone both ways, against the gap between the "
            f"two readings at {s['duration_s']:g} s; holds where it moves at least half the gap either way",
            unit="environments",
        ),
        holds(
            "the paper's model as printed fails by latched spins",
            "beyond the paper",
            fails > 0 and f["latched spin"] > fails / 2,
            f"{f['latched spin']} of {fails} failures",
            f"failure classes of the paper's reading at the end of its {s['lengths_s'][-1]:g} s runs: {f}",
            unit="failures",
        ),
        holds(
            "in physics too, the start weights move each reading toward the other",
            "beyond the paper",
            len(toward) == len(s["physics"]["options"]),
            "; ".join(
                f"{o} {ph[f'paper + {o}']['success'] - ph['paper']['success']:+d} on, "
                f"{ph[f'original - {o}']['success'] - ph['original']['success']:+d} off"
                for o in s["physics"]["options"]
            ),
            f"on physics AMOSII in Table 2's first {s['physics']['environments']} environments: each start weight set "
            "as the code's does not lower the paper's reading's not-stuck count, and set as the paper's does not raise "
            "the code's",
            unit="environments not stuck",
        ),
    ]
