"""The latched spin: how the plastic network fails in Table 2 (the paper's "very small confined spaces").

A neuron that is on (O ≈ 1) while its partner is off (O ≈ -1) keeps itself on with no echo at all
(I = -1) while its drive b_on·1 + c·(-1) + 4.7·(-1) stays positive, i.e. while b_on + (q1 + q2)/2 > 4.7
(tanh saturation aside; facts §3.4: b ≥ 3, c ≥ 4 never switch off without decay). In a pocket between a
box and a wall the turn grows these weights with every echo, the turn never switches off, and the
robot spins in place: the body is never blocked. This figure finds the first Table 2 environments whose
plastic run ends in a latched spin (the Table 2 failure rule) on the surrogate, reruns them with their
trajectories, and draws the path in the pocket, the steering, and b_on + mean q against 4.7.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from neurowalk.arenas import make_arena
from neurowalk.experiments import Result, Settings
from neurowalk.experiments.stores import run_store, store_folder
from neurowalk.experiments.suites.random_envs import STEPS, environments, failure_class, spec
from neurowalk.metrics import turn_state
from neurowalk.plotting import draw_arena
from neurowalk.plotting.style import LINE, SIDE_COLOURS, legend_outside, letter_panels, pyplot, time_colorbar
from neurowalk.runners.specs import spec_key
from neurowalk.sim.episode import EpisodeConfig, run_episode, seeds

if TYPE_CHECKING:
    from matplotlib.figure import Figure

THRESHOLD = 4.7  # the input weight: the latch holds while b_on + mean q exceeds it
SHOWN = 2  # environments drawn
SEARCHED = 200  # environments searched for latched spins


def run(s: Settings) -> Result:
    """Search the first :data:`SEARCHED` Table 2 environments (quick: 40) for latched spins of the plastic network
    (Eq. 1-6 unless ``s.variant``) through a resumable store in ``s.out``; keep two. The settings: :class:`Settings`.
    """
    variant = s.variant or "paper"
    envs = environments(40 if s.quick else SEARCHED, s.seed)
    specs = [spec(e, "plastic", STEPS, "surrogate", variant=variant, params=s.params) for e in envs]
    with store_folder(s.out) as folder:
        stored, _ = run_store(specs, folder, s.workers or 2)
    summaries = [stored[spec_key(x)] for x in specs]
    cfgs = [EpisodeConfig.from_spec(x) for x in specs]
    classes = [failure_class(x) for x in summaries]
    chosen = [i for i, c in enumerate(classes) if c == "latched spin"][:SHOWN]
    arrays: dict[str, np.ndarray] = {}
    shown = []
    for k, i in enumerate(chosen):
        ep = run_episode(cfgs[i])
        tr = ep.trajectory
        on = np.where(tr.outputs[:, 0:1] > tr.outputs[:, 1:2], tr.b[:, 0:1], tr.b[:, 1:2])[:, 0]
        arrays[f"env{k}/pose"] = tr.pose[::5].copy()
        arrays[f"env{k}/outputs"] = tr.outputs[::5].copy()
        arrays[f"env{k}/latch"] = (on + tr.q.mean(axis=1))[::5].copy()
        start = _latch_start(tr.outputs)
        shown.append(
            {
                **envs[i],
                "latched_from_step": start,
                "final_weights": ep.summary["final_weights"],
                "end_turn_share": ep.summary["end_turn_share"],
            }
        )
    counts = {c: classes.count(c) for c in ("latched spin", "wedged", "other")}
    summary = {
        "variant": variant,
        "params": s.params,
        "steps": STEPS,
        "seed": s.seed,
        "searched": len(envs),
        "failures": counts,
        "shown": shown,
        "stride": 5,
        "threshold": THRESHOLD,
    }
    return Result("latched-spin", summary, arrays)


def _latch_start(outputs: np.ndarray) -> int:
    """First step of the final unbroken run of one turn direction (the latch)."""
    s = turn_state(outputs)
    last = s[-1]
    k = len(s) - 1
    while k > 0 and s[k - 1] == last:
        k -= 1
    return int(k)


def _arena(env: dict[str, Any], variant: str) -> Any:
    opts = spec(env, "plastic", 1, "surrogate", variant=variant)["arena_opts"]
    return make_arena("random", rng=seeds(EpisodeConfig(seed=env["seed"]))[2], **opts)


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
        axes[k, 1].plot(
            t, out[:, 0], color=SIDE_COLOURS["left"], lw=LINE["thin"], label="O1 (left neuron → right legs)"
        )
        axes[k, 1].plot(
            t, out[:, 1], color=SIDE_COLOURS["right"], lw=LINE["thin"], label="O2 (right neuron → left legs)"
        )
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
