"""Fig. 2: neural dynamics of the sensory network with frozen weights.

B-D. One neuron with self connection b: near-linear input-output relation for small b (B),
     hysteresis around b = 2.4 (C), a two-state switch that no input in [-1, 1] can flip for
     large b (D). Stable fixed points solid, unstable dotted; the measured up and down sweeps on
     top.
E.   The two-neuron network (right input held at -1, no obstacle): hysteresis of the left output
     for the static network (b = 2.4, c = -3.5), the authors' start (2, -3), and the learned
     weights (4.63, -7.04), which latch on.
F.   Hysteresis width against b: one neuron (analytic and measured) and the two-neuron network
     with c = -3.5.
G.   Hysteresis width of the two-neuron network over (b, c); black where it latches on.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from neurowalk.experiments import Result
from neurowalk.neural.analysis import (
    hysteresis_loop,
    hysteresis_width_map,
    single_neuron_branches,
    single_neuron_thresholds,
)
from neurowalk.plotting import pyplot

if TYPE_CHECKING:
    from matplotlib.figure import Figure

NAME = "fig2"
PANEL_B = (0.5, 2.4, 8.0)  # self weights of panels B, C, D
LOOPS = ((2.4, -3.5), (2.0, -3.0), (4.63, -7.04))  # (b, c) of panel E


def _thresholds(loop: object) -> dict:
    return {
        "switch_on": loop.switch_on,
        "switch_off": loop.switch_off,  # type: ignore[attr-defined]
        "width": loop.width,
        "latched": loop.switch_on is not None and loop.switch_off is None,
    }  # type: ignore[attr-defined]


def run(*, quick: bool = False, seed: int = 0) -> Result:
    """Compute every panel (deterministic; ``seed`` is unused). ``quick`` coarsens the grids."""
    n_levels = 101 if quick else 201
    b_grid = np.round(np.linspace(0.0, 6.0, 13 if quick else 25), 6)
    arrays: dict[str, np.ndarray] = {"b_grid": b_grid}
    single = []
    for b in b_grid:
        loop = hysteresis_loop(float(b), 0.0, single=True, n_levels=n_levels)
        th = single_neuron_thresholds(float(b))
        single.append(
            {
                "b": float(b),
                **_thresholds(loop),
                "switch_on_analytic": th[0] if th else None,
                "switch_off_analytic": th[1] if th else None,
                "width_analytic": (th[0] - th[1]) if th else 0.0,
            }
        )
    for i, b in enumerate(PANEL_B):
        branch_i, branch_o, stable = single_neuron_branches(b)
        loop = hysteresis_loop(b, 0.0, single=True, n_levels=n_levels)
        arrays.update(
            {
                f"n{i}_branch_i": branch_i,
                f"n{i}_branch_o": branch_o,
                f"n{i}_stable": stable,
                f"n{i}_levels": loop.levels,
                f"n{i}_out": loop.outputs[:, 0],
            }
        )
    two = []
    for i, (b, c) in enumerate(LOOPS):
        loop = hysteresis_loop(b, c, n_levels=n_levels)
        arrays[f"e{i}_levels"], arrays[f"e{i}_out"] = loop.levels, loop.outputs
        two.append({"b": b, "c": c, **_thresholds(loop)})
    two_vs_b = [
        {"b": float(b), "c": -3.5, **_thresholds(hysteresis_loop(float(b), -3.5, n_levels=n_levels))} for b in b_grid
    ]
    mb = np.linspace(0.0, 5.0, 11 if quick else 26)
    mc = np.linspace(-8.0, 0.0, 9 if quick else 33)
    arrays.update(map_b=mb, map_c=mc, map_width=hysteresis_width_map(mb, mc, n_levels=n_levels))
    summary = {
        "single_neuron": single,
        "two_neuron_loops": two,
        "two_neuron_vs_b": two_vs_b,
        "input_weight_a": 4.7,
        "other_input": -1.0,
        "notes": "thresholds are inputs I in [-1, 1]; width = switch_on - switch_off; "
        "latched = switched on and never off within [-1, 1]; switch_on null = never switched on",
    }
    return Result(NAME, summary, arrays)


def plot(res: Result) -> Figure:
    """Seven panels, B-G, as described in the module docstring."""
    plt = pyplot()

    a, s = res.arrays, res.summary
    fig = plt.figure(figsize=(14, 8), constrained_layout=True)
    gs = fig.add_gridspec(2, 4)
    for i, (b, lab) in enumerate(zip(PANEL_B, "BCD", strict=True)):
        ax = fig.add_subplot(gs[0, i])
        bi, bo, st = a[f"n{i}_branch_i"], a[f"n{i}_branch_o"], a[f"n{i}_stable"].astype(bool)
        ax.plot(np.where(st, bi, np.nan), bo, color="green", lw=2, label="stable")
        ax.plot(np.where(~st, bi, np.nan), bo, color="orange", ls=":", lw=2, label="unstable")
        lv, out = a[f"n{i}_levels"], a[f"n{i}_out"]
        half = lv.size // 2
        ax.plot(lv[:half], out[:half], "b-", lw=0.8, alpha=0.6, label="sweep up")
        ax.plot(lv[half:], out[half:], "r-", lw=0.8, alpha=0.6, label="sweep down")
        ax.set(
            xlim=(-1, 1), ylim=(-1.05, 1.05), xlabel="input I", ylabel="output O", title=f"{lab}  one neuron, b = {b}"
        )
        if i == 0:
            ax.legend(fontsize=7, loc="upper left")
    ax = fig.add_subplot(gs[0, 3])
    for i, loop in enumerate(s["two_neuron_loops"]):
        lv, out = a[f"e{i}_levels"], a[f"e{i}_out"][:, 0]
        ax.plot(lv, out, color=f"C{i}", label=f"b = {loop['b']}, c = {loop['c']}")
    ax.set(xlabel="left input I1 (I2 = -1)", ylabel="left output O1", title="E  two neurons: hysteresis")
    ax.legend(fontsize=7, loc="upper left")
    ax = fig.add_subplot(gs[1, 0:2])
    b = np.array([r["b"] for r in s["single_neuron"]])
    w = np.array([r["width"] if r["width"] is not None else np.nan for r in s["single_neuron"]], dtype=float)
    wa = np.array([r["width_analytic"] for r in s["single_neuron"]], dtype=float)
    w2 = np.array([r["width"] if r["width"] is not None else np.nan for r in s["two_neuron_vs_b"]], dtype=float)
    ax.plot(b, wa, "k-", label="one neuron, analytic")
    ax.plot(b, w, "ko", ms=4, label="one neuron, measured")
    ax.plot(b, w2, "C0s-", ms=4, label="two neurons, c = -3.5")
    ax.axhline(2.0, color="gray", lw=0.6, ls=":")
    ax.set(
        xlabel="self connection b",
        ylabel="hysteresis width (input units)",
        title="F  hysteresis width grows with b (gaps: latched or never switched)",
    )
    ax.legend(fontsize=8)
    ax = fig.add_subplot(gs[1, 2:4])
    wm = np.ma.masked_invalid(a["map_width"])
    cmap = plt.get_cmap("viridis").with_extremes(bad="black")
    im = ax.pcolormesh(a["map_c"], a["map_b"], wm, cmap=cmap, shading="nearest")
    fig.colorbar(im, ax=ax, label="hysteresis width")
    ax.plot([-3.5], [2.4], "w*", ms=12)
    ax.plot([-7.04], [4.63], "r*", ms=12)
    ax.set(
        xlabel="inhibitory weight c",
        ylabel="self connection b",
        title="G  two neurons: width over (b, c); black: latched",
    )
    return fig
