"""Fig. 4: synaptic weight changes of the plastic sensory network for different inputs.

A. Constant inputs I1 = 1, I2 = -1 (an obstacle held on the left). From b = 2.4, q = 3.5 (the
   paper's start) and from several other starts, b1 and q1 rise and converge to the analytic
   fixed points sqrt(mu/(gamma(1 - k))) (4.63 and 7.04) whatever the start; b2 and q2, whose
   neuron is silent, barely move.
B. Changing inputs, recorded in a simulated environment as in the paper: the ultrasonic inputs
   (I1, I2) of a physics run of AMOSII (:data:`PANEL_B_ARENA` arena, plastic network from the
   panel's start b = 2.4, q = 3.5, the figure's seed and control rate), replayed offline through
   the plastic network from the same start. The robot meets walls and corners on either side,
   turns, and leaves them behind; the weights of the stimulated side grow fast, peak-like, while
   the reflex (I > -0.5) is on, and decay slowly afterwards. The replay reproduces the weights the
   network had in the run (their largest difference is in the json).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from neurowalk.experiments import Result
from neurowalk.experiments.suites.timing import SIM_HZ
from neurowalk.neural.plasticity import fixed_point
from neurowalk.neural.sensory import simulate
from neurowalk.neural.variants import get_variant
from neurowalk.plotting import pyplot
from neurowalk.sim.episode import EpisodeConfig, run_episode

if TYPE_CHECKING:
    from matplotlib.figure import Figure

NAME = "fig4"
PAPER_START = (2.4, 3.5)  # b, q at the start of panel A (paper §2.1.2)
OTHER_STARTS = ((0.0, 0.0), (1.0, 1.0), (2.0, 3.0), (6.0, 10.0))
PANEL_B_ARENA = "difficult"  # the original 9 x 9 m arena: walls, sharp corners, narrow passages
PANEL_B_STEPS = 5000  # control steps of panel B's physics run (the network's rates are per control step)
QUICK_B_STEPS = 3000  # with ``quick``: at seed 0 still walls on both sides


def reflex_episodes(inputs: np.ndarray, distance: np.ndarray, t: np.ndarray, threshold: float) -> list[dict]:
    """A run's stretches with an obstacle in reflex range: rows where I1 or I2 (``inputs``, (T, 2)) > ``threshold``.

    Each: ``start``, ``end`` (rows, end exclusive), ``start_s`` (time of the first row, s, from ``t`` (T,)),
    ``side`` (left, right or corner: both sensors), ``closest_m`` (nearest reading, from ``distance`` (T, 2) m).
    """
    on = inputs > threshold
    edges = np.diff(np.concatenate([[0], np.any(on, axis=1).astype(int), [0]]))
    out = []
    for a, b in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True):
        left, right = bool(on[a:b, 0].any()), bool(on[a:b, 1].any())
        near = distance[a:b][np.isfinite(distance[a:b])]
        out.append(
            {
                "start": int(a),
                "end": int(b),
                "start_s": round(float(t[a]), 4),
                "side": "corner" if left and right else "left" if left else "right",
                "closest_m": float(near.min()) if near.size else None,
            }
        )
    return out


def run(
    *,
    quick: bool = False,
    seed: int = 0,
    variant: str = "paper",
    params: dict[str, float] | None = None,
    control_hz: float = SIM_HZ,
) -> Result:
    """Compute both panels.

    ``quick`` shortens panel B's physics run (:data:`QUICK_B_STEPS` control steps instead of
    :data:`PANEL_B_STEPS`); ``seed``, ``control_hz``: that run's seed and control rate (Hz); ``variant``/``params``:
    the network (default Eq. 1-6).
    """
    p = get_variant(variant, params).sensory
    b_star = fixed_point(p.mu_b, p.gamma_b, p.k)
    q_star = fixed_point(p.mu_q, p.gamma_q, p.k)
    steps_a = 5000
    const = np.tile([1.0, -1.0], (steps_a, 1))
    arrays: dict[str, np.ndarray] = {}
    converged = []
    for i, (b0, q0) in enumerate((PAPER_START, *OTHER_STARTS)):
        tr = simulate(const, b0=b0, q0=q0, params=p)
        arrays[f"a{i}_b"], arrays[f"a{i}_q"] = tr.b, tr.q
        converged.append(
            {
                "b0": b0,
                "q0": q0,
                "b1": tr.b[-1, 0],
                "q1": tr.q[-1, 0],
                "b2": tr.b[-1, 1],
                "q2": tr.q[-1, 1],
                "b1_rel_error": abs(tr.b[-1, 0] - b_star) / b_star,
                "q1_rel_error": abs(tr.q[-1, 0] - q_star) / q_star,
            }
        )

    steps_b = QUICK_B_STEPS if quick else PANEL_B_STEPS
    cfg = EpisodeConfig(
        arena=PANEL_B_ARENA,
        controller="plastic",
        steps=steps_b,
        seed=seed,
        control_hz=control_hz,
        b0=PAPER_START[0],
        q0=PAPER_START[1],
        variant=variant,
        params=params,
    )
    rec = run_episode(cfg).trajectory
    inputs = rec.inputs
    tr = simulate(inputs, b0=PAPER_START[0], q0=PAPER_START[1], params=p)
    replay_diff = float(max(np.abs(tr.b - rec.b).max(), np.abs(tr.q - rec.q).max()))
    episodes = reflex_episodes(inputs, rec.us_distance, rec.t, p.reflex_threshold)
    arrays.update(b_t=rec.t, b_inputs=inputs, b_outputs=tr.outputs, b_b=tr.b, b_q=tr.q)
    reflex = inputs > p.reflex_threshold
    db = np.diff(np.vstack([[PAPER_START[0]] * 2, tr.b]), axis=0)
    growth = float(np.mean(db[reflex][db[reflex] > 0])) if np.any(db[reflex] > 0) else 0.0
    decay = float(np.mean(-db[~reflex][db[~reflex] < 0])) if np.any(db[~reflex] < 0) else 0.0
    summary = {
        "fixed_points": {"b": b_star, "q": q_star, "rule": "sqrt(mu/(gamma*(1-k)))"},
        "panel_a": {
            "inputs": [1.0, -1.0],
            "steps": steps_a,
            "starts": converged,
            "max_b1_rel_error": max(c["b1_rel_error"] for c in converged),
            "max_q1_rel_error": max(c["q1_rel_error"] for c in converged),
        },
        "panel_b": {
            "source": "ultrasonic inputs recorded in a physics run, replayed offline through the plastic network",
            "arena": PANEL_B_ARENA,
            "body": cfg.body,
            "controller": cfg.controller,
            "steps": steps_b,
            "seed": seed,
            "control_hz": float(control_hz),
            "duration_s": steps_b / control_hz,
            "start": {"b": PAPER_START[0], "q": PAPER_START[1]},
            "replay_max_abs_diff_from_run": replay_diff,
            "episodes": episodes,
            "mean_db_per_step_reflex_on": growth,
            "mean_decay_per_step_reflex_off": decay,
            "growth_to_decay_ratio": growth / decay if decay > 0 else None,
        },
        "params": vars(p),
        "variant": variant,
    }
    return Result(NAME, summary, arrays)


def plot(res: Result) -> Figure:
    """Panel A (weights for constant inputs, several starts) and panel B (changing inputs)."""
    plt = pyplot()

    s, a = res.summary, res.arrays
    fig = plt.figure(figsize=(12, 8), constrained_layout=True)
    gs = fig.add_gridspec(3, 2, width_ratios=[1, 1.6])
    ax = fig.add_subplot(gs[:, 0])
    n = len(s["panel_a"]["starts"])
    for i in range(n):
        t = np.arange(1, a[f"a{i}_b"].shape[0] + 1)
        lw, alpha = (2.0, 1.0) if i == 0 else (1.0, 0.6)
        ax.plot(t, a[f"a{i}_b"][:, 0], "C0", lw=lw, alpha=alpha, label="b1" if i == 0 else None)
        ax.plot(t, a[f"a{i}_q"][:, 0], "C3", lw=lw, alpha=alpha, label="q1" if i == 0 else None)
        ax.plot(t, a[f"a{i}_b"][:, 1], "C0--", lw=lw, alpha=alpha, label="b2" if i == 0 else None)
        ax.plot(t, a[f"a{i}_q"][:, 1], "C3--", lw=lw, alpha=alpha, label="q2" if i == 0 else None)
    for v, lab in ((s["fixed_points"]["b"], "b*"), (s["fixed_points"]["q"], "q*")):
        ax.axhline(v, color="k", lw=0.8, ls=":")
        ax.text(t[0], v, f" {lab} = {v:.2f}", va="bottom", ha="left")
    ax.set(xlabel="time step (network update)", ylabel="weight", title="A  constant inputs I1 = 1, I2 = -1")
    ax.legend(loc="center right", fontsize=8)
    pb = s["panel_b"]
    tb = a["b_t"] if "b_t" in a else np.arange(a["b_inputs"].shape[0])
    for row, (key, ylabel) in enumerate((("b_inputs", "input I"), ("b_outputs", "output O"), (None, "weight"))):
        axb = fig.add_subplot(gs[row, 1])
        if key:
            axb.plot(tb, a[key][:, 0], "C0", lw=0.8, label="left (1)")
            axb.plot(tb, a[key][:, 1], "C1", lw=0.8, label="right (2)")
            if key == "b_inputs":
                axb.axhline(-0.5, color="k", lw=0.6, ls=":")
                axb.set_title(
                    f"B  changing inputs: AMOSII in the {pb.get('arena', '?')} arena, seed {pb['seed']}, "
                    f"{pb.get('control_hz', SIM_HZ):g} Hz"
                )
        else:
            axb.plot(tb, a["b_b"][:, 0], "C0", label="b1")
            axb.plot(tb, a["b_b"][:, 1], "C1", label="b2")
            axb.plot(tb, a["b_q"][:, 0], "C0--", label="q1")
            axb.plot(tb, a["b_q"][:, 1], "C1--", label="q2")
            axb.set_xlabel("time (s)" if "b_t" in a else "time step")
        axb.set_ylabel(ylabel)
        axb.legend(loc="upper right", fontsize=7, ncol=4)
    return fig
