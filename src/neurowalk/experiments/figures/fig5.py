"""Fig. 5: the plastic network in dead ends and in the difficult arena.

Panels as the paper's caption and text name them: A. Simple deadlock and B. narrow passage: escaped, by a long turn
in one direction once the weights have grown. C. Neural activations and weights in the narrow passage (B).
D-E. Input against output, coloured by time: switching between hysteresis and single-attractor states. F. The
difficult arena: the plastic network, started from zero weights, explores. G. Its four weights (self b1, b2;
inhibitions c1 = -q1, c2 = -q2) over the whole long run. Beside them (not in the paper): the coverage over time of
the plastic, static and Braitenberg networks in the same arena, and the wedged periods of each run (start,
duration, cause).

Run lengths: the dead ends 5000 control steps; the long runs :data:`LONG_STEPS` = 100,000 control steps (10,000 s
at 10 Hz), the paper's 1,000,000 time steps read as physics steps of the authors' simulator, ten to a control step
(the reading and its argument: :mod:`neurowalk.experiments.suites.long_runs`; the json's ``time_step_reading``).
The long runs are streamed and keep every 10th control step and the last (``long_rows`` in the json).
``--quick``: long runs of :data:`~neurowalk.experiments.suites.long_runs.QUICK_LONG_STEPS`. The json compares
plastic with static and Braitenberg over the same number of steps (trapping, coverage, wedged periods) and holds
the escape counts of every network over ``--seeds`` seeds and ±20% geometry changes, the plastic network started
from zero (as in the paper's exploration experiment) and from b = 2.4, q = 3.5 (its Fig. 4 start).

Fig. 5F's exploration is judged over :data:`COVERAGE_SEEDS` seeds of the plastic long run (the first is the one
drawn): each seed's coverage at the end, against the authors' own controller in their simulator in the same arena
over as many steps (:func:`~neurowalk.experiments.reproduce.authors.coverage_curve`), with a saturating curve
``c_max (1 - exp(-t / tau))`` fitted to each (:func:`~neurowalk.experiments.suites.long_runs.saturating_fit`): where
coverage levels off, and whether it still rises at the end. No linear extrapolation of a rate.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from neurowalk import metrics
from neurowalk.arenas.spec import WALL_HEIGHT
from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.reproduce import authors
from neurowalk.experiments.reproduce.claims import Claim, holds
from neurowalk.experiments.study_runs import Kept
from neurowalk.experiments.suites import deadends
from neurowalk.experiments.suites.deadends import QUICK_LONG_STEPS, dead_end_claim
from neurowalk.experiments.suites.deadends_plot import Curve
from neurowalk.experiments.suites.deadends_plot import plot as draw
from neurowalk.experiments.suites.long_runs import LONG as LONG_TERM
from neurowalk.experiments.suites.long_runs import WEDGED_LONG_S, control_steps_of, saturating_fit
from neurowalk.neural.plasticity import fixed_point
from neurowalk.neural.variants import get_variant
from neurowalk.plotting.style import network_line
from neurowalk.sim.config import EpisodeConfig

if TYPE_CHECKING:
    from matplotlib.figure import Figure

NAME = "fig5"
NETWORK = "plastic"
LONG = {
    "difficult (plastic)": {"arena": "difficult", "controller": "plastic"},
    "difficult (static)": {"arena": "difficult", "controller": "static"},
    "difficult (braitenberg)": {"arena": "difficult", "controller": "braitenberg"},
}
PAPER_TIME_STEPS = {"difficult-arena run (F, G)": 1_000_000}
LONG_STEPS = control_steps_of(PAPER_TIME_STEPS["difficult-arena run (F, G)"])  # 100,000 control steps
PANELS = {
    "A": "simple deadlock: escaped",
    "B": "narrow passage: escaped",
    "C": "neural activations and weights in the narrow passage (B)",
    "D": "left input against output",
    "E": "right input against output",
    "F": "difficult arena: the plastic network's path over the long run",
    "G": "the plastic network's weights b1, b2, c1, c2 over the whole long run",
}
WEIGHTS = ("b1", "b2", "c1", "c2")  # G: b (self) and c = -q (inhibition) of the left and right neuron
COVERAGE_SEEDS = (4, 2)  # seeds of the plastic long run judged for Fig. 5F (full, quick), the drawn one first
SPREAD_SDS = 2.0  # the coverage rule's allowance: this many of the seeds' standard deviations


def runs(s: Settings) -> Iterator[Plan]:
    """The outcome table over ``s.seeds`` seeds (default 10; 1 with ``quick``), the example and the long runs
    (:func:`~neurowalk.experiments.suites.deadends.runs`)."""
    yield from deadends.runs(s, NETWORK, LONG, LONG_STEPS)
    steps = min(LONG_STEPS, QUICK_LONG_STEPS) if s.quick else LONG_STEPS
    for seed in range(s.seed + 1, s.seed + COVERAGE_SEEDS[s.quick]):
        opts = {"height": WALL_HEIGHT} if s.climbing else {}  # as the drawn long run's (deadends.runs)
        cfg = EpisodeConfig(arena="difficult", arena_opts=opts, controller="plastic", steps=steps, seed=seed)
        yield Plan(("coverage", seed), cfg, (LONG_TERM,))


def measure(s: Settings, runs: Mapping[Any, Sequence[Kept]]) -> Result:
    """The outcome table, the traces, the long runs' coverage and wedged periods, the difficult arena compared."""
    planned = runs  # every run by its label (``runs`` below: the long runs' summaries)
    long_runs = {k: v for k, v in runs.items() if k[0] != "coverage"}
    res = deadends.measure(NAME, NETWORK, LONG, s, long_runs, long_steps=LONG_STEPS, paper_time_steps=PAPER_TIME_STEPS)
    summary = res.summary
    summary["panels"] = PANELS
    runs, wedged = summary["runs"], summary["wedged"]
    nets, over = ("plastic", "static", "braitenberg"), f"over_{WEDGED_LONG_S:g}s"
    summary["difficult_comparison"] = {
        "steps": summary["long_steps"],
        **{f"{n}_{k}": runs[f"difficult ({n})"][k] for k in ("trapped", "coverage") for n in nets},
        "plastic_covers_more": runs["difficult (plastic)"]["coverage"] > runs["difficult (static)"]["coverage"],
        **{f"{n}_wedged": wedged[f"difficult ({n})"]["periods"] for n in nets},
        **{f"{n}_wedged_{over}": wedged[f"difficult ({n})"][over] for n in nets},
    }
    summary["fig5g"] = weights_over_run(res, "difficult (plastic)")
    summary["fig5f"], more = _exploration(res, planned, s)
    res.arrays.update(more)
    return res


def _exploration(res: Result, runs: Mapping[Any, Sequence[Kept]], s: Settings) -> tuple[dict, dict[str, np.ndarray]]:
    """Fig. 5F over seeds: each plastic long run's coverage at its end and its :func:`saturating_fit`, the authors'
    run over as many steps; and the arrays of the further seeds' and the authors' curves (``coverage/SEED/step``,
    ``coverage/SEED/coverage``, ``coverage/authors``)."""
    a, hz = res.arrays, s.rate
    key = "difficult (plastic)"
    curves = {s.seed: (a[f"{key}/step"], a[f"{key}/coverage"])}
    for label, rs in sorted((k, v) for k, v in runs.items() if k[0] == "coverage"):
        curves[label[1]] = (rs[0].kept["long"]["step"], rs[0].kept["long"]["coverage"])
    step = a[f"{key}/step"]
    theirs = authors.coverage_curve("plastic", step)
    final = [float(c[-1]) for _, c in curves.values()]
    sd = float(np.std(final, ddof=1)) if len(final) > 1 else 0.0
    fits = [saturating_fit((st + 1) / hz, c) for st, c in curves.values()]
    out = {
        "seeds": list(curves),
        "seconds": float((step[-1] + 1) / hz),
        "coverage": final,
        "median": float(np.median(final)),
        "sd": sd,
        "fits": fits,
        "authors": {
            "coverage": float(theirs[-1]),
            "fit": saturating_fit((step + 1) / authors.CONTROL_HZ, theirs),
            "source": "the authors' controller in their simulator, the same arena, as many control steps",
        },
        "rule": (
            f"explored as far as the authors' system: the seeds' median coverage at the end is at least the authors' "
            f"run's less {SPREAD_SDS:g} standard deviations of the seeds' coverage (the spread one run has, which the "
            "authors' single run has too); partly where some seed is, not where none is. The saturating fits say "
            "where each curve levels off (c_max) and how fast (tau): no extrapolation enters the verdict"
        ),
    }
    more = {f"coverage/{seed}/{k}": v for seed, (st, c) in curves.items() if seed != s.seed for k, v in
            (("step", st), ("coverage", c))}  # fmt: skip
    more["coverage/authors"] = theirs
    return out, more


def weights_over_run(res: Result, key: str) -> dict:
    """What panel G draws, in numbers: the four weights' first, last, least and greatest values over the long run
    ``key``, the steps its rows cover and their stride."""
    a, s = res.arrays, res.summary
    step = a[f"{key}/step"]
    w = np.column_stack([a[f"{key}/b"], 0.0 - a[f"{key}/q"]]) + 0.0  # b1, b2, c1 = -q1, c2 = -q2 (no -0.0)
    finite = bool(np.isfinite(w).all())
    return {
        "run": key,
        "weights": list(WEIGHTS),
        "rows": len(step),
        "first_step": int(step[0]),
        "last_step": int(step[-1]),
        "stride": s["long_rows"]["stride"],
        "seconds": float((step[-1] + 1) / s["control_hz"]),
        "finite": finite,
        "start": dict(zip(WEIGHTS, w[0].tolist(), strict=True)),
        "end": dict(zip(WEIGHTS, w[-1].tolist(), strict=True)),
        "min": dict(zip(WEIGHTS, np.nanmin(w, axis=0).tolist(), strict=True)) if finite else None,
        "max": dict(zip(WEIGHTS, np.nanmax(w, axis=0).tolist(), strict=True)) if finite else None,
    }


def plot(res: Result) -> Figure:
    """Panels A-G, the coverage over time (H), the wedged periods circled on F; the escape counts as a table."""
    a, s = res.arrays, res.summary
    hz = float(s.get("control_hz", 10.0))
    more: list[Curve] = [
        (
            "plastic, further seeds" if k == 0 else "_",
            a[f"coverage/{seed}/step"] / hz,
            a[f"coverage/{seed}/coverage"],
            {"color": network_line("plastic")["color"], "lw": 1.0, "alpha": 0.6},
        )
        for k, seed in enumerate(s["fig5f"]["seeds"][1:])
    ]
    t = a["difficult (plastic)/step"] / hz
    more.append(("authors' simulator (plastic)", t, a["coverage/authors"], {"color": "black", "ls": "-.", "lw": 1.5}))
    return draw(res, NETWORK, list(LONG), weights_panel=True, more_coverage=more)


def claims(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Plastic network: escapes both dead ends; explores the difficult arena (covers more than the static one) with
    no long held period (slow turns in place, wedged but not held, are counted apart); its weights adapt stably
    over the whole long run (Fig. 5G)."""
    p, st = s["runs"]["difficult (plastic)"], s["runs"]["difficult (static)"]
    wedged = s["wedged"]["difficult (plastic)"]
    held = wedged["held"]
    held_over = next(v for k, v in held.items() if k.startswith("over_"))
    g = s["fig5g"]
    sensory = get_variant(s["variant"]).sensory
    b_star = fixed_point(sensory.mu_b, sensory.gamma_b, sensory.k)
    q_star = fixed_point(sensory.mu_q, sensory.gamma_q, sensory.k)
    whole = g["first_step"] <= g["stride"] and g["last_step"] == s["long_steps"] - 1
    bounded = (
        g["finite"]
        and max(g["max"]["b1"], g["max"]["b2"]) <= 1.01 * b_star
        and min(g["min"]["c1"], g["min"]["c2"]) >= -1.01 * q_star
        and min(g["min"]["b1"], g["min"]["b2"]) >= 0.0
    )
    return [
        dead_end_claim(
            s, "simple-deadlock", "plastic", "escaped", "plastic network escapes the simple dead end (Fig. 5A)"
        ),
        dead_end_claim(
            s, "narrow-passage", "plastic", "escaped", "plastic network escapes the narrow passage (Fig. 5B)"
        ),
        holds(
            "plastic network explores the difficult arena: not stuck at the end, more of it covered than by the "
            "static network (Fig. 5F)",
            "escapes all deadlocks, explores the whole environment",
            not p["trapped"] and p["coverage"] > st["coverage"],
            f"coverage {p['coverage']:.1%} (static {st['coverage']:.1%}), {'stuck' if p['trapped'] else 'not stuck'}",
            f"one run of {p['steps']} control steps ({s['time_step_reading']['long_runs']}): not stuck at the end and "
            "more of the free area visited than the static network's run in the same arena",
        ),
        explored_claim(s["fig5f"]),
        holds(
            "no held period over 300 s in the plastic network's long run (Fig. 5F: escapes all deadlocks)",
            "escapes from all deadlocks, corners",
            held_over["periods"] == 0,
            f"{held_over['periods']} held over 300 s; {wedged['periods']} wedged periods, "
            + f"of which {held['turning_periods']} turning"
            + f"; longest wedged {wedged['longest_s']:.0f} s",
            f"held: trunk centre within {metrics.WEDGE_RADIUS:g} m and heading within {metrics.HELD_HEADING_DEG:g} "
            f"degrees for more than {metrics.WEDGE_MIN_S:g} s; turning: wedged with the "
            f"heading sweeping more, a slow turn in place; causes over 300 s: {held_over['causes'] or '-'}",
        ),
        holds(
            "the weights adapt stably over the whole long run (Fig. 5G)",
            "stable adaptation",
            whole and bounded,
            {
                "max b": round(max(g["max"]["b1"], g["max"]["b2"]), 3),
                "min c": round(min(g["min"]["c1"], g["min"]["c2"]), 3),
            },
            f"rows from step {g['first_step']} to {g['last_step']} every {g['stride']}; finite, b within [0, b*] and "
            f"c within [-q*, 0] (1% margin), b* = {b_star:.3f} and q* = {q_star:.3f} the learning rule's fixed points",
        ),
    ]


def explored_claim(f: dict[str, Any]) -> Claim:
    """Fig. 5F over seeds (``fig5f`` of the summary): explored as far as the authors' own system in the same window
    (its rule: ``f["rule"]``)."""
    them = f["authors"]["coverage"]
    need = them - SPREAD_SDS * f["sd"]
    verdict = "reproduced" if f["median"] >= need else "partly" if max(f["coverage"]) >= need else "not"
    span = f["seconds"]
    each = ", ".join(f"{c:.1%} ({_level(fit, span)})" for c, fit in zip(f["coverage"], f["fits"], strict=True))
    rule = (
        f"{len(f['coverage'])} seeds of {span:,.0f} s: {each}; median {f['median']:.1%}, sd {f['sd']:.1%}. "
        f"The authors' run: {them:.1%} ({_level(f['authors']['fit'], span)}). " + f["rule"]
    )
    return Claim(
        "plastic network explores the difficult arena as far as the authors' own system (Fig. 5F: the whole "
        "environment)",
        "explores the whole environment",
        f"median {f['median']:.1%} of {len(f['coverage'])} seeds (authors' {them:.1%}, need {need:.1%})",
        verdict,
        rule,
    )


def _level(fit: dict[str, Any], span_s: float) -> str:
    """A saturating fit in words: where it levels off and how fast, or, where its time constant is beyond the run's
    ``span_s`` s, that it still rises at the end (its level then lies beyond what the run shows)."""
    if fit["tau_s"] > span_s:
        return f"still rising at the end, tau {fit['tau_s']:,.0f} s"
    return f"levels off at {fit['c_max']:.0%}, tau {fit['tau_s']:,.0f} s"
