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
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from neurowalk import metrics
from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.reproduce.claims import Claim, holds
from neurowalk.experiments.stores import Kept
from neurowalk.experiments.suites import deadends
from neurowalk.experiments.suites.deadends import dead_end_claim
from neurowalk.experiments.suites.deadends_plot import plot as draw
from neurowalk.experiments.suites.long_runs import WEDGED_LONG_S, control_steps_of
from neurowalk.experiments.suites.random_envs import COVERAGE_PER_1000S, coverage_threshold
from neurowalk.neural.plasticity import fixed_point
from neurowalk.neural.variants import get_variant

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


def runs(s: Settings) -> Iterator[Plan]:
    """The outcome table over ``s.seeds`` seeds (default 10; 1 with ``quick``), the example and the long runs
    (:func:`~neurowalk.experiments.suites.deadends.runs`)."""
    return deadends.runs(s, NETWORK, LONG, LONG_STEPS)


def measure(s: Settings, runs: Mapping[Any, Sequence[Kept]]) -> Result:
    """The outcome table, the traces, the long runs' coverage and wedged periods, the difficult arena compared."""
    res = deadends.measure(NAME, NETWORK, LONG, s, runs, long_steps=LONG_STEPS, paper_time_steps=PAPER_TIME_STEPS)
    summary = res.summary
    summary["panels"] = PANELS
    runs, wedged = summary["runs"], summary["wedged"]
    p, st, br = (runs[f"difficult ({n})"] for n in ("plastic", "static", "braitenberg"))
    over = f"over_{WEDGED_LONG_S:g}s"
    summary["difficult_comparison"] = {
        "steps": summary["long_steps"],
        "plastic_trapped": p["trapped"],
        "static_trapped": st["trapped"],
        "braitenberg_trapped": br["trapped"],
        "plastic_coverage": p["coverage"],
        "static_coverage": st["coverage"],
        "braitenberg_coverage": br["coverage"],
        "plastic_covers_more": p["coverage"] > st["coverage"],
        **{f"{n}_wedged": wedged[f"difficult ({n})"]["periods"] for n in ("plastic", "static", "braitenberg")},
        **{f"{n}_wedged_{over}": wedged[f"difficult ({n})"][over] for n in ("plastic", "static", "braitenberg")},
    }
    summary["fig5g"] = weights_over_run(res, "difficult (plastic)")
    return res


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
    return draw(res, NETWORK, list(LONG), weights_panel=True)


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
        holds(
            "plastic network explores the difficult arena by Table 2's coverage rule (Fig. 5F: the whole environment)",
            "explores the whole environment",
            p["coverage"] >= (need := coverage_threshold(p["steps"] / s["control_hz"])),
            f"coverage {p['coverage']:.1%} (the rule asks {need:.1%})",
            f"Table 2's coverage rule: at least {COVERAGE_PER_1000S:.1%} of the free cells per 1000 s simulated, "
            f"{need:.1%} in this run's {p['steps'] / s['control_hz']:.0f} s",
        ),
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
