"""Step-height sweep with ablations: which part of the climbing controller climbs which step.

The robot walks straight at a single step (arena ``steps``, steering fixed forward) with reflexes and
backbone control both on, each alone, and neither; ``seeds`` seeds (default 10; 3 with ``quick``) per
height and variant, through the resumable store in the output folder. Every run lasts at most
:data:`~neurowalk.experiments.suites.climbing.STEP_S` s of simulated time at the control rate ``control_hz`` (10 Hz by
default; with ``quick`` at a high rate, at most :data:`QUICK_MAX_STEPS` control steps); it stops once climbed. Every
variant steps the same physics. The json gives each
variant's climb rate per height, the median time to climb (s) and its highest step climbed reliably (rule in the
json).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.ticker import PercentFormatter

from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.reproduce.claims import Claim, holds
from neurowalk.experiments.study_runs import Kept
from neurowalk.experiments.suites.climbing import (
    QUICK_SWEEP_HEIGHTS,
    RELIABLE,
    STEP_RULE,
    STEP_S,
    SWEEP_HEIGHTS,
    VARIANTS,
    climbed,
    highest_reliable,
    step_spec,
)
from neurowalk.experiments.suites.timing import quick_note, quick_seconds, steps_for
from neurowalk.plotting.style import LINE, legend_outside, pyplot, styled
from neurowalk.sim.config import EpisodeConfig

if TYPE_CHECKING:
    from matplotlib.figure import Figure

QUICK_MAX_STEPS = 3000  # control steps of a quick run at most (STEP_S at 10 Hz; 111 s at 27 Hz)


def _steps(s: Settings) -> tuple[float, int]:
    """Seconds and control steps per run: :data:`~neurowalk.experiments.suites.climbing.STEP_S` s at the control
    rate, at most :data:`QUICK_MAX_STEPS` control steps with ``quick``."""
    seconds = quick_seconds(STEP_S, QUICK_MAX_STEPS, s.rate) if s.quick else STEP_S
    return seconds, steps_for(seconds, s.rate)


def runs(s: Settings) -> Iterator[Plan]:
    """Every variant of the climbing modules at every height (``(variant, height)``), ``s.seeds`` seeds (10; quick:
    3)."""
    heights, (_, steps) = QUICK_SWEEP_HEIGHTS if s.quick else SWEEP_HEIGHTS, _steps(s)
    for v in VARIANTS:
        for h in heights:
            for k in range(s.n(10, 3)):
                yield Plan((v, h), EpisodeConfig.from_spec(step_spec(h, v, s.seed + k, steps, control_hz=s.rate)))


def measure(s: Settings, runs: Mapping[tuple[str, float], Sequence[Kept]]) -> Result:
    """Climb rates per variant and height, and the highest height each variant climbs reliably (see the module
    doc)."""
    control_hz = s.rate
    n, heights = s.n(10, 3), QUICK_SWEEP_HEIGHTS if s.quick else SWEEP_HEIGHTS
    seconds, steps = _steps(s)
    variants = {}
    for v in VARIANTS:
        rates, times = {}, {}
        for h in heights:
            rs = [r.summary.to_dict() for r in runs[v, h]]
            ok = [climbed(r) for r in rs]
            rates[h] = sum(ok) / n
            done = [r["exit_step"] for r in rs if r["exit_step"] is not None]
            times[h] = float(np.median(done)) if done else None
        best = highest_reliable(rates)
        variants[v] = {
            "modules": VARIANTS[v],
            "climb_rate": {f"{h:.2f}": r for h, r in rates.items()},
            "median_steps_to_climb": {f"{h:.2f}": t for h, t in times.items()},
            "median_time_to_climb_s": {f"{h:.2f}": None if t is None else t / control_hz for h, t in times.items()},
            "highest_reliable_m": best,
        }
    summary = {
        "heights_m": list(heights),
        "seeds": n,
        "seed": s.seed,
        "steps": steps,
        "control_hz": float(control_hz),
        "duration_s": steps / control_hz,
        "quick_note": quick_note(STEP_S, seconds, control_hz) if s.quick else None,
        "rule": STEP_RULE,
        "reliable_share": RELIABLE,
        "variants": variants,
    }
    return Result("steps", summary)


#: Line of each variant: colour, dash, marker and marker size (large hollow to small filled, so that equal rates
#: stay visible without moving them).
STYLES = (
    {"color": "#1B9E77", "ls": "-", "marker": "o", "ms": 12, "mfc": "none"},
    {"color": "#D95F02", "ls": "--", "marker": "s", "ms": 9, "mfc": "none"},
    {"color": "#7570B3", "ls": ":", "marker": "^", "ms": 7},
    {"color": "0.3", "ls": "-.", "marker": "D", "ms": 4},
)


@styled
def plot(res: Result) -> Figure:
    """Climb rate against step height, one line per variant (equal rates drawn one over another, told apart by
    their markers), the reliability threshold dashed; the legend beside the axes."""
    plt = pyplot()
    s = res.summary
    fig, ax = plt.subplots(figsize=(10, 5), layout="constrained")
    for i, (v, d) in enumerate(s["variants"].items()):
        h = [float(k) for k in d["climb_rate"]]
        best = d["highest_reliable_m"]
        label = f"{v}\n(reliable up to {best * 100:g} cm)" if best is not None else f"{v}\n(none reliable)"
        ax.plot(np.array(h) * 100, list(d["climb_rate"].values()), mew=1.5, label=label, **STYLES[i % len(STYLES)])
    ax.axhline(
        s["reliable_share"], color="0.5", ls="--", lw=LINE["thin"], label=f"reliable: >= {s['reliable_share']:.0%}"
    )
    ax.set(
        xlabel="step height (cm)",
        ylabel=f"climbed (share of {s['seeds']} seeds)",
        ylim=(-0.04, 1.04),
        title=f"Single step, steering straight ahead ({s['steps'] / s.get('control_hz', 10.0):.0f} s at most per run"
        f" at {s.get('control_hz', 10.0):g} Hz)",
    )
    ax.yaxis.set_major_formatter(PercentFormatter(1.0))
    legend_outside(ax)
    return fig


def claims(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Beyond the paper: backbone control and the leg reflexes together climb the highest step (Fig. 10's modules,
    ablated)."""
    v = s["variants"]
    full, none = v["reflexes + backbone"]["highest_reliable_m"], v["neither"]["highest_reliable_m"]
    best = max((x["highest_reliable_m"] or 0.0) for x in v.values())
    return [
        holds(
            "backbone control with the leg reflexes climbs the highest step of all module sets",
            "beyond the paper: the modules of Fig. 10 ablated",
            (full or 0.0) >= best and (full or 0.0) > (none or 0.0),
            {name: x["highest_reliable_m"] for name, x in v.items()},
            f"highest step (m) climbed reliably ({s['rule']})",
            unit="m",
        )
    ]
