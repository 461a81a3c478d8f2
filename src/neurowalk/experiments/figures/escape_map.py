"""Escape map: escape rate against trap size, for the plastic, static and Braitenberg networks.

Three sweeps, 5000 control steps per run (at any ``control_hz``: the networks' steps; seconds follow the
rate): the simple deadlock's width (0.6-1.6 m), the narrow passage's gap between its end obstacles, and the
narrow passage's width at the mouth (its end is narrower by the funnel). Where each network works and where it
fails: the plastic network's long turns escape narrow passages that trap the static one, but in a very tight
space (some wall always within reflex range) its weights stay grown and it keeps turning on the spot.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from matplotlib.ticker import PercentFormatter

from neurowalk.experiments import Result, Settings
from neurowalk.experiments.stores import store_folder
from neurowalk.experiments.suites.deadends import TRAP_STEPS, stored_runs
from neurowalk.experiments.suites.timing import SIM_HZ
from neurowalk.plotting.style import legend_outside, letter_panels, network_line, pyplot
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


def run(s: Settings) -> Result:
    """Every sweep x network x size x seed: ``s.seeds`` seeds (default 5; 1 with ``quick``), with the settings it
    takes (:data:`~neurowalk.experiments.FIGURES`): climbing, variant, gait, control_hz (each run keeps its
    :data:`TRAP_STEPS` control steps), workers; its runs are kept in the resumable store ``s.out/results.sqlite``."""
    quick, seed, climbing, n = s.quick, s.seed, s.climbing, s.n(full=5, quick=QUICK_SEEDS)
    variant, gait, control_hz = s.variant or "paper", s.gait or "wave", s.control_hz or SIM_HZ
    keys, configs = [], []
    sweeps = {}
    for label, (arena, opt, sizes) in SWEEPS.items():
        if quick:
            sizes = (sizes[0], sizes[-1])[:QUICK_SIZES]
        sweeps[label] = {"arena": arena, "option": opt, "sizes": list(sizes)}
        for size in sizes:
            for net in NETWORKS:
                for i in range(seed, seed + n):
                    keys.append((label, size, net))
                    configs.append(
                        EpisodeConfig(
                            arena=arena,
                            arena_opts={opt: size},
                            controller=net,
                            steps=TRAP_STEPS,
                            until="escaped",
                            seed=i,
                            control_hz=control_hz,
                            reflexes=climbing,
                            backbone=climbing,
                            variant=variant,
                            gait=gait,
                        )
                    )
    with store_folder(s.out) as folder:
        results = stored_runs(configs, folder, "results.sqlite", s.workers or 2, True, "escape map", traces=False)
    counts: dict = {}
    for (label, size, net), r in zip(keys, results, strict=True):
        c = counts.setdefault(label, {}).setdefault(net, {}).setdefault(str(size), {"runs": 0, "escaped": 0})
        c["runs"] += 1
        c["escaped"] += int(bool(r["escaped"]))
    summary = {
        "seeds": n,
        "first_seed": seed,
        "climbing": climbing,
        "variant": variant,
        "gait": gait,
        "quick": quick,
        "steps": TRAP_STEPS,
        "control_hz": control_hz,
        "seconds": TRAP_STEPS / control_hz,
        "sweeps": sweeps,
        "counts": counts,
        "rule": "escape rate = runs that reached the exit region behind the trap's mouth / runs",
        "stop_rule": UNTIL["escaped"] + "; a run that does not escape runs all its steps",
    }
    return Result(NAME, summary, {})


#: Marker of each network: large hollow to small filled, so that equal rates stay visible without moving them.
MARKERS = {"plastic": ("o", 11, "none"), "static": ("s", 7, None), "braitenberg": ("^", 5, None)}


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
