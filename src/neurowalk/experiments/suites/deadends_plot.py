"""The picture of Fig. 3 and Fig. 5: dead-end trajectories, neural traces, input-output loops, long runs, and the
escape counts as a table (the wedged periods of the long runs are circled on their paths; their list is in the json).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.patches import Circle
from matplotlib.ticker import PercentFormatter

from neurowalk.arenas import make_arena
from neurowalk.experiments import Result
from neurowalk.plotting import draw_arena
from neurowalk.plotting.runs import draw_traces
from neurowalk.plotting.style import (
    FONT,
    LINE,
    TIME_CMAP,
    draw_table,
    legend_outside,
    letter,
    network_line,
    pyplot,
    styled,
    time_colorbar,
    weight_style,
)

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.collections import PathCollection
    from matplotlib.figure import Figure
    from matplotlib.gridspec import SubplotSpec


#: At most this many wedged periods of a path are labelled with their duration (the longest); the others are circled.
WEDGED_LABELS = 6


def draw_wedged(ax: Axes, periods: list[dict], most: int = WEDGED_LABELS) -> None:
    """Circle each wedged period (its centre, radius its extent, at least 0.3 m); label the ``most`` longest held
    ones with the time held (s), so that the labels of a long run wedged many times do not pile up; the legend entry
    says how many there are and which are labelled.

    Each period carries its held runs (``held``, :func:`neurowalk.metrics.wedged_periods`): it is held (dashed black
    circles, labelled) or turning in place (no held step: dotted grey circles, not labelled, their own legend
    entry).

    Longest first, a label goes above its circle, or below it, or beside it, whichever is first clear of the labels
    placed before (so that nearby periods' labels do not cover each other).
    """
    placed: list[tuple[float, float]] = []
    turning = [p for p in periods if not p["held"]]
    held = [p for p in periods if p["held"]]
    longest = sorted(held, key=lambda p: -p["held_s"])[:most]
    if held:  # the legend's entry for the circles
        what = "held (duration)"
        if len(longest) < len(held):
            what = f"held {len(held)}x, {most} longest labelled (s)"
        ax.plot([], [], "o", mfc="none", mec="k", ms=11, ls="none", label=what)
    if turning:
        label = f"turning in place {len(turning)}x (wedged, not held)"
        ax.plot([], [], "o", mfc="none", mec="0.55", ms=11, ls="none", label=label)
    for group, style in ((held, {"ec": "k", "lw": 1.2, "ls": "--"}), (turning, {"ec": "0.55", "lw": 1.0, "ls": ":"})):
        for p in group:
            ax.add_patch(Circle(tuple(p["centre"]), max(p.get("extent_m", 0.3), 0.3), fill=False, zorder=6, **style))
    for p in longest:
        (x, y), r = p["centre"], max(p.get("extent_m", 0.3), 0.3)
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
            f"{p['held_s']:.0f} s",
            (lx, ly),
            ha=ha,
            va=va,
            fontsize=FONT["small"],
            zorder=7,
            bbox={"boxstyle": "round,pad=0.15", "fc": "w", "ec": "none", "alpha": 0.8},
        )


def _io_loop(ax: Axes, x: np.ndarray, y: np.ndarray, t: np.ndarray, side: int, title: str) -> PathCollection:
    """Input against output of neuron ``side`` (1 left, 2 right), coloured by time (s) from dark blue to dark red
    (paper Fig. 3D-E); returns the scatter for the colour bar."""
    sc = ax.scatter(x, y, c=t, cmap=TIME_CMAP, s=3, lw=0, vmin=0.0, vmax=max(float(t[-1]), 1e-9))
    ax.set(
        xlim=(-1.05, 1.05),
        ylim=(-1.05, 1.05),
        xlabel=f"input I{side}",
        ylabel=f"output O{side}",
        title=title,
    )
    return sc


def _long_path(ax: Axes, r: dict, pose: np.ndarray, step: np.ndarray, mark: int | None, hz: float) -> None:
    """A long run's path: time-coloured (with a colour bar); with ``mark``, red up to that step and gray after it
    (paper Fig. 3F), a red dot at the start and a green one at the mark (Fig. 3G)."""
    arena = make_arena(r["arena"], **r["arena_opts"])
    if mark is None:
        path = draw_arena(ax, arena, pose, t=step / hz, lw=LINE["trace"])
        if path is not None:
            time_colorbar(path, ax)
        return
    draw_arena(ax, arena)
    i = int(np.searchsorted(step, mark))  # the first kept row at or after the mark
    ax.plot(pose[i:, 0], pose[i:, 1], color="0.6", lw=LINE["thin"], label=f"after step {mark:,}")
    ax.plot(pose[: i + 1, 0], pose[: i + 1, 1], color="#CC5050", lw=LINE["trace"], label=f"steps 0-{mark:,}")
    ax.plot(*pose[0, :2], "o", color="red", ms=7, zorder=5, label="start")
    ax.plot(*pose[min(i, len(pose) - 1), :2], "o", color="limegreen", mec="k", ms=7, zorder=5, label=f"step {mark:,}")


def _long_title(key: str, r: dict, hz: float) -> str:
    cov = r["coverage"]
    wedged = f"\nwedged {r['wedged_periods']}x (longest {r['longest_wedged_s']:.0f} s)"
    wedged += f", held {r['held_periods']}x (longest {r['longest_held_s']:.0f} s)"
    outcome = "trapped" if r["trapped"] else "not trapped"
    return f"{key}, {r['steps'] / hz:,.0f} s\n{outcome}, coverage {cov:.0%}{wedged}"


def _weights(ax: Axes, a: dict, key: str, r: dict, hz: float) -> None:
    """Paper Fig. 5G: the four weights of the long run ``key`` over time, its wedged periods shaded."""
    tl = a[f"{key}/step"] / hz
    b, q = a[f"{key}/b"], a[f"{key}/q"]
    for kind, w in (("b", b), ("c", 0.0 - q)):
        for k, side in enumerate(("left", "right")):
            ax.plot(tl, w[:, k], label=f"{kind}{k + 1} ({side})", **{**weight_style(kind, side), "lw": LINE["thin"]})
    for i, p in enumerate(r["wedged"]):
        ax.axvspan(p["start"] / hz, (p["end"] + 1) / hz, color="0.88", zorder=0, label="wedged" if i == 0 else None)
    for i, (a0, a1) in enumerate(h for p in r["wedged"] for h in p["held"]):
        ax.axvspan(a0 / hz, (a1 + 1) / hz, color="0.7", zorder=0, label="held" if i == 0 else None)
    ax.axhline(0, color="k", lw=0.5)
    stride = int(np.median(np.diff(a[f"{key}/step"]))) if len(tl) > 1 else 1
    ax.set(
        xlabel="time (s)",
        ylabel="weight",
        xlim=(0, tl[-1]),
        title=f"{key}: weights over the whole run (every {stride}th control step)",
    )
    legend_outside(ax)


#: A further coverage curve of panel H: its label, time (n,) s, coverage (n,) shares, and its line style.
Curve = tuple[str, np.ndarray, np.ndarray, dict[str, Any]]

#: Two coverage curves closer than this share of the panel's height everywhere are drawn as coinciding (H).
COINCIDE = 0.02


def _coverage(ax: Axes, a: dict, keys: list[str], hz: float, more: Sequence[Curve] = ()) -> None:
    """The share of the free area visited over time, one line per long run (not in the paper), and the ``more``
    curves (label, time (s), coverage, line style) over them.

    Curves that coincide (closer than :data:`COINCIDE` of the panel's height at every kept step) stay all visible:
    the first one drawn wide, each later one narrower on top of it with markers, and its legend entry names the
    curve it lies on and the greatest difference between them.
    """
    curves = {key: (a[f"{key}/step"] / hz, np.asarray(a[f"{key}/coverage"], dtype=float)) for key in keys}
    top = max((float(np.nanmax(c)) for _, c in curves.values() if np.isfinite(c).any()), default=0.0)
    nets = {key: key[key.find("(") + 1 : key.rfind(")")] if "(" in key else key for key in keys}
    under: dict[str, list[tuple[str, float]]] = {key: [] for key in keys}  # each curve: the earlier ones it lies on
    for j, key in enumerate(keys):
        t, c = curves[key]
        for other in keys[:j]:
            t2, c2 = curves[other]
            if len(t) == len(t2) and np.array_equal(t, t2) and len(c):
                gap = float(np.nanmax(np.abs(c - c2)))
                if gap <= COINCIDE * top:
                    under[key].append((other, gap))
    for key in keys:
        t, c = curves[key]
        layer, above = len(under[key]), sum(key in [o for o, _ in under[k]] for k in keys)
        style = {**network_line(nets[key]), "lw": LINE["thick"] * (1.0 + above), "zorder": 2 + layer}
        if layer:
            style.update(marker="o", ms=5, mfc="white", mew=1.2, markevery=(0.04 * layer, 0.12))
        label = nets[key]
        if layer:
            other, gap = under[key][0]
            label += f": on {nets[other]}'s line\n(at most {gap:.1%} apart)"
        ax.plot(t, c, label=label, **style)
    for label, t, c, style in more:
        ax.plot(t, c, label=label, **{"zorder": 1, **style})
    ax.set(xlabel="time (s)", ylabel="coverage (share of free cells)", title="coverage (not in the paper)")
    ax.set_ylim(bottom=0)
    ax.yaxis.set_major_formatter(PercentFormatter(1.0))  # its decimals as the ticks need them (2.5%, not 2%)
    legend_outside(ax, side="below", ncol=1 if any(under.values()) else 3)


def _traces(fig: Figure, spec: SubplotSpec, a: dict, hz: float) -> Axes:
    """Paper Figs. 3C and 5C: the narrow passage's inputs, outputs and (where they change) weights over time (s),
    each on its own axes (:func:`~neurowalk.plotting.runs.draw_traces`); returns the top one (for the panel
    letter)."""
    t = np.arange(len(a["narrow-passage/inputs"])) / hz
    b, q = a["narrow-passage/b"], a["narrow-passage/q"]
    plastic = bool(np.isfinite(b).all() and np.ptp(b) > 0)
    signals = [(a["narrow-passage/inputs"], "I", "input I"), (a["narrow-passage/outputs"], "O", "output O")]
    title = "narrow passage: neural activations" + (" and weights" if plastic else "")
    return draw_traces(fig, spec, t, signals, b, q, title, plastic=plastic)


def _counts_table(ax: Axes, s: dict, hz: float) -> None:
    """The escape counts of every network in every dead end, as a table (cells tinted by the share escaped)."""
    counts = s["table"]["counts"]
    steps = s["table"].get("steps", 5000)
    nets = list(next(iter(counts.values())))
    cells = [[f"{row[n]['escaped']}/{row[n]['runs']}" for n in nets] for row in counts.values()]
    shares = [[row[n]["escaped"] / row[n]["runs"] if row[n]["runs"] else None for n in nets] for row in counts.values()]
    draw_table(
        ax,
        cells,
        list(counts),
        nets,
        shares=shares,
        title=f"escaped / runs ({s['table']['seeds']} seeds, {steps / hz:g} s each)",
    )


@styled
def plot(
    res: Result, network: str, long_keys: list[str], *, weights_panel: bool = False, more_coverage: Sequence[Curve] = ()
) -> Figure:
    """Panels A-G for the figure's ``network`` and the escape counts as a table; one row of panels per subfigure.

    Fig. 3 (``weights_panel`` False): F and G the paths of the first two long runs, red up to ``mark_step`` and gray
    after. Fig. 5 (``weights_panel``): F the path of the first long run coloured by time, beside it H, the coverage
    over time of every long run (not in the paper) with the ``more_coverage`` curves, and G (a row of its own) the
    first long run's weights over the whole run.
    """
    plt = pyplot()
    s, a = res.summary, res.arrays
    hz = float(s.get("control_hz", 10.0))
    ratios = [4.6, 5.0, 3.0, 3.2] if weights_panel else [4.6, 5.0, 3.2]
    fig = plt.figure(figsize=(19, sum(ratios) + 0.5), layout="constrained")
    rows = fig.subfigures(len(ratios), 1, height_ratios=ratios)
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
    top = rows[0].add_gridspec(1, 3, width_ratios=[1, 1, 2.3])
    dead = []
    for i, name in enumerate(("simple-deadlock", "narrow-passage")):
        ax = rows[0].add_subplot(top[0, i])
        pose = a[f"{name}/pose"]
        path = draw_arena(ax, make_arena(runs[name]["arena"], **runs[name]["arena_opts"]), pose,
                          t=np.arange(len(pose)) / hz)  # fmt: skip
        outcome = "escaped" if runs[name]["escaped"] else ("trapped" if runs[name]["trapped"] else "not out")
        ax.set_title(f"{name.replace('-', ' ')}, {network}: {outcome}")
        letter(ax, "AB"[i])
        dead.append((ax, path))
    tmax = max(len(a[f"{n}/pose"]) for n in ("simple-deadlock", "narrow-passage")) / hz
    for _, path in dead:
        path.set_clim(0.0, tmax)
    time_colorbar(dead[1][1], [ax for ax, _ in dead], shrink=0.8)
    legend_outside(dead[0][0], side="below", ncol=2)
    letter(_traces(rows[0], top[0, 2], a, hz), "C")
    middle = rows[1].add_gridspec(1, 4)
    t = np.arange(len(a["narrow-passage/inputs"])) / hz
    loops = []
    for side, lab in ((1, "D"), (2, "E")):
        ax = rows[1].add_subplot(middle[0, side - 1])
        x, y = a["narrow-passage/inputs"][:, side - 1], a["narrow-passage/outputs"][:, side - 1]
        loops.append((ax, _io_loop(ax, x, y, t, side, f"{'left' if side == 1 else 'right'} neuron, narrow passage")))
        ax.set_box_aspect(1)
        letter(ax, lab)
    time_colorbar(loops[1][1], [ax for ax, _ in loops], shrink=0.8)
    mark = s.get("mark_step")
    paths = long_keys[:1] if weights_panel else long_keys[:2]
    for j, key in enumerate(paths):
        ax = rows[1].add_subplot(middle[0, 2 + j])
        r = runs[key]
        _long_path(ax, r, a[f"{key}/pose"], a[f"{key}/step"], mark, hz)
        draw_wedged(ax, r.get("wedged", []))
        legend_outside(ax, side="below", ncol=2)
        ax.set_title(_long_title(key, r, hz))
        letter(ax, "FG"[j])
    if weights_panel:  # paper Fig. 5G: the weights of the long run over time; the coverage curves beside F
        ax = rows[1].add_subplot(middle[0, 3])
        _coverage(ax, a, long_keys, hz, more_coverage)
        ax.set_box_aspect(1)
        letter(ax, "H")
        ax = rows[2].add_subplot(1, 1, 1)
        _weights(ax, a, long_keys[0], runs[long_keys[0]], hz)
        letter(ax, "G")
    ax = rows[-1].add_subplot(rows[-1].add_gridspec(1, 5)[0, 1:4])
    _counts_table(ax, s, hz)
    return fig
