"""Pictures of runs: arena top view with the path, and the neural traces over time."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import matplotlib
import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.patches import Polygon, Rectangle

from neurowalk.arenas.spec import ArenaSpec
from neurowalk.sim.trajectory import Trajectory

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


def pyplot() -> Any:
    """matplotlib.pyplot on the non-interactive Agg backend."""
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # here, not at the top: after Agg is chosen, and only when neurowalk draws

    return plt


def draw_arena(ax: Axes, arena: ArenaSpec, pose: np.ndarray | None = None, *, margin: float = 0.5) -> None:
    """Boxes (grey), exit region (green), the path coloured by time (dark blue → dark red), start/end dots."""
    for b in arena.boxes:
        ax.add_patch(Polygon(b.corners(), closed=True, color="0.55"))
    if arena.exit_region is not None:
        x0, x1, y0, y1 = arena.exit_region
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color="green", alpha=0.12, lw=0))
    pts = [b.corners() for b in arena.boxes]
    if pose is not None:
        xy = pose[:, :2]
        seg = np.stack([xy[:-1], xy[1:]], axis=1)
        lc = LineCollection(seg, cmap="jet", lw=1.5)
        lc.set_array(np.linspace(0, 1, len(seg)))
        ax.add_collection(lc)
        ax.plot(*xy[0], "o", color="red", ms=7, zorder=5, label="start")
        ax.plot(*xy[-1], "o", color="limegreen", mec="k", ms=7, zorder=5, label="end")
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


def run_title(summary: dict[str, Any]) -> str:
    """The title of a run's picture: arena, body, controller, steps, seed (e.g. ``box, amosii, plastic, ...``)."""
    ctrl = summary["controller"] + (f" {tuple(summary['steer'])}" if summary.get("steer") else "")
    body = summary.get("body", "amosii")
    if body.startswith("mjcf:"):  # a user's robot: its file's name, not the whole path
        body = "mjcf:" + Path(body.removeprefix("mjcf:")).name
    return f"{summary['arena']}, {body}, {ctrl}, {summary['steps']} steps, seed {summary['seed']}"


def plot_run(tr: Trajectory, arena: ArenaSpec, summary: dict[str, Any]) -> Figure:
    """Top view of the run and its inputs, steering and weights over time."""
    plt = pyplot()
    fig = plt.figure(figsize=(12, 6), constrained_layout=True)
    gs = fig.add_gridspec(3, 2, width_ratios=[1, 1.4])
    ax = fig.add_subplot(gs[:, 0])
    draw_arena(ax, arena, tr.pose)
    ax.legend(loc="best", fontsize=8)
    ax.set_title(run_title(summary))
    t = tr.t
    for row, (key, label) in enumerate((("inputs", "input I"), ("outputs", "steering O"))):
        a = fig.add_subplot(gs[row, 1])
        arr = getattr(tr, key)
        a.plot(t, arr[:, 0], lw=0.8, label="1 (left)")
        a.plot(t, arr[:, 1], lw=0.8, label="2 (right)")
        a.set(ylabel=label, ylim=(-1.1, 1.1))
        a.legend(loc="upper right", fontsize=7, ncol=2)
    a = fig.add_subplot(gs[2, 1])
    if np.isfinite(tr.b).any():
        a.plot(t, tr.b[:, 0], "C0", label="b1")
        a.plot(t, tr.b[:, 1], "C1", label="b2")
        a.plot(t, -0.5 * tr.q.sum(axis=1), "k", label="c")
        a.legend(loc="upper right", fontsize=7, ncol=3)
        a.set(xlabel="time (s)", ylabel="weights")
    else:  # no sensory network (fixed steering): what the sensors saw instead
        us = np.where(np.isfinite(tr.us_distance), tr.us_distance, np.nan)
        a.plot(t, us[:, 0], "C0", lw=0.8, label="left")
        a.plot(t, us[:, 1], "C1", lw=0.8, label="right")
        a.legend(loc="upper right", fontsize=7, ncol=2)
        a.set(xlabel="time (s)", ylabel="ultrasonic (m, gaps: no echo)", ylim=(0, 0.42))
    return fig
