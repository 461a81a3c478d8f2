"""The latched spin: how the plastic network fails in Table 2 (the paper's "very small confined spaces").

A neuron that is on (O ≈ 1) while its partner is off (O ≈ -1) keeps itself on with no echo at all
(I = -1) while its drive b_on·1 + c·(-1) + 4.7·(-1) stays positive, i.e. while b_on + (q1 + q2)/2 > 4.7
(tanh saturation aside; facts §3.4: b ≥ 3, c ≥ 4 never switch off without decay); below that, an echo on
the side of the neuron that is on (its I above -1) holds it, as at a latch's start. In a pocket between a
box and a wall the turn grows these weights with every echo, the turn never switches off, and the
robot spins in place: the body is never blocked. This figure finds the first Table 2 environments whose
plastic run ends in a latched spin (the Table 2 failure rule) on the surrogate, with their kept traces, and
draws the path in the pocket, the steering, and b_on + mean q against 4.7.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from neurowalk.arenas import make_arena
from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.reproduce.claims import Claim, holds
from neurowalk.experiments.study_runs import Kept
from neurowalk.experiments.suites.random_envs import LATCH, STEPS, STRIDE, environments, failure_class, spec
from neurowalk.plotting import draw_arena
from neurowalk.plotting.style import LINE, SIDE_COLOURS, legend_outside, letter_panels, pyplot, styled, time_colorbar
from neurowalk.sim.episode import EpisodeConfig, seeds

if TYPE_CHECKING:
    from matplotlib.figure import Figure

THRESHOLD = 4.7  # the input weight: with no echo, the latch holds while b_on + mean q exceeds it
SHOWN = 2  # environments drawn
SEARCHED = 200  # environments searched for latched spins


def runs(s: Settings) -> Iterator[Plan]:
    """The plastic network (Eq. 1-6 unless ``s.variant``) in the first :data:`SEARCHED` Table 2 environments
    (quick: 40) on the surrogate, a latched spin kept with its traces."""
    for i, e in enumerate(_envs(s)):
        yield Plan(i, EpisodeConfig.from_spec(spec(e, "plastic", STEPS, "surrogate")), (LATCH,))


def measure(s: Settings, runs: Mapping[int, Sequence[Kept]]) -> Result:
    """The failures' classes over the environments searched, and the first :data:`SHOWN` latched spins."""
    envs = _envs(s)
    classes = [failure_class(runs[i][0].summary.to_dict()) for i in range(len(envs))]
    chosen = [i for i, c in enumerate(classes) if c == "latched spin"][:SHOWN]
    arrays: dict[str, np.ndarray] = {}
    shown = []
    for k, i in enumerate(chosen):
        r = runs[i][0]
        latch = r.kept["latch"]
        arrays.update({f"env{k}/{key}": latch[key] for key in ("pose", "outputs", "latch")})
        shown.append(
            {
                **envs[i],
                "latched_from_step": latch["latched_from_step"],
                "final_weights": r.summary.to_dict()["final_weights"],
                "end_turn_share": r.end_turn_share,
            }
        )
    counts = {c: classes.count(c) for c in ("latched spin", "wedged", "other")}
    summary = {
        "variant": s.variant or "paper",
        "params": s.params,
        "steps": STEPS,
        "seed": s.seed,
        "searched": len(envs),
        "failures": counts,
        "shown": shown,
        "stride": STRIDE,
        "threshold": THRESHOLD,
    }
    return Result("latched-spin", summary, arrays)


def _envs(s: Settings) -> list[dict[str, Any]]:
    """The environments searched: the first :data:`SEARCHED` of Table 2 (quick: 40)."""
    return environments(40 if s.quick else SEARCHED, s.seed)


def _arena(env: dict[str, Any], variant: str) -> Any:
    opts = spec(env, "plastic", 1, "surrogate", variant=variant)["arena_opts"]
    return make_arena("random", rng=seeds(EpisodeConfig(seed=env["seed"]))[2], **opts)


@styled
def plot(res: Result) -> Figure:
    """Per environment (a row, lettered across): the path coloured by time (colour bar, s; black after the latch),
    steering over time, and b_on + mean q against 4.7 (the dashed red line: when the latch began)."""
    plt = pyplot()
    s = res.summary
    n = max(1, len(s["shown"]))
    fig, axes = plt.subplots(
        n, 3, figsize=(17, 5.2 * n), squeeze=False, gridspec_kw={"width_ratios": [1, 1.3, 1.3]}, layout="constrained"
    )
    for k, env in enumerate(s["shown"]):
        pose, out, latch = (res.arrays[f"env{k}/{key}"] for key in ("pose", "outputs", "latch"))
        t = np.arange(len(pose)) * s["stride"] / 10.0
        start = env["latched_from_step"] / 10
        ax = axes[k, 0]
        path = draw_arena(ax, _arena(env, s["variant"]), pose, t=t)
        i0 = env["latched_from_step"] // s["stride"]
        ax.plot(*pose[i0:, :2].T, c="k", lw=LINE["thin"], label="after the latch")
        if path is not None:
            time_colorbar(path, ax)
        legend_outside(ax, side="below", ncol=3)
        ax.set_title(f"{env['n_boxes']} boxes, seed {env['seed']}: latched from {start:.0f} s")
        for j, (side, legs) in enumerate((("left", "right"), ("right", "left"))):
            label = f"O{j + 1} ({side} neuron → {legs} legs)"
            axes[k, 1].plot(t, out[:, j], color=SIDE_COLOURS[side], lw=LINE["thin"], label=label)
        axes[k, 1].set(xlabel="time (s)", ylabel="steering O", ylim=(-1.1, 1.1), yticks=(-1, 0, 1), title="steering")
        axes[k, 2].plot(t, latch, c="k", lw=LINE["trace"], label="b_on + (q1 + q2)/2")
        axes[k, 2].axhline(s["threshold"], c="0.4", ls=":", label=f"{s['threshold']} (input weight): latch holds above")
        axes[k, 2].set(xlabel="time (s)", ylabel="weight", title="the latch's weights")
        for ax in axes[k, 1:]:
            ax.axvline(start, c="r", ls="--", lw=LINE["trace"], label="the latch begins")
            legend_outside(ax, side="below", ncol=2)
    if not s["shown"]:
        axes[0, 0].text(0.5, 0.5, "no latched spin found", ha="center", transform=axes[0, 0].transAxes)
    else:
        letter_panels(axes[: len(s["shown"])].flat)
    f = s["failures"]
    fig.suptitle(
        f"Latched spins: plastic ({s['variant']}) on the surrogate, {s['searched']} Table 2 environments: "
        f"{f['latched spin']} latched spins, {f['wedged']} wedged, {f['other']} other failures"
    )
    return fig


def claims(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Beyond the paper: the plastic network's failures in random environments are mostly latched spins."""
    f = s["failures"]
    total = sum(f.values())
    return [
        holds(
            "the plastic network's failures in random environments are mostly latched spins (a turn held by the "
            "learned weights)",
            "beyond the paper: neurowalk's diagnosis",
            total > 0 and f["latched spin"] > total / 2,
            f"{f['latched spin']} of {total} failures",
            f"failure classes of {s['searched']} surrogate runs of {s['steps']} steps: {f}",
        )
    ]
