"""The picture of Fig. 3 and Fig. 5: dead-end trajectories, neural traces, input-output loops, long runs."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from matplotlib.patches import Circle

from neurowalk.arenas import make_arena
from neurowalk.experiments import Result
from neurowalk.plotting import draw_arena, pyplot

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


def _io_loop(ax: Axes, x: np.ndarray, y: np.ndarray, title: str) -> None:
    """Input against output, coloured by time from dark blue to dark red (paper Fig. 3D-E)."""
    ax.scatter(x, y, c=np.linspace(0, 1, len(x)), cmap="jet", s=2, lw=0)
    ax.set(xlim=(-1.05, 1.05), ylim=(-1.05, 1.05), xlabel="input", ylabel="output", title=title)


def draw_wedged(ax: Axes, periods: list[dict]) -> None:
    """Circle each wedged period (its centre, radius its extent, at least 0.3 m) labelled with its duration (s).

    A label goes above its circle, or below it, or beside it, whichever is first clear of the labels placed
    before (so that nearby periods' labels do not cover each other).
    """
    placed: list[tuple[float, float]] = []
    for p in periods:
        (x, y), r = p["centre"], max(p.get("extent_m", 0.3), 0.3)
        ax.add_patch(Circle((x, y), r, fill=False, ec="k", lw=1.2, ls="--", zorder=6))
        spots = [
            ((x, y + r), "center", "bottom"),
            ((x, y - r), "center", "top"),
            ((x + r, y), "left", "center"),
            ((x - r, y), "right", "center"),
        ]
        clear = [s for s in spots if all(abs(s[0][0] - u) > 0.6 or abs(s[0][1] - v) > 0.35 for u, v in placed)]
        (lx, ly), ha, va = (clear or spots)[0]
        placed.append((lx, ly))
        ax.annotate(
            f"{p['duration_s']:.0f} s",
            (lx, ly),
            ha=ha,
            va=va,
            fontsize=7,
            zorder=7,
            bbox={"boxstyle": "round,pad=0.15", "fc": "w", "ec": "none", "alpha": 0.8},
        )


def plot(res: Result, network: str, long_keys: list[str], *, weights_panel: bool = False) -> Figure:
    """Panels A-G for the figure's ``network`` and the outcome table; ``weights_panel``: G shows weights."""
    plt = pyplot()
    s, a = res.summary, res.arrays
    fig = plt.figure(figsize=(18, 11), constrained_layout=True)
    gs = fig.add_gridspec(3, 4, height_ratios=[1, 1, 0.28])
    runs = s["runs"]
    notes = []
    if s.get("variant", "paper") != "paper":
        notes.append(f"network variant: {s['variant']} (the authors' code)")
    if s.get("climbing"):
        notes.append("with leg reflexes and backbone joint control switched on (Fig. 10's modules)")
    if notes:
        fig.suptitle("; ".join(notes))
    for i, name in enumerate(("simple-deadlock", "narrow-passage")):
        ax = fig.add_subplot(gs[0, i])
        draw_arena(ax, make_arena(runs[name]["arena"], **runs[name]["arena_opts"]), a[f"{name}/pose"])
        outcome = "escaped" if runs[name]["escaped"] else ("trapped" if runs[name]["trapped"] else "not out")
        ax.set_title(f"{'AB'[i]}  {name}, {network}: {outcome}")
    ax = fig.add_subplot(gs[0, 2:])
    t = np.arange(len(a["narrow-passage/inputs"])) / 10.0
    ax.plot(t, a["narrow-passage/inputs"][:, 0] + 2.5, "C0", lw=0.6, label="I1 (left)")
    ax.plot(t, a["narrow-passage/inputs"][:, 1] + 2.5, "C1", lw=0.6, label="I2 (right)")
    ax.plot(t, a["narrow-passage/outputs"][:, 0], "C0", lw=1.0, label="O1")
    ax.plot(t, a["narrow-passage/outputs"][:, 1], "C1", lw=1.0, label="O2")
    if np.isfinite(a["narrow-passage/b"]).all() and np.ptp(a["narrow-passage/b"]) > 0:
        ax.plot(t, a["narrow-passage/b"][:, 0] / 2 - 4, "C0--", lw=1, label="b1")
        ax.plot(t, a["narrow-passage/b"][:, 1] / 2 - 4, "C1--", lw=1, label="b2")
        ax.plot(t, -a["narrow-passage/q"].sum(axis=1) / 4 - 4, "k--", lw=1, label="c")
    ticks = {1.5: "I -1", 2.5: "0", 3.5: "1", -1.0: "O -1", 0.0: "0", 1.0: "1", -6.0: "w -4", -4.0: "0", -2.0: "4"}
    ax.set_yticks(list(ticks), list(ticks.values()), fontsize=7)
    ax.set(xlabel="time (s)", title="C  narrow passage: inputs I (top), outputs O, weights w = b, c (bottom)")
    ax.legend(loc="upper right", ncol=7, fontsize=7)
    _io_loop(
        fig.add_subplot(gs[1, 0]),
        a["narrow-passage/inputs"][:, 0],
        a["narrow-passage/outputs"][:, 0],
        "D  left: I1 vs O1 (time: blue → red)",
    )
    _io_loop(
        fig.add_subplot(gs[1, 1]),
        a["narrow-passage/inputs"][:, 1],
        a["narrow-passage/outputs"][:, 1],
        "E  right: I2 vs O2",
    )
    for j, key in enumerate(long_keys[:2]):
        ax = fig.add_subplot(gs[1, 2 + j])
        r = runs[key]
        if weights_panel and j == 1:  # paper Fig. 5G: the weights of the long run over time
            key0 = long_keys[0]
            tl = np.arange(len(a[f"{key0}/b"])) / 10.0
            ax.plot(tl, a[f"{key0}/b"][:, 0], "C0", lw=0.8, label="b1")
            ax.plot(tl, a[f"{key0}/b"][:, 1], "C1", lw=0.8, label="b2")
            ax.plot(tl, -0.5 * a[f"{key0}/q"].sum(axis=1), "k", lw=0.8, label="c")
            ax.set(xlabel="time (s)", ylabel="weight", title=f"G  {key0}: weights over time")
            ax.legend(fontsize=7, ncol=3)
            continue
        draw_arena(ax, make_arena(r["arena"], **r["arena_opts"]), a[f"{key}/pose"])
        draw_wedged(ax, r.get("wedged", []))
        cov = r["coverage"]
        wedged = f"\nwedged {r['wedged_periods']}x (longest {r['longest_wedged_s']:.0f} s)" if "wedged" in r else ""
        ax.set_title(
            f"{'FG'[j]}  {key}: {r['steps']} steps, {'trapped' if r['trapped'] else 'not trapped'}, "
            f"coverage {cov:.0%}{wedged}",
            fontsize=9,
        )
    counts = s["table"]["counts"]
    lines = ["escaped / runs (seeds " + str(s["table"]["seeds"]) + ", 5000 steps):"]
    for v, row in counts.items():
        lines.append(f"{v}: " + ", ".join(f"{n} {c['escaped']}/{c['runs']}" for n, c in row.items()))
    for k, w in s.get("wedged", {}).items():
        causes = ", ".join(f"{c} {n}" for c, n in w["causes"].items()) or "none"
        lines.append(
            f"{k}: wedged {w['periods']}x, longest {w['longest_s']:.0f} s, in all {w['total_s']:.0f} s "
            f"({causes}; dashed circles)"
        )
    ax = fig.add_subplot(gs[2, :])
    ax.axis("off")
    ax.text(0, 1, "\n".join(lines), fontsize=8, family="monospace", va="top", transform=ax.transAxes)
    return fig
