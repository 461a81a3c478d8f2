"""Shared by ``fig8`` and ``fig9``, the paper's real-robot experiments in simulation (physics body ``amosii``).

* Durations: a run's length is a number of control steps, the same at 10 Hz (the authors' simulator) as at 27 Hz
  (the real robot's controller): the networks count their time in steps (the CPG period, the weights' growth and
  decay), so an arm at either rate gives its network as many updates. A run stops once its outcome is decided
  (``until="escaped"``: the trunk in the arena's exit region).
* Runs: one per network and seed (:func:`config`), each kept with its top-view path (the term :data:`PATH`),
  sampled every :data:`PATH_EVERY_S` s (:func:`path_every` control steps), so that a figure can draw every seed's
  path without rerunning, and the control step it first saw an obstacle (:func:`seen_step`), where the paper's
  photo series starts its intervals.
* The example seed of each network is kept in full too (the term :data:`EXAMPLE`) for the snapshot strip, the
  neural traces and, on request, a video.
* Snapshots: rendered offscreen from a fixed camera over the arena, as the paper's photos are taken, at
  moments evenly spread from the start to the moment the robot got out (or the end of the run); the strip
  writes each frame's time on it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from neurowalk.body.registry import body_model
from neurowalk.experiments.reproduce.claims import Claim, interval
from neurowalk.experiments.study_runs import Kept, Term
from neurowalk.experiments.suites.long_runs import sample_steps
from neurowalk.experiments.suites.timing import steps_for
from neurowalk.neural.sensory import STATIC_B, STATIC_Q, initial_weights
from neurowalk.neural.variants import get_variant
from neurowalk.plotting import draw_arena
from neurowalk.plotting import runs as run_plots
from neurowalk.plotting.style import (
    FONT,
    LINE,
    OUTCOME_COLOURS,
    colorbar,
    legend_outside,
    letter,
)
from neurowalk.render import render_frames, render_video
from neurowalk.sim.config import EpisodeConfig

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure, SubFigure
    from matplotlib.gridspec import SubplotSpec

    from neurowalk.arenas.spec import ArenaSpec
    from neurowalk.experiments.study import Settings
    from neurowalk.sim.episode import Episode

NETWORKS: tuple[str, ...] = ("plastic", "static")
SEEN_M = 0.35  # m: "an obstacle seen": an echo nearer than this (activation 0.125; the noise's std is about 0.008)
PATH_EVERY_S = 1.0  # s of simulated time between stored path points (10 control steps at 10 Hz)
N_SNAPSHOTS = 6
ROBOT_REACH = 0.35  # m, the robot's feet from its trunk centre (0.33 m) with a margin: framed at the start
VIDEO_FPS = 15.0  # frames per second of the videos
VIDEO_SPEEDUP = 6.0  # the videos play at 6x simulated time (4 control steps a frame at 10 Hz)


def path_every(control_hz: float) -> int:
    """Control steps between stored path points: :data:`PATH_EVERY_S` s at ``control_hz`` Hz (at least 1)."""
    return steps_for(PATH_EVERY_S, control_hz)


def video_every(control_hz: float) -> int:
    """Control steps per video frame: :data:`VIDEO_SPEEDUP` x simulated time at :data:`VIDEO_FPS` (at least 1)."""
    return steps_for(VIDEO_SPEEDUP / VIDEO_FPS, control_hz)


def config(arena: str, opts: dict[str, float], network: str, seed: int, steps: int) -> EpisodeConfig:
    """One run: the ``network`` (a controller name) in ``arena`` (its options ``opts``) for at most ``steps`` control
    steps, stopped once in the arena's exit region (the settings' variant, params and control rate are applied by
    the runner)."""
    return EpisodeConfig(
        arena=arena, arena_opts=dict(opts), controller=network, steps=steps, seed=seed, until="escaped"
    )


def seen_step(us_distance: np.ndarray) -> int | None:
    """First control step at which either ultrasonic sensor read an obstacle nearer than :data:`SEEN_M` (from the
    readings ``us_distance`` (T, 2) m as the controller saw them, ``inf``: no echo); None if never."""
    idx = np.flatnonzero((np.asarray(us_distance) < SEEN_M).any(axis=1))
    return int(idx[0]) if len(idx) else None


def keep_path(ep: Episode) -> dict[str, Any]:
    """``path``: (n, 2) x, y in m: every :func:`path_every`-th row (every :data:`PATH_EVERY_S` s at the run's
    control rate) of the trunk's pose and the last row, rounded to 1 mm; ``seen_step``: :func:`seen_step`."""
    tr = ep.trajectory
    every = path_every(ep.config.control_hz)
    return {"path": np.round(sampled(tr.pose[:, :2], every), 3), "seen_step": seen_step(tr.us_distance)}


def sampled(xy: np.ndarray, every: int) -> np.ndarray:
    """Rows 0, ``every``, 2 ``every``, ... and the last row of ``xy`` (T, k)."""
    return xy[sample_steps(len(xy), every)]


def keep_example(ep: Episode) -> dict[str, Any]:
    """What the figures draw of an example run: time (T,) s, pose (T, 3), outputs, b, q (T, 2), qpos (T, nq)."""
    tr = ep.trajectory
    return {"t": tr.t, "pose": tr.pose, "outputs": tr.outputs, "b": tr.b, "q": tr.q, "qpos": tr.qpos}


#: The top-view path of a run (:func:`keep_path`), and an example run kept in full (:func:`keep_example`).
PATH = Term("path", keep_path, arrays={"path": "float64"})
EXAMPLE = Term("example", keep_example, arrays=dict.fromkeys(("t", "pose", "outputs", "b", "q", "qpos"), "float64"))


def with_path(runs: Sequence[Kept]) -> list[dict[str, Any]]:
    """Each run's summary (a dict) with its ``path`` and ``seen_step``."""
    return [{**r.summary.to_dict(), **r.kept["path"]} for r in runs]


def example_of(run: Kept) -> dict[str, Any]:
    """An example run as the figures draw it: ``summary`` (a dict) and the arrays of :func:`keep_example`."""
    return {"summary": run.summary.to_dict(), **run.kept["example"]}


def snapshot_rows(n_rows: int, end: int | None, n: int = N_SNAPSHOTS) -> np.ndarray:
    """``n`` control steps evenly spread from 0 to ``end`` (the step the robot got out; None: the last row)."""
    last = n_rows - 1 if end is None else min(int(end), n_rows - 1)
    return np.unique(np.linspace(0, last, n).round().astype(int))


def camera_view(arena: ArenaSpec, *, aspect: float = 4 / 3, fovy_deg: float = 45.0) -> dict[str, Any]:
    """A fixed camera over the arena's boxes and the robot at its start, x to the right of the frame.

    Returns the look-at point (m), distance (m), azimuth and elevation (deg) that frame the boxes in a picture of
    width/height ``aspect`` (MuJoCo's vertical field of view ``fovy_deg``).
    """
    start = np.array([arena.start[:2]]) + np.array([[-1, -1], [1, 1]]) * ROBOT_REACH
    pts = np.vstack([b.corners() for b in arena.boxes] + [start])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = float(max((hi[0] - lo[0]) / aspect, hi[1] - lo[1])) + 0.3
    distance = 0.5 * span / math.tan(math.radians(fovy_deg) / 2)
    return {
        "lookat": [float((lo[0] + hi[0]) / 2), float((lo[1] + hi[1]) / 2), 0.0],
        "distance": distance,
        "azimuth": 90.0,
        "elevation": -70.0,
    }


def snapshots(
    arena: ArenaSpec, qpos: np.ndarray, rows: np.ndarray, *, width: int = 400, height: int = 300
) -> np.ndarray:
    """Rendered frames (len(rows), height, width, 3) of the run's positions ``qpos`` (T, nq) at ``rows``."""
    view = camera_view(arena, aspect=width / height)
    return render_frames(body_model("amosii", arena), qpos[rows], view=view, width=width, height=height)


def network_arrays(
    net: str, runs: list[dict[str, Any]], example: dict[str, Any], arena: ArenaSpec, end: int | None
) -> dict[str, np.ndarray]:
    """A network's arrays: ``NET/path/K`` (n, 2) m, the top-view path of each of ``runs``; ``NET/snapshot_qpos``
    (n, nq), the example's positions at its snapshots (:func:`snapshot_rows` up to step ``end``; rendered by
    :func:`snapshot_frames`), ``NET/snapshot_t`` their times (s), and ``NET/example/KEY`` the example's t, pose,
    outputs, b, q (:func:`keep_example`)."""
    arrays = {f"{net}/path/{k}": np.asarray(r["path"]) for k, r in enumerate(runs)}
    rows = snapshot_rows(len(example["t"]), end)
    arrays[f"{net}/snapshot_qpos"] = example["qpos"][rows]
    arrays[f"{net}/snapshot_t"] = example["t"][rows]
    arrays.update({f"{net}/example/{key}": example[key] for key in ("t", "pose", "outputs", "b", "q")})
    return arrays


def snapshot_frames(
    arrays: Mapping[str, np.ndarray], nets: Sequence[str], arena: ArenaSpec, **size: int
) -> dict[str, np.ndarray]:
    """Each network's snapshots ``NET/frames`` (n, height, width, 3), rendered from ``NET/snapshot_qpos`` of
    :func:`network_arrays` (``size``: width, height in pixels, as :func:`snapshots`)."""
    return {
        f"{net}/frames": snapshots(arena, q, np.arange(len(q)), **size)
        for net in nets
        for q in [arrays[f"{net}/snapshot_qpos"]]
    }


def arena_geometry(arena: ArenaSpec) -> dict[str, Any]:
    """The arena's boxes (centre, yaw, sizes; m, rad), start pose and exit region, for the record."""
    return {
        "boxes": [[b.x, b.y, b.yaw, b.sx, b.sy, b.h] for b in arena.boxes],
        "box_fields": "x y yaw sx sy h",
        "start": list(arena.start),
        "exit_region": list(arena.exit_region),
    }


def run_record(
    s: Settings, arena: ArenaSpec, geometry: dict[str, Any], *, seeds: int, steps: int, rule: str, **timing: Any
) -> dict[str, Any]:
    """The head of a figure's summary: the arena and its ``geometry``, the seeds, the runs' length (``steps``
    control steps at the control rate of ``s``; ``timing``: further entries after ``duration_s``), the networks and
    the outcome ``rule``."""
    return {
        "arena": arena.name,
        "arena_opts": arena.options,
        "geometry": geometry,
        "seed": s.seed,
        "seeds": seeds,
        "steps": steps,
        "control_hz": float(s.rate),
        "duration_s": steps / s.rate,
        **timing,
        "variant": s.variant or "paper",
        "params": s.params,
        "body": "amosii",
        "networks": network_words(s.variant or "paper", s.params),
        "rule": rule,
    }


def network_words(variant: str, params: Mapping[str, float] | None = None) -> dict[str, str]:
    """The two networks of the real-robot figures in words, from the network ``variant`` and its ``params``: the
    plastic one's start weights, the static one's fixed weights."""
    v = get_variant(variant, params)
    b, q = initial_weights("plastic", v.sensory)
    start = f"b = {b[0]:g}, q = {q[0]:g}" if b[0] == b[1] and q[0] == q[1] else f"b = {b.tolist()}, q = {q.tolist()}"
    return {
        "plastic": f"plastic ({v.name}), weights start at {start}",
        "static": f"static (b = {STATIC_B:g}, c = {-STATIC_Q:g})",
    }


def write_videos(name: str, arena: ArenaSpec, examples: dict[str, dict[str, Any]], out: Path) -> list[str]:
    """One mp4 per network's example run in ``out`` (camera tracking the trunk, :data:`VIDEO_SPEEDUP` x simulated
    time); the paths written."""
    model = body_model("amosii", arena)
    paths = []
    for net, ex in examples.items():
        path = Path(out) / f"{name}-{net}-seed{ex['summary']['seed']}.mp4"
        every = video_every(ex["summary"]["control_hz"])
        render_video(model, ex["qpos"], path, fps=VIDEO_FPS, every=every, distance=1.6, progress=True)
        paths.append(str(path))
    return paths


def draw_strip(axes: list[Axes], frames: np.ndarray, times: list[float], label: str, panel: str | None = None) -> None:
    """The snapshot strip: one frame per axis, its time (s) written on it; ``label`` over the first frame (and the
    panel letter ``panel`` beside it)."""
    for i, ax in enumerate(axes):
        ax.axis("off")
        if i >= len(frames):
            continue
        ax.imshow(frames[i])
        ax.text(
            0.03,
            0.95,
            f"{times[i]:.0f} s",
            transform=ax.transAxes,
            va="top",
            fontsize=FONT["note"] + 1,
            color="white",
            bbox={"facecolor": "black", "alpha": 0.6, "lw": 0},
        )
    axes[0].set_title(label, loc="left")
    if panel:
        letter(axes[0], panel)


def draw_paths(
    ax: Axes,
    arena: ArenaSpec,
    paths: list[np.ndarray],
    good: list[bool],
    example: np.ndarray,
    title: str,
    *,
    t: np.ndarray | None = None,
    outcomes: tuple[str, str] = ("escaped", "not escaped"),
) -> None:
    """Top view of the arena's bounds: every seed's path (green: ``outcomes[0]``, red: ``outcomes[1]``), the
    example's coloured by time ``t`` (s, with a colour bar), start and end dots; a legend below."""
    path = draw_arena(ax, arena, example, t=t)
    for p, ok in zip(paths, good, strict=True):
        colour = OUTCOME_COLOURS["ok"] if ok else OUTCOME_COLOURS["failed"]
        ax.plot(p[:, 0], p[:, 1], color=colour, lw=LINE["thin"], alpha=0.5, zorder=1.5)
    ax.plot([], [], color=OUTCOME_COLOURS["ok"], lw=LINE["trace"], label=f"a seed: {outcomes[0]}")
    ax.plot([], [], color=OUTCOME_COLOURS["failed"], lw=LINE["trace"], label=f"a seed: {outcomes[1]}")
    if path is not None and t is not None:
        colorbar(path, ax, "time (s), the example seed", shrink=0.9)
    legend_outside(ax, side="below", ncol=2)
    ax.set_title(title)


def draw_traces(
    fig: Figure | SubFigure, spec: SubplotSpec, t: np.ndarray, outputs: np.ndarray, b: np.ndarray, q: np.ndarray,
    label: str,
) -> Axes:  # fmt: skip
    """Steering (O1, O2) over time (s) and, below it where the network has them, the weights b1, b2 and
    c = -(q1 + q2)/2, each on its own axes with its legend beside it, titled ``label: steering and weights``;
    returns the top axes."""
    plastic = bool(np.isfinite(b).any())
    title = f"{label}: steering" + (" and weights" if plastic else "")
    signals = [(outputs, "O", "steering O")]
    return run_plots.draw_traces(fig, spec, t, signals, b, q, title, plastic=plastic, lw=LINE["thin"])


def real_robot_claims(s: dict[str, Any]) -> list[Claim]:
    """Each interval of the figure's ``real_robot`` entry: the median simulated one over the runs where both its
    events happened against the real robot's (:func:`~neurowalk.experiments.reproduce.claims.interval`); none where
    the runs were not on the real robot's controller clock (27 Hz), whose times do not compare."""
    rr = s.get("real_robot", {})
    if not rr.get("same_clock"):
        return []
    claims = []
    for name, e in rr["events"].items():
        sim = e["sim"]
        context = (
            f" at {rr['control_hz']:g} Hz, median over the {sim['happened']} of {sim['runs']} runs where it happened "
            f"(range {sim['min_s']:.0f}-{sim['max_s']:.0f} s)"
            if sim["happened"]
            else f" at {rr['control_hz']:g} Hz: in none of {sim['runs']} runs"
        )
        context += f"; the paper: {e['paper']}"
        claims.append(interval(f"{name} (real robot's photos)", e["paper_s"], sim["median_s"], context))
    return claims
