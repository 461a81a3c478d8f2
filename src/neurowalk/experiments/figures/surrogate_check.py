"""The planar surrogate against physics: calibration on held-out steering, and escape outcomes run by run.

A. Forward speed and yaw rate of the surrogate against fresh physics runs at steering pairs between
the calibration grid points (errors relative to full scale). B. The dead-end suite of Fig. 3/5
(simple deadlock, narrow passage and its ±20% variants; four networks; ``--seeds`` seeds) run on
both bodies with the same seeds: escape counts side by side, and the fraction of runs whose outcome
(escaped or not) is the same on both.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.ticker import MaxNLocator

from neurowalk.body.surrogate import load_calibration
from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.calibration.calibrate import held_pairs, validation
from neurowalk.experiments.calibration.fit import body_velocity
from neurowalk.experiments.calibration.subjects import CONTROL_HZ, HELD_OUT, WARMUP, WINDOW
from neurowalk.experiments.plan import RUN_SETTINGS
from neurowalk.experiments.reproduce.claims import Claim, holds
from neurowalk.experiments.study_runs import Kept, Term
from neurowalk.experiments.suites.deadends import NETWORKS, VARIANTS, table_counts, table_runs
from neurowalk.plotting.style import FONT, LINE, legend_outside, letter_panels, network_colour, pyplot, styled
from neurowalk.sim.config import EpisodeConfig

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from neurowalk.sim.episode import Episode

NAME = "surrogate"
QUICK_HELD_OUT = (-0.4, -0.05, 0.15, 0.75)


def agreement(phys_runs: list[list[Any]], sur_runs: list[list[Any]]) -> dict[str, Any]:
    """Per-run comparison of two outcome lists ([variant, network, seed, escaped, trapped] each)."""
    p = {tuple(r[:3]): r[3] for r in phys_runs}
    s = {tuple(r[:3]): r[3] for r in sur_runs}
    keys = sorted(set(p) & set(s))
    same = [p[k] == s[k] for k in keys]
    by_variant: dict[str, list[bool]] = {}
    for k, ok in zip(keys, same, strict=True):
        by_variant.setdefault(k[0], []).append(ok)
    return {
        "runs": len(keys),
        "same_outcome": int(sum(same)),
        "fraction": float(np.mean(same)) if keys else None,
        "by_variant": {v: float(np.mean(x)) for v, x in by_variant.items()},
        "differ": [[*k, p[k], s[k]] for k, ok in zip(keys, same, strict=True) if not ok],
    }


BODIES = ("amosii", "surrogate")  # the physics body, and its planar surrogate


def _window_velocity(ep: Episode) -> dict[str, Any]:
    """The steady body velocity (3,) (forward m/s, lateral m/s, yaw rad/s) of a held-out drive, after its warm-up."""
    return {"velocity": body_velocity(ep.trajectory.pose[WARMUP:], CONTROL_HZ)}


VELOCITY = Term("velocity", _window_velocity, {"velocity": "float64"})


def held_out(s: Settings) -> list[tuple[float, float]]:
    """The held-out steering pairs of the calibration check (quick: fewer)."""
    return held_pairs(QUICK_HELD_OUT if s.quick else HELD_OUT)


def runs(s: Settings) -> Iterator[Plan]:
    """The dead-end suite on both bodies (``s.seeds`` seeds: 10; quick: 1), labelled ``(body, dead end,
    network)``; and the calibration check's drives of the physics body at the held-out steering pairs (constant
    steering through the locomotion network, no sensor noise, as the calibration measures), labelled
    ``("held-out", O1, O2)``."""
    for body in BODIES:
        for plan in table_runs(s, body=body):
            yield Plan((body, *plan.label[1:]), plan.config, plan.terms)
    for pair in held_out(s):
        cfg = EpisodeConfig(arena="open", body="amosii", controller="fixed", steer=pair, noise=0.0,
                            control_hz=CONTROL_HZ, steps=WARMUP + WINDOW)  # fmt: skip
        yield Plan(("held-out", *pair), cfg, (VELOCITY,), fixed=RUN_SETTINGS)


def measure(s: Settings, runs: Mapping[tuple, Sequence[Kept]]) -> Result:
    """The outcome tables of both bodies and their agreement, run by run; the held-out calibration check (the
    surrogate's velocities against the physics drives at steering pairs between its grid's)."""
    cal = load_calibration()
    pairs = held_out(s)
    val = validation(cal, pairs, np.array([runs[("held-out", *p)][0].kept["velocity"]["velocity"] for p in pairs]))
    phys, sur = (table_counts(s, runs, body=b, prefix=(b,)) for b in BODIES)
    summary = {
        "seeds": s.n(full=10, quick=1),
        "first_seed": s.seed,
        "calibration": {
            "file_meta": {k: v for k, v in cal.meta.items() if k != "validation"},
            "tau_s": cal.tau_s,
            "delay_steps": cal.delay_steps,
            "startup_steps": cal.startup_steps,
        },
        "validation": val,
        "physics": phys,
        "surrogate": sur,
        "agreement": agreement(phys["runs"], sur["runs"]),
        "rule": "same outcome: the run escaped on both bodies or on neither (same arena, network and seed)",
    }
    return Result(NAME, summary)


@styled
def plot(res: Result) -> Figure:
    """A: held-out calibration scatter (surrogate against physics, fractions of full scale); B: escapes per dead end
    and network, physics bars (network colours) with the surrogate's count marked on each."""
    plt = pyplot()
    s = res.summary
    fig, ax = plt.subplots(1, 2, figsize=(16, 6.5), gridspec_kw={"width_ratios": [1, 2.2]}, layout="constrained")
    v = s["validation"]
    phys, sur, fs = np.asarray(v["physics"]), np.asarray(v["surrogate"]), v["full_scale"]
    ax[0].plot([-1, 1], [-1, 1], "k-", lw=LINE["thin"], label="equal")
    ax[0].plot(phys[:, 0] / fs["speed_m_s"], sur[:, 0] / fs["speed_m_s"], "o", color="C0", label="forward speed")
    ax[0].plot(phys[:, 2] / fs["yaw_rate_rad_s"], sur[:, 2] / fs["yaw_rate_rad_s"], "s", mfc="none", color="C1",
               mew=1.5, label="yaw rate")  # fmt: skip
    ax[0].set(
        xlabel="physics (fraction of full scale)",
        ylabel="surrogate (fraction of full scale)",
        aspect="equal",
        title=f"held-out steering\nmax error {v['speed_error_max']:.1%} speed, {v['yaw_rate_error_max']:.1%} turning",
    )
    legend_outside(ax[0], side="below", ncol=3)
    variants, nets = list(VARIANTS), list(NETWORKS)
    width = 0.8 / len(nets)
    for j, net in enumerate(nets):
        x = np.arange(len(variants)) + (j - (len(nets) - 1) / 2) * width
        pc = [s["physics"]["counts"][vn][net]["escaped"] for vn in variants]
        sc = [s["surrogate"]["counts"][vn][net]["escaped"] for vn in variants]
        ax[1].bar(x, pc, width * 0.9, color=network_colour(net), alpha=0.8, label=f"{net} (physics)")
        ax[1].plot(x, sc, "_", color="k", ms=16, mew=2.5)
    ax[1].plot([], [], "_", color="k", ms=16, mew=2.5, label="surrogate")
    ax[1].set_xticks(
        range(len(variants)), [vn.replace("narrow-passage", "passage").replace(" ", "\n", 1) for vn in variants]
    )
    ax[1].tick_params(axis="x", labelsize=FONT["note"])
    ax[1].yaxis.set_major_locator(MaxNLocator(integer=True))
    ax[1].set(xlabel="dead end", ylabel=f"escaped (runs, of {s['seeds']})", ylim=(0, s["seeds"] * 1.08))
    a = s["agreement"]
    ax[1].set_title(f"dead ends: same outcome in {a['same_outcome']}/{a['runs']} runs ({a['fraction']:.0%})")
    legend_outside(ax[1], side="below", ncol=3)
    letter_panels(ax)
    fig.suptitle("The planar surrogate against the physics body")
    return fig


def claims(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Beyond the paper: the planar surrogate and the physics robot agree on the dead-end outcomes."""
    a = s["agreement"]
    return [
        holds(
            "the planar surrogate ends the dead-end runs as the physics robot does in at least 80% of them",
            "beyond the paper: the surrogate stands in for the physics in Table 2",
            a["fraction"] is not None and a["fraction"] >= 0.8,
            f"{a['same_outcome']}/{a['runs']}",
            s["rule"],
            unit="runs with the same outcome",
        )
    ]
