"""Fig. 4: synaptic weight changes of the plastic sensory network for different inputs.

A. Constant inputs I1 = 1, I2 = -1 (an obstacle held on the left). From b = 2.4, q = 3.5 (the
   paper's start) and from several other starts, b1 and q1 rise and converge to the analytic
   fixed points sqrt(mu/(gamma(1 - k))) (4.63 and 7.04) whatever the start; b2 and q2, whose
   neuron is silent, barely move.
B. Changing inputs: obstacle episodes (the robot approaches an obstacle on one side or in a
   corner, turns, and leaves it behind), drawn from the run's seed. The weights of the stimulated
   side grow fast, peak-like, while the reflex (I > -0.5) is on, and decay slowly afterwards.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from neurowalk.experiments import Result
from neurowalk.neural.plasticity import fixed_point
from neurowalk.neural.sensory import distance_to_input, simulate
from neurowalk.neural.variants import get_variant
from neurowalk.plotting import pyplot

if TYPE_CHECKING:
    from matplotlib.figure import Figure

NAME = "fig4"
PAPER_START = (2.4, 3.5)  # b, q at the start of panel A (paper §2.1.2)
OTHER_STARTS = ((0.0, 0.0), (1.0, 1.0), (2.0, 3.0), (6.0, 10.0))
FAR_M = 0.45  # distance beyond the sensor's range (m)


def obstacle_episodes(n_steps: int, rng: np.random.Generator) -> tuple[np.ndarray, list[dict]]:
    """Inputs (n_steps, 2) of a robot meeting obstacles now and then.

    Each episode: an obstacle on the left, the right or both (a corner) comes from beyond the
    range to 0.10-0.25 m in 10-30 steps, stays for 5-60 steps while the robot turns, and falls
    behind in 5-15 steps; 150-500 free steps follow. Distances carry 5 mm noise.
    """
    d = np.full((n_steps, 2), FAR_M)
    episodes: list[dict] = []
    t = int(rng.integers(50, 150))
    while t < n_steps:
        side = str(rng.choice(["left", "right", "corner"], p=[0.4, 0.4, 0.2]))
        near = float(rng.uniform(0.10, 0.25))
        n_in, n_hold, n_out = (int(rng.integers(lo, hi)) for lo, hi in ((10, 30), (5, 60), (5, 15)))
        prof = np.concatenate([np.linspace(FAR_M, near, n_in), np.full(n_hold, near), np.linspace(near, FAR_M, n_out)])
        end = min(t + prof.size, n_steps)
        cols = {"left": [0], "right": [1], "corner": [0, 1]}[side]
        for c in cols:
            d[t:end, c] = prof[: end - t]
        episodes.append({"start": t, "end": end, "side": side, "closest_m": near})
        t = end + int(rng.integers(150, 500))
    d += rng.normal(0.0, 0.005, size=d.shape)
    return distance_to_input(d), episodes


def run(
    *, quick: bool = False, seed: int = 0, variant: str = "paper", params: dict[str, float] | None = None
) -> Result:
    """Compute both panels. ``quick`` shortens panel B; ``variant``/``params``: the network (default Eq. 1-6)."""
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

    rng = np.random.default_rng(seed)
    steps_b = 3000 if quick else 8000
    inputs, episodes = obstacle_episodes(steps_b, rng)
    tr = simulate(inputs, b0=PAPER_START[0], q0=PAPER_START[1], params=p)
    arrays.update(b_inputs=inputs, b_outputs=tr.outputs, b_b=tr.b, b_q=tr.q)
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
            "steps": steps_b,
            "seed": seed,
            "start": {"b": PAPER_START[0], "q": PAPER_START[1]},
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
    ax.set(xlabel="time step (0.1 s)", ylabel="weight", title="A  constant inputs I1 = 1, I2 = -1")
    ax.legend(loc="center right", fontsize=8)
    tb = np.arange(a["b_inputs"].shape[0])
    for row, (key, ylabel) in enumerate((("b_inputs", "input I"), ("b_outputs", "output O"), (None, "weight"))):
        axb = fig.add_subplot(gs[row, 1])
        if key:
            axb.plot(tb, a[key][:, 0], "C0", lw=0.8, label="left (1)")
            axb.plot(tb, a[key][:, 1], "C1", lw=0.8, label="right (2)")
            if key == "b_inputs":
                axb.axhline(-0.5, color="k", lw=0.6, ls=":")
                axb.set_title("B  changing inputs (obstacle episodes)")
        else:
            axb.plot(tb, a["b_b"][:, 0], "C0", label="b1")
            axb.plot(tb, a["b_b"][:, 1], "C1", label="b2")
            axb.plot(tb, a["b_q"][:, 0], "C0--", label="q1")
            axb.plot(tb, a["b_q"][:, 1], "C1--", label="q2")
            axb.set_xlabel("time step (0.1 s)")
        axb.set_ylabel(ylabel)
        axb.legend(loc="upper right", fontsize=7, ncol=4)
    return fig
