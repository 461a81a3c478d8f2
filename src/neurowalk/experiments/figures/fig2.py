"""Fig. 2: neural dynamics of the sensory network with frozen weights.

A.   The two-neuron network (a diagram, as the paper's panel A): inputs I1, I2 through the input weight a,
     self connections b1, b2, mutual inhibitions c1, c2, outputs O1, O2.
B-D. One neuron with self connection b: near-linear input-output relation for small b (B),
     hysteresis around b = 2.4 (C), a two-state switch that no input in [-1, 1] can flip for
     large b (D). Stable fixed points solid (carried on to O = -1 and 1 at the panel's edges) and
     marked with dots on top of everything, unstable dotted; the measured up and down sweeps on
     the lines.
E.   The two-neuron network (right input held at -1, no obstacle): hysteresis of the left output
     for the static network (b = 2.4, c = -3.5), the authors' start (2, -3), and the learned
     weights (4.63, -7.04), which latch on.
F.   Hysteresis width against b: one neuron (analytic and measured) and the two-neuron network
     with c = -3.5.
G.   Hysteresis width of the two-neuron network over (b, c); black where it latches on.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.patches import Circle, FancyArrowPatch

from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.reproduce.claims import Claim, holds
from neurowalk.neural.analysis import (
    hysteresis_loop,
    hysteresis_width_map,
    single_neuron_branches,
    single_neuron_thresholds,
)
from neurowalk.plotting.style import (
    FONT,
    LINE,
    colorbar,
    legend_outside,
    letter_panels,
    network_colour,
    pyplot,
    styled,
)

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

NAME = "fig2"
PANEL_B = (0.5, 2.4, 8.0)  # self weights of panels B, C, D
LOOPS = ((2.4, -3.5), (2.0, -3.0), (4.63, -7.04))  # (b, c) of panel E
#: What each loop of panel E is, and the network whose colour it takes (in E, and its marker in G).
LOOP_NAMES = (("static network", "static"), ("the authors' start", "plastic-original"), ("learned", "plastic"))
LOOP_MARKERS = ("*", "D", "o")
#: Panels B-D: the legend entry of the stable fixed points, and the inputs at which a marker shows each stable branch
#: (on top of the measured sweeps, which run along the branches).
STABLE_LABEL = "stable fixed point"
STABLE_MARKS = np.linspace(-0.9, 0.9, 7)
STABLE_STYLE = {"color": "green", "mfc": "limegreen", "mec": "darkgreen", "mew": 1.0, "ms": 6.5}


def _thresholds(loop: object) -> dict:
    return {
        "switch_on": loop.switch_on,
        "switch_off": loop.switch_off,  # type: ignore[attr-defined]
        "width": loop.width,
        "latched": loop.switch_on is not None and loop.switch_off is None,
    }  # type: ignore[attr-defined]


def runs(s: Settings) -> Iterator[Plan]:
    """None: the figure is the sensory network alone, computed by :func:`measure`."""
    return iter(())


def measure(s: Settings, runs: Mapping[Any, Any]) -> Result:
    """Compute every panel (deterministic: no seed); ``s.quick`` coarsens the grids."""
    n_levels = 101 if s.quick else 201
    b_grid = np.round(np.linspace(0.0, 6.0, 13 if s.quick else 25), 6)
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
    mb = np.linspace(0.0, 5.0, 11 if s.quick else 26)
    mc = np.linspace(-8.0, 0.0, 9 if s.quick else 33)
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


def stable_branches(
    branch_i: np.ndarray, branch_o: np.ndarray, stable: np.ndarray, reach: float = 1.0
) -> list[tuple[np.ndarray, np.ndarray]]:
    """The stable parts of one neuron's fixed-point curve (inputs, outputs; inputs increasing), each carried on to its
    limit where it is an end of the curve.

    The curve is sampled over outputs O in (-1, 1) (:func:`~neurowalk.neural.analysis.single_neuron_branches`); its
    ends go on to O = -1 as I -> -inf and O = 1 as I -> +inf. A panel of inputs in [-``reach``, ``reach``] would lose
    them (for a large self weight b the samples of the stable branches hardly reach into it), so an end is carried to
    the panel's edge at O = -1 or 1: there the curve lies between the end's last sample and -1 or 1 (within 0.0025
    of it for 801 samples), so the straight piece drawn is off by less than that."""
    runs: list[tuple[np.ndarray, np.ndarray]] = []
    edges = np.flatnonzero(np.diff(np.r_[0, stable.astype(int), 0]))
    for start, stop in zip(edges[::2], edges[1::2], strict=True):
        i, o = branch_i[start:stop], branch_o[start:stop]
        if start == 0 and i[0] > -reach:  # the low end: O -> -1 as I -> -inf
            i, o = np.r_[-reach, i], np.r_[-1.0, o]
        if stop == len(stable) and i[-1] < reach:  # the high end: O -> 1 as I -> +inf
            i, o = np.r_[i, reach], np.r_[o, 1.0]
        order = np.argsort(i, kind="stable")
        runs.append((i[order], o[order]))
    return runs


def draw_stable(ax: Axes, branch_i: np.ndarray, branch_o: np.ndarray, stable: np.ndarray) -> None:
    """Panels B-D: the stable fixed points, a green line under the measured sweeps (which follow it) and markers with
    a dark edge on top of them at the inputs :data:`STABLE_MARKS`, so that the stable states at O = -1 and 1, where the
    sweeps lie, stay visible; one legend entry (line and marker)."""
    for i, o in stable_branches(branch_i, branch_o, stable):
        ax.plot(i, o, color=STABLE_STYLE["color"], lw=LINE["thick"], zorder=1.9)
        marks = STABLE_MARKS
        at = marks[(marks >= i[0]) & (marks <= i[-1])]
        ax.plot(at, np.interp(at, i, o), "o", ls="none", zorder=4, **STABLE_STYLE)
    ax.plot([], [], "o-", lw=LINE["thick"], label=STABLE_LABEL, **STABLE_STYLE)


def draw_network(ax: Axes, a: float = 4.7) -> None:
    """Panel A: the two-neuron network. Excitation ends in an arrow head, inhibition in a bar."""
    ax.set(xlim=(0, 1), ylim=(0, 1), aspect="equal")
    ax.axis("off")
    r, dy = 0.1, 0.04  # neuron radius; the two inhibitory links above and below the centre line
    centres = {1: (0.3, 0.5), 2: (0.7, 0.5)}

    def link(p: tuple[float, float], q: tuple[float, float], style: str, rad: float = 0.0) -> None:
        arrow = FancyArrowPatch(
            p, q, arrowstyle=style, connectionstyle=f"arc3,rad={rad}", mutation_scale=14, lw=1.4, fc="k", ec="k"
        )
        ax.add_patch(arrow)

    for n, (x, y) in centres.items():
        side = -1 if n == 1 else 1  # the self loop on the outer side
        ax.add_patch(Circle((x, y), r, fc="0.92", ec="k", lw=1.4, zorder=3))
        ax.text(x, y, str(n), ha="center", va="center", fontsize=FONT["letter"], zorder=4)
        link((x, y - 0.36), (x, y - r), "-|>")
        ax.text(x, y - 0.38, f"I{n}", ha="center", va="top")
        ax.text(x + 0.02, y - 0.24, f"a = {a:g}", ha="left", va="center", fontsize=FONT["note"])
        link((x, y + r), (x, y + 0.34), "-|>")
        ax.text(x, y + 0.36, f"O{n} ({'left' if n == 1 else 'right'})", ha="center", va="bottom")
        ex, ey = x + side * r * np.cos(0.7), r * np.sin(0.7)
        link((ex, y + ey), (ex, y - ey), "-|>", -side * 2.4)
        ax.text(x + side * (r + 0.15), y, f"b{n}", ha="right" if n == 1 else "left", va="center")
    (x1, y1), (x2, _) = centres[1], centres[2]
    edge = np.sqrt(r * r - dy * dy)
    bar = "-[, widthB=0.6, lengthB=0.0"
    link((x1 + edge, y1 + dy), (x2 - edge - 0.01, y1 + dy), bar)
    ax.text(0.5, y1 + dy + 0.02, "c1", ha="center", va="bottom")
    link((x2 - edge, y1 - dy), (x1 + edge + 0.01, y1 - dy), bar)
    ax.text(0.5, y1 - dy - 0.02, "c2", ha="center", va="top")
    ax.set_title("two-neuron network")


@styled
def plot(res: Result) -> Figure:
    """Panels A-G as described in the module docstring (A-D as the paper letters its Fig. 2; E-G added)."""
    plt = pyplot()

    a, s = res.arrays, res.summary
    fig = plt.figure(figsize=(16, 9.5), layout="constrained")
    top, bottom = fig.subfigures(2, 1)
    panels = list(top.subplots(1, 4))
    draw_network(panels[0], s.get("input_weight_a", 4.7))
    for i, (b, ax) in enumerate(zip(PANEL_B, panels[1:], strict=True)):
        bi, bo, st = a[f"n{i}_branch_i"], a[f"n{i}_branch_o"], a[f"n{i}_stable"].astype(bool)
        ax.plot(np.where(~st, bi, np.nan), bo, color="orange", ls=":", lw=LINE["thick"], label="unstable fixed point")
        lv, out = a[f"n{i}_levels"], a[f"n{i}_out"]
        half = lv.size // 2
        ax.plot(lv[:half], out[:half], "b-", lw=LINE["thin"], alpha=0.7, label="sweep up (measured)")
        ax.plot(lv[half:], out[half:], "r-", lw=LINE["thin"], alpha=0.7, label="sweep down (measured)")
        draw_stable(ax, bi, bo, st)
        ax.set(xlim=(-1, 1), ylim=(-1.05, 1.05), xlabel="input I", ylabel="output O", title=f"one neuron, b = {b}")
    handles, labels = panels[1].get_legend_handles_labels()
    order = [labels.index(k) for k in (STABLE_LABEL, "unstable fixed point")] + [
        j for j, k in enumerate(labels) if "sweep" in k
    ]
    top.legend(handles=[handles[j] for j in order], loc="outside lower center", ncol=4)
    ax, f_ax, g_ax = bottom.subplots(1, 3)
    panels += [ax, f_ax, g_ax]
    for i, loop in enumerate(s["two_neuron_loops"]):
        lv, out = a[f"e{i}_levels"], a[f"e{i}_out"][:, 0]
        name, net = LOOP_NAMES[i] if i < len(LOOP_NAMES) else ("", f"C{i}")
        colour = network_colour(net) if i < len(LOOP_NAMES) else net
        ax.plot(lv, out, color=colour, lw=LINE["thick"], label=f"{name}: b = {loop['b']:g}, c = {loop['c']:g}")
    ax.set(
        xlim=(-1.05, 1.05),
        xticks=(-1, -0.5, 0, 0.5, 1),
        xlabel="left input I1 (right input I2 = -1)",
        ylabel="left output O1",
        title="two neurons: hysteresis",
    )
    legend_outside(ax, side="below", fontsize=FONT["small"])
    ax = f_ax
    b = np.array([r["b"] for r in s["single_neuron"]])
    w = np.array([r["width"] if r["width"] is not None else np.nan for r in s["single_neuron"]], dtype=float)
    wa = np.array([r["width_analytic"] for r in s["single_neuron"]], dtype=float)
    w2 = np.array([r["width"] if r["width"] is not None else np.nan for r in s["two_neuron_vs_b"]], dtype=float)
    ax.plot(b, wa, "k-", label="one neuron, analytic")
    ax.plot(b, w, "ko", ms=4, label="one neuron, measured")
    ax.plot(b, w2, "s-", color=network_colour("static"), ms=4, label="two neurons, c = -3.5")
    ax.axhline(2.0, color="gray", lw=LINE["thin"], ls=":")
    ax.set(
        xlabel="self connection b",
        ylabel="hysteresis width (input I)",
        title="width grows with b\n(gaps: latched or never switched)",
    )
    legend_outside(ax, side="below", ncol=2, fontsize=FONT["small"])
    ax = g_ax
    wm = np.ma.masked_invalid(a["map_width"])
    cmap = plt.get_cmap("viridis").with_extremes(bad="black")
    im = ax.pcolormesh(a["map_c"], a["map_b"], wm, cmap=cmap, shading="nearest")
    colorbar(im, ax, "hysteresis width (input I)")
    for i, loop in enumerate(s["two_neuron_loops"][: len(LOOP_NAMES)]):
        ax.plot(
            [loop["c"]],
            [loop["b"]],
            LOOP_MARKERS[i],
            color=network_colour(LOOP_NAMES[i][1]),
            mec="white",
            mew=1.2,
            ms=14 if LOOP_MARKERS[i] == "*" else 9,
            label=LOOP_NAMES[i][0],
        )
    ax.plot([], [], "s", color="black", ms=9, label="latched (no switch back)")
    ax.set(xlabel="inhibitory weight c", ylabel="self connection b", title="two neurons: width over (b, c)")
    legend_outside(ax, side="below", ncol=2, fontsize=FONT["small"])
    letter_panels(panels)
    return fig


def claims(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Single neuron: linear for small b, a hysteresis for larger b, its width growing with b; the static
    network's b = 2.4, c = -3.5 has a hysteresis; the strong weights latch (permanent turning)."""
    single = s["single_neuron"]
    small = [r for r in single if r["b"] < 1.0]
    larger = [r for r in single if r["b"] > 1.0 and not r["latched"]]
    widths = [r["width"] for r in larger]
    static, strong = s["two_neuron_loops"][0], s["two_neuron_loops"][-1]
    return [
        holds(
            "single neuron, small self-connection b < 1: no hysteresis (Fig. 2B)",
            "approximately linear I-O",
            all(r["width"] < 1e-6 for r in small),
            max(r["width"] for r in small),
            f"largest hysteresis width for b < 1 (input units): {max(r['width'] for r in small):.2g}",
            unit="(largest hysteresis width, input units)",
        ),
        holds(
            "single neuron, b > 1: a hysteresis (Fig. 2C) whose width grows with b",
            "hysteresis, width proportional to b",
            len(widths) > 1 and all(w > 0 for w in widths) and bool(np.all(np.diff(widths) > 0)),
            [round(w, 3) for w in widths],
            f"widths at b = {[r['b'] for r in larger]}",
            unit="(hysteresis widths, input units, b rising)",
        ),
        holds(
            f"static network b = {static['b']}, c = {static['c']}: a hysteresis, not latched",
            "hysteresis interval (Fig. 2C)",
            static["width"] is not None and static["width"] > 0 and not static["latched"],
            static["width"],
            f"width {static['width']:.3g} of the input range [-1, 1]",
            unit="(hysteresis width, input units)",
        ),
        holds(
            f"strong weights b = {strong['b']}, c = {strong['c']}: two states, the active one kept (Fig. 2D)",
            "permanent turning (active state)",
            bool(strong["latched"]),
            "latched" if strong["latched"] else f"width {strong['width']:.3g}",
            "latched: switched on and never off within the input range",
        ),
    ]
