"""Escape map: escape rate against trap size, for the plastic, static and Braitenberg networks.

Three sweeps, 5000 control steps per run (at any ``control_hz``: the networks' steps; seconds follow the
rate): the simple deadlock's width (0.6-1.6 m), the narrow passage's gap between its end obstacles, and the
narrow passage's width at the mouth (its end is narrower by the funnel). Where each network works and where it
fails: the plastic network's long turns escape narrow passages that trap the static one, but in a very tight
space (some wall always within reflex range) its weights stay grown and it keeps turning on the spot.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.ticker import PercentFormatter

from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.reproduce.claims import Claim, holds
from neurowalk.experiments.study import grid
from neurowalk.experiments.suites.deadends import TRAP_STEPS
from neurowalk.plotting.style import legend_outside, letter_panels, network_line, pyplot, styled
from neurowalk.sim.config import UNTIL
from neurowalk.sim.episode import EpisodeConfig

if TYPE_CHECKING:
    from matplotlib.figure import Figure

NAME = "escape-map"
NETWORKS = ("plastic", "static", "braitenberg")
SWEEPS = {
    "simple-deadlock width (m)": ("simple-deadlock", "width", (0.6, 0.8, 1.0, 1.2, 1.4, 1.6)),
    "narrow-passage gap (m)": ("narrow-passage", "gap", (0.15, 0.2, 0.25, 0.3, 0.36, 0.42)),
    "narrow-passage width (m)": ("narrow-passage", "width", (1.0, 1.2, 1.4, 1.6, 1.8, 2.0)),
}
QUICK_SIZES = 2  # sizes per sweep with --quick (the smallest and the largest)
QUICK_SEEDS = 1  # seeds per size with --quick (unless --seeds)


def sizes(s: Settings) -> dict[str, dict]:
    """Each sweep's arena, option and sizes (the smallest and largest with ``quick``)."""
    return {
        label: {"arena": arena, "option": opt, "sizes": list((sizes[0], sizes[-1])[:QUICK_SIZES] if s.quick else sizes)}
        for label, (arena, opt, sizes) in SWEEPS.items()
    }


def runs(s: Settings) -> Iterator[Plan]:
    """Every sweep x size x network x seed: ``s.seeds`` seeds (default 5; 1 with ``quick``), each run its
    :data:`TRAP_STEPS` control steps at any rate, stopped once escaped."""
    for label, sweep in sizes(s).items():
        base = EpisodeConfig(arena=sweep["arena"], steps=TRAP_STEPS, until="escaped")
        axes = {f"arena_opts.{sweep['option']}": sweep["sizes"], "controller": NETWORKS}
        for plan in grid(base, s.seed_range(5, QUICK_SEEDS), **axes):
            yield Plan((label, *plan.label), plan.config)


def measure(s: Settings, runs: Mapping[tuple, list]) -> Result:
    """Escaped runs out of runs, by sweep, network and size."""
    counts: dict = {}
    for (label, size, net), rs in runs.items():
        counts.setdefault(label, {}).setdefault(net, {})[str(size)] = {
            "runs": len(rs),
            "escaped": sum(bool(r.escaped) for r in rs),
        }
    summary = {
        "seeds": s.n(full=5, quick=QUICK_SEEDS),
        "first_seed": s.seed,
        "climbing": s.climbing,
        "variant": s.variant or "paper",
        "gait": s.gait or "wave",
        "quick": s.quick,
        "steps": TRAP_STEPS,
        "control_hz": s.rate,
        "seconds": TRAP_STEPS / s.rate,
        "sweeps": sizes(s),
        "counts": counts,
        "rule": "escape rate = runs that reached the exit region behind the trap's mouth / runs",
        "stop_rule": UNTIL["escaped"] + "; a run that does not escape runs all its steps",
    }
    return Result(NAME, summary, {})


#: Marker of each network: large hollow to small filled, so that equal rates stay visible without moving them.
MARKERS = {"plastic": ("o", 11, "none"), "static": ("s", 7, None), "braitenberg": ("^", 5, None)}


@styled
def plot(res: Result) -> Figure:
    """One panel per sweep (A, B, C): escape rate against size, one line per network (its colour and dash; equal
    rates drawn one over another, told apart by their markers); one legend for all."""
    plt = pyplot()
    s = res.summary
    n = len(s["sweeps"])
    fig, axes = plt.subplots(1, n, figsize=(5 * n + 1.5, 4.8), layout="constrained", sharey=True)
    axes = list(np.atleast_1d(axes))
    for ax, (label, sw) in zip(axes, s["sweeps"].items(), strict=True):
        for net in NETWORKS:
            c = s["counts"][label][net]
            rate = np.array([c[str(x)]["escaped"] / c[str(x)]["runs"] for x in sw["sizes"]])
            marker, size, face = MARKERS.get(net, ("o", 6, None))
            ax.plot(sw["sizes"], rate, marker=marker, ms=size, mfc=face, mew=1.5, label=net, **network_line(net))
        ax.set(xlabel=label.replace("-", " "), ylim=(-0.04, 1.04), title=label.split(" (")[0].replace("-", " "))
        ax.yaxis.set_major_formatter(PercentFormatter(1.0))
    axes[0].set_ylabel(f"escaped (share of {s['seeds']} seeds)")
    letter_panels(axes)
    legend_outside(axes[-1])
    fig.suptitle(
        f"Escape rate against trap size: {s['seeds']} seeds per size, {s['steps']} control steps "
        f"({s['steps'] / s.get('control_hz', 10.0):g} s) per run"
    )
    return fig


def claims(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Beyond the paper: over every trap size swept, the plastic network escapes at least as often as the static
    one, and the static one at least as often as the Braitenberg vehicle (no memory)."""
    claims = []
    for label, by_net in s["counts"].items():
        total = {
            net: (sum(c["escaped"] for c in cells.values()), sum(c["runs"] for c in cells.values()))
            for net, cells in by_net.items()
        }
        (p, n), (st, _), (br, _) = total["plastic"], total["static"], total["braitenberg"]
        claims.append(
            holds(
                f"{label}: escapes, plastic >= static >= Braitenberg",
                "beyond the paper: memory and plasticity widen the traps escaped",
                p >= st >= br,
                f"plastic {p}/{n}, static {st}/{n}, Braitenberg {br}/{n}",
                f"escaped runs over the sizes {s['sweeps'][label]['sizes']}, {s['seeds']} seeds each",
                unit="runs escaped",
            )
        )
    return claims
