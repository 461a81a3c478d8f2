"""Pictures of runs: arena top view with the path coloured by time, and the neural traces over time (run.png,
and the trace panels of Figs. 3, 5, 8 and 9: :func:`draw_traces`)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.patches import Polygon, Rectangle

from neurowalk.arenas.climbing import CLIMB_WORDS
from neurowalk.arenas.spec import WALL_HEIGHT, ArenaSpec
from neurowalk.plotting.style import (
    LINE,
    MEAN_WEIGHT,
    SIDE_COLOURS,
    TIME_CMAP,
    legend_outside,
    letter_panels,
    pyplot,
    styled,
    time_colorbar,
    weight_style,
)
from neurowalk.sim.config import Episode
from neurowalk.sim.trajectory import Trajectory

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure, SubFigure
    from matplotlib.gridspec import SubplotSpec

BOX_COLOUR = "0.55"
EXIT_COLOUR = "green"
START_COLOUR = "red"
END_COLOUR = "limegreen"


def draw_arena(
    ax: Axes,
    arena: ArenaSpec,
    pose: np.ndarray | None = None,
    *,
    margin: float = 0.5,
    t: np.ndarray | None = None,
    lw: float = LINE["path"],
) -> LineCollection | None:
    """Boxes (grey), exit region (green), the path coloured by time (dark blue → dark red), start/end dots.

    ``pose``: (n, >=2) positions (m). ``t``: the time of each row (s), for a colour bar in seconds (without it the
    colours run over the row index). Returns the path's line collection (the mappable of
    :func:`~neurowalk.plotting.style.time_colorbar`), None without a path.
    """
    for b in arena.boxes:
        ax.add_patch(Polygon(b.corners(), closed=True, color=BOX_COLOUR))
    if arena.exit_region is not None:
        x0, x1, y0, y1 = arena.exit_region
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color=EXIT_COLOUR, alpha=0.12, lw=0, label="exit region"))
    pts = [b.corners() for b in arena.boxes]
    lc = None
    if pose is not None:
        xy = pose[:, :2]
        seg = np.stack([xy[:-1], xy[1:]], axis=1)
        lc = LineCollection(seg, cmap=TIME_CMAP, lw=lw)
        when = np.arange(len(xy), dtype=float) if t is None else np.asarray(t, dtype=float)
        lc.set_array(when[1:] if len(when) > 1 else when)
        if len(when):
            lo = 0.0 if t is not None and when[0] >= 0.0 else when[0]  # time from the start of the run
            lc.set_clim(lo, max(when[-1], lo + 1e-9))
        ax.add_collection(lc)
        ax.plot(*xy[0], "o", color=START_COLOUR, ms=7, zorder=5, label="start")
        ax.plot(*xy[-1], "o", color=END_COLOUR, mec="k", ms=7, zorder=5, label="end")
        pts.append(xy)
    if arena.bounds is not None:
        x0, x1, y0, y1 = arena.bounds
        ax.set(xlim=(x0 - 0.2, x1 + 0.2), ylim=(y0 - 0.2, y1 + 0.2))
    elif pts:
        allp = np.vstack(pts)
        lo, hi = allp.min(axis=0) - margin, allp.max(axis=0) + margin
        ax.set(xlim=(lo[0], hi[0]), ylim=(lo[1], hi[1]))
    ax.set_aspect("equal")
    ax.set(xlabel="x (m)", ylabel="y (m)")
    return lc


def side_lines(ax: Axes, t: np.ndarray, arr: np.ndarray, name: str, lw: float = LINE["trace"]) -> None:
    """``name``1 (left) and ``name``2 (right), the columns of ``arr`` (T, 2), over time ``t`` (s)."""
    ax.plot(t, arr[:, 0], color=SIDE_COLOURS["left"], lw=lw, label=f"{name}1 (left)")
    ax.plot(t, arr[:, 1], color=SIDE_COLOURS["right"], lw=lw, label=f"{name}2 (right)")


def weight_lines(ax: Axes, t: np.ndarray, b: np.ndarray, q: np.ndarray) -> None:
    """The self weights b1, b2 (``b`` (T, 2)) and the mean inhibition c = -(q1 + q2)/2 over time ``t`` (s)."""
    ax.plot(t, b[:, 0], label="b1 (left)", **weight_style("b", "left"))
    ax.plot(t, b[:, 1], label="b2 (right)", **weight_style("b", "right"))
    ax.plot(t, -0.5 * q.sum(axis=1), **MEAN_WEIGHT)
    ax.set_ylabel("weight")


def draw_traces(
    fig: Figure | SubFigure,
    spec: SubplotSpec,
    t: np.ndarray,
    signals: list[tuple[np.ndarray, str, str]],
    b: np.ndarray,
    q: np.ndarray,
    title: str,
    *,
    plastic: bool,
    lw: float = LINE["trace"],
) -> Axes:
    """Each of ``signals`` ((T, 2) array, its letter "I" or "O", its y label) over time ``t`` (s) on its own axes
    (line width ``lw``), and below them, where ``plastic``, the weights (:func:`weight_lines`); each with its legend
    beside it, the top one titled ``title``. Returns the top axes (for the panel letter)."""
    rows = spec.subgridspec(len(signals) + plastic, 1, hspace=0.08)
    top = fig.add_subplot(rows[0])
    axes = [top] + [fig.add_subplot(rows[k], sharex=top) for k in range(1, len(signals) + plastic)]
    for ax, (arr, name, ylabel) in zip(axes, signals, strict=False):
        side_lines(ax, t, arr, name, lw)
        ax.set(ylim=(-1.1, 1.1), yticks=(-1, 0, 1), ylabel=ylabel)
        legend_outside(ax)
    if plastic:
        weight_lines(axes[-1], t, b, q)
        legend_outside(axes[-1])
    for ax in axes[:-1]:
        ax.tick_params(labelbottom=False)
    axes[-1].set_xlabel("time (s)")
    top.set_title(title)
    return top


def run_title(summary: dict[str, Any]) -> str:
    """The title of a run's picture: arena, body, controller, network variant, steps, seed (e.g.
    ``box, amosii, plastic, variant paper, 300 steps (30 s), seed 0``)."""
    ctrl = summary["controller"] + (f" {tuple(summary['steer'])}" if summary.get("steer") else "")
    body = summary.get("body", "amosii")
    if body.startswith("mjcf:"):  # a user's robot: its file's name, not the whole path
        body = "mjcf:" + Path(body.removeprefix("mjcf:")).name
    variant = f"variant {summary.get('variant', 'paper')}" + (" + params" if summary.get("params") else "")
    hz = summary.get("control_hz")
    steps = f"{summary['steps']} steps" + (f" ({summary['steps'] / hz:g} s)" if hz else "")
    return f"{summary['arena']}, {body}, {ctrl}, {variant}, {steps}, seed {summary['seed']}"


@styled
def plot_run(tr: Trajectory | Episode, arena: ArenaSpec | None = None, summary: dict[str, Any] | None = None) -> Figure:
    """The picture of a run (run.png): ``plot_run(ep)`` of an :class:`~neurowalk.sim.config.Episode`, or of its
    trajectory, arena and summary. A: top view of the run, the path coloured by time (colour bar in s); B-D: its
    inputs, steering and weights (or, without a sensory network, the ultrasonic readings) over time (s); E, on an
    arena with steps to climb (a physics body): the trunk's rise over its start height and the steps' heights (m),
    the climb marked. The title names the run."""
    if isinstance(tr, Episode):
        tr, arena, summary = tr.trajectory, tr.arena, tr.summary
    if arena is None or summary is None:
        raise TypeError("plot_run takes an Episode, or a trajectory with its arena and summary")
    plt = pyplot()
    physics = tr.qpos.ndim == 2 and tr.qpos.shape[1] > 2 and bool(np.isfinite(tr.qpos[:, 2]).all())
    climbs = _step_heights(arena) if physics else []  # a trunk height to draw, and steps to climb
    rows = 4 if climbs else 3
    fig = plt.figure(figsize=(13, 6.5 + 1.6 * (rows - 3)), layout="constrained")
    gs = fig.add_gridspec(rows, 2, width_ratios=[1, 1.35])
    ax = fig.add_subplot(gs[:, 0])
    t = tr.t
    path = draw_arena(ax, arena, tr.pose, t=t)
    if path is not None:
        time_colorbar(path, ax, shrink=0.8)
    legend_outside(ax, side="below", ncol=2)
    fig.suptitle(run_title(summary))
    traces = [fig.add_subplot(gs[0, 1])]
    traces += [fig.add_subplot(gs[row, 1], sharex=traces[0]) for row in range(1, rows)]
    for a, (key, label) in zip(traces, (("inputs", "input I"), ("outputs", "steering O")), strict=False):
        side_lines(a, t, getattr(tr, key), label.split()[-1])
        a.set(ylabel=label, ylim=(-1.1, 1.1))
        a.tick_params(labelbottom=False)
        legend_outside(a)
    a = traces[2]
    if np.isfinite(tr.b).any():
        weight_lines(a, t, tr.b, tr.q)
    else:  # no sensory network (fixed steering): what the sensors saw instead
        us = np.where(np.isfinite(tr.us_distance), tr.us_distance, np.nan)
        a.plot(t, us[:, 0], color=SIDE_COLOURS["left"], lw=LINE["trace"], label="left")
        a.plot(t, us[:, 1], color=SIDE_COLOURS["right"], lw=LINE["trace"], label="right")
        a.set(ylabel="ultrasonic echo (m)\n(gaps: no echo)", ylim=(0, 0.42))
    legend_outside(a)
    if climbs:
        a.tick_params(labelbottom=False)
        height_lines(traces[3], t, tr.qpos[:, 2] - tr.qpos[0, 2], climbs, summary)
    traces[-1].set_xlabel("time (s)")
    letter_panels([ax, *traces])
    return fig


def _step_heights(arena: ArenaSpec) -> list[float]:
    """The heights (m) of an arena's steps a robot climbs onto (its boxes lower than a wall), lowest first; none
    where its exit is not a climb."""
    if arena.exit_words != CLIMB_WORDS:
        return []
    return sorted({round(b.h, 4) for b in arena.boxes if b.h < WALL_HEIGHT})


def height_lines(a: Axes, t: np.ndarray, rise: np.ndarray, steps: list[float], summary: dict[str, Any]) -> None:
    """The trunk's rise over its start height (m) against time (s), each step's height dashed, and when the robot
    climbed (the summary's ``climbed_at_s``) a dotted line."""
    a.plot(t, rise, color="k", lw=LINE["trace"], label="trunk rise")
    for k, h in enumerate(steps):
        a.axhline(h, color=BOX_COLOUR, ls="--", lw=LINE["thin"], label="step height" if k == 0 else None)
    when = summary.get("climbed_at_s")
    if when is not None:
        a.axvline(when, color=EXIT_COLOUR, ls=":", lw=LINE["thin"], label=f"climbed at {when:.1f} s")
    a.set(
        ylabel="trunk rise (m)",
        ylim=(min(-0.02, float(np.nanmin(rise))), 1.25 * max(max(steps), float(np.nanmax(rise)))),
    )
    legend_outside(a)
