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


def _long_path(ax: Axes, r: dict, pose: np.ndarray, step: np.ndarray, mark: int | None) -> None:
    """A long run's path: time-coloured; with ``mark``, red up to that step and gray after it (paper Fig. 3F), a
    red dot at the start and a green one at the mark (Fig. 3G)."""
    arena = make_arena(r["arena"], **r["arena_opts"])
    if mark is None:
        draw_arena(ax, arena, pose)
        return
    draw_arena(ax, arena)
    i = int(np.searchsorted(step, mark))  # the first kept row at or after the mark
    ax.plot(pose[i:, 0], pose[i:, 1], color="0.6", lw=0.6, label=f"after step {mark:,}")
    ax.plot(pose[: i + 1, 0], pose[: i + 1, 1], color="#CC5050", lw=0.9, label=f"steps 0-{mark:,}")
    ax.plot(*pose[0, :2], "o", color="red", ms=7, zorder=5, label="start")
    ax.plot(*pose[min(i, len(pose) - 1), :2], "o", color="limegreen", mec="k", ms=7, zorder=5, label=f"step {mark:,}")
    ax.legend(fontsize=6, loc="lower left")


def _long_title(letter: str, key: str, r: dict, hz: float) -> str:
    cov = r["coverage"]
    wedged = f", wedged {r['wedged_periods']}x (longest {r['longest_wedged_s']:.0f} s)" if "wedged" in r else ""
    return (
        f"{letter}  {key}: {r['steps']:,} steps ({r['steps'] / hz:,.0f} s)\n"
        f"{'trapped' if r['trapped'] else 'not trapped'}, coverage {cov:.0%}{wedged}"
    )


def _weights(ax: Axes, a: dict, key: str, r: dict, hz: float) -> None:
    """Paper Fig. 5G: the four weights of the long run ``key`` over time, its wedged periods shaded."""
    tl = a[f"{key}/step"] / hz
    b, q = a[f"{key}/b"], a[f"{key}/q"]
    ax.plot(tl, b[:, 0], color="red", lw=0.7, label="b1")
    ax.plot(tl, b[:, 1], color="blue", lw=0.7, label="b2")
    ax.plot(tl, 0.0 - q[:, 0], color="green", lw=0.7, label="c1")
    ax.plot(tl, 0.0 - q[:, 1], color="purple", lw=0.7, label="c2")
    for i, p in enumerate(r.get("wedged", [])):
        ax.axvspan(p["start"] / hz, (p["end"] + 1) / hz, color="0.85", zorder=0, label="wedged" if i == 0 else None)
    ax.axhline(0, color="k", lw=0.5)
    stride = int(np.median(np.diff(a[f"{key}/step"]))) if len(tl) > 1 else 1
    ax.set(
        xlabel="time (s)",
        ylabel="weight",
        xlim=(0, tl[-1]),
        title=f"G  {key}: weights over the whole run (every {stride}th control step; shaded: wedged periods)",
    )
    ax.legend(fontsize=7, ncol=5, loc="upper right")


def _coverage(ax: Axes, a: dict, keys: list[str], hz: float) -> None:
    """The share of the free area visited over time, one line per long run (not in the paper)."""
    for key in keys:
        ax.plot(a[f"{key}/step"] / hz, a[f"{key}/coverage"], lw=1, label=key)
    ax.set(xlabel="time (s)", ylabel="coverage", ylim=(0, 1), title="coverage over time (not in the paper)")
    ax.legend(fontsize=7)


def _wedged_lines(s: dict, most: int = 30, per_line: int = 6) -> list[str]:
    """The text of the long runs' wedged periods: per run its counts, then its periods (start, duration, cause),
    ``per_line`` to a line, the first ``most`` of them."""
    lines = []
    for k, w in s.get("wedged", {}).items():
        causes = ", ".join(f"{c} {n}" for c, n in w["causes"].items()) or "none"
        over = next((v for name, v in w.items() if name.startswith("over_")), None)
        longer = f"; over 300 s: {over['periods']}" if over is not None else ""
        lines.append(
            f"{k}: wedged {w['periods']}x, longest {w['longest_s']:.0f} s, in all {w['total_s']:.0f} s "
            f"({causes}{longer})"
        )
        periods = [f"{p['start_s']:.0f} s +{p['duration_s']:.0f} s {p['cause']}" for p in w.get("list", [])[:most]]
        for i in range(0, len(periods), per_line):
            head = "    start +duration cause: " if i == 0 else "    "
            lines.append(head + ", ".join(periods[i : i + per_line]))
        if len(w.get("list", [])) > most:
            lines.append(f"    ... and {len(w['list']) - most} more (the json's wedged/{k}/list)")
    return lines


def plot(res: Result, network: str, long_keys: list[str], *, weights_panel: bool = False) -> Figure:
    """Panels A-G for the figure's ``network`` and the outcome table.

    Fig. 3 (``weights_panel`` False): F and G the paths of the first two long runs, red up to ``mark_step`` and gray
    after. Fig. 5 (``weights_panel``): F the path of the first long run, beside it the coverage over time of every
    long run, and G (a row of its own) the first long run's weights over the whole run.
    """
    plt = pyplot()
    s, a = res.summary, res.arrays
    hz = float(s.get("control_hz", 10.0))
    counts = s["table"]["counts"]
    steps = s["table"].get("steps", 5000)
    lines = [f"escaped / runs (seeds {s['table']['seeds']}, {steps} control steps, {steps / hz:g} s):"]
    for v, row in counts.items():
        lines.append(f"{v}: " + ", ".join(f"{n} {c['escaped']}/{c['runs']}" for n, c in row.items()))
    wedged = _wedged_lines(s)
    if wedged:
        lines += ["wedged periods of the long runs (dashed circles on the paths):", *wedged]
    text_h = 0.15 * len(lines)  # inches: 8 pt lines
    fig = plt.figure(figsize=(18, (13.5 if weights_panel else 9.5) + text_h), constrained_layout=True)
    ratios = [4, 4, 2.4, text_h] if weights_panel else [4, 4, text_h]
    gs = fig.add_gridspec(len(ratios), 4, height_ratios=ratios)
    runs = s["runs"]
    notes = []
    if s.get("variant", "paper") != "paper":
        notes.append(f"network variant: {s['variant']} (the authors' code)")
    if s.get("climbing"):
        notes.append("with leg reflexes and backbone joint control switched on (Fig. 10's modules)")
    if s.get("quick"):
        full = s.get("long_steps_full", s["long_steps"])
        notes.append(f"--quick: long runs of {s['long_steps']:,} control steps (the full figure's: {full:,})")
    if hz != 10.0:
        notes.append(f"control rate {hz:g} Hz")
    if notes:
        fig.suptitle("; ".join(notes))
    for i, name in enumerate(("simple-deadlock", "narrow-passage")):
        ax = fig.add_subplot(gs[0, i])
        draw_arena(ax, make_arena(runs[name]["arena"], **runs[name]["arena_opts"]), a[f"{name}/pose"])
        outcome = "escaped" if runs[name]["escaped"] else ("trapped" if runs[name]["trapped"] else "not out")
        ax.set_title(f"{'AB'[i]}  {name}, {network}: {outcome}")
    ax = fig.add_subplot(gs[0, 2:])
    t = np.arange(len(a["narrow-passage/inputs"])) / hz
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
    mark = s.get("mark_step")
    paths = long_keys[:1] if weights_panel else long_keys[:2]
    for j, key in enumerate(paths):
        ax = fig.add_subplot(gs[1, 2 + j])
        r = runs[key]
        _long_path(ax, r, a[f"{key}/pose"], a[f"{key}/step"], mark)
        draw_wedged(ax, r.get("wedged", []))
        ax.set_title(_long_title("FG"[j], key, r, hz), fontsize=9)
    if weights_panel:  # paper Fig. 5G: the weights of the long run over time; the coverage curves beside F
        _coverage(fig.add_subplot(gs[1, 3]), a, long_keys, hz)
        _weights(fig.add_subplot(gs[2, :]), a, long_keys[0], runs[long_keys[0]], hz)
    ax = fig.add_subplot(gs[-1, :])
    ax.axis("off")
    ax.text(0, 1, "\n".join(lines), fontsize=8, family="monospace", va="top", transform=ax.transAxes)
    return fig
