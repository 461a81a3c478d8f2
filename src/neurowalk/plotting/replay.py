"""A run as a 3-D replay: the meshes of the arena and the robot, and where each moving part is at each step.

:func:`load_replay` reads a run's folder (``summary.json`` and ``trajectory.npz``, as ``neurowalk run`` writes
them) and rebuilds what a viewer draws, with no viewer in it (the web page is :mod:`neurowalk.plotting.web`):

- a MuJoCo body (AMOSII, the wheeled robot, a user's MJCF): every visible geom of the model (groups 0-2, as
  MuJoCo's viewer shows them), the arena's as fixed parts, the robot's merged into one part per body and colour,
  each posed at each step by forward kinematics (``mj_kinematics``) from the recorded ``qpos``; the ultrasonic
  rays start at the rangefinder sites ``US_L`` and ``US_R`` along their z axes;
- the planar surrogate: the arena's boxes, and the robot as its footprint (the calibration's circles, as flat
  discs) on its recorded pose, the rays from the calibration's origins and directions.

Rays are drawn as long as the echo (``us_distance``) or, without one, the sensor's range; they are coloured by
the network's input (I = -1 far, +1 near). A long run is replayed at most :data:`MAX_FRAMES` frames (every
k-th step); the traces keep every step.
"""

from __future__ import annotations

import json
import math
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from neurowalk import anatomy
from neurowalk.arenas.spec import ArenaSpec
from neurowalk.plotting.meshes import Mesh, box_mesh, cylinder_mesh, geom_mesh, merge, yaw_quat
from neurowalk.sim.config import EpisodeConfig, build
from neurowalk.sim.trajectory import Trajectory

#: The most frames a replay keeps (a longer run is shown every k-th step).
MAX_FRAMES = 20_000
#: MuJoCo's viewer shows geom groups 0, 1 and 2 by default; the others are collision or helper geoms.
VISIBLE_GROUPS = 3


class RunFolderError(ValueError):
    """A folder that is not a run's, or a run whose files are damaged: the message names the folder and the fault."""


@dataclass
class Part:
    """A rigid part of the scene: one mesh in its own frame, with one colour."""

    name: str
    mesh: Mesh
    rgb: tuple[int, int, int]
    opacity: float = 1.0


@dataclass
class Replay:
    """What a viewer draws of one run.

    Attributes:
        title: one line naming the run (arena, body, controller, steps).
        control_hz: control steps per second of simulated time.
        t: (T,) simulated time of each step, s. frames: (F,) the steps replayed (indices into ``t``).
        fixed: parts that do not move (the arena), each posed once: (part, position (3,) m, wxyz (4,)).
        parts: the moving parts (the robot's). pos: (F, P, 3) their positions, m. quat: (F, P, 4) wxyz.
        path: (T, 3) the trunk's position at each step, m.
        ray_from: (F, 2, 3) the two rays' origins, m (left, right). ray_to: (F, 2, 3) their ends, m.
        inputs, outputs, b, q: (T, 2) the network's inputs I1, I2, outputs O1, O2 and weights (NaN when fixed).
        summary: the run's ``summary.json``.
        wedged: (first step, last step) of each wedged period the summary names.
    """

    title: str
    control_hz: float
    t: np.ndarray
    frames: np.ndarray
    fixed: list[tuple[Part, np.ndarray, np.ndarray]]
    parts: list[Part]
    pos: np.ndarray
    quat: np.ndarray
    path: np.ndarray
    ray_from: np.ndarray
    ray_to: np.ndarray
    inputs: np.ndarray
    outputs: np.ndarray
    b: np.ndarray
    q: np.ndarray
    summary: dict[str, Any] = field(default_factory=dict)
    wedged: list[tuple[int, int]] = field(default_factory=list)

    @property
    def steps(self) -> int:
        """The number of recorded control steps."""
        return len(self.t)

    def frame_of_step(self, step: int) -> int:
        """The replayed frame that shows control step ``step`` (the last one at or before it)."""
        return int(np.clip(np.searchsorted(self.frames, step, side="right") - 1, 0, len(self.frames) - 1))


def read_run(folder: Path) -> tuple[dict[str, Any], Trajectory]:
    """The summary and trajectory of the run in ``folder``; :class:`RunFolderError` names what is wrong."""
    summary_path, traj_path = folder / "summary.json", folder / "trajectory.npz"
    if not folder.is_dir():
        raise RunFolderError(f"{str(folder)!r} is not a folder")
    if not summary_path.is_file() or not traj_path.is_file():
        raise RunFolderError(f"{str(folder)!r} is not a run's folder: it needs summary.json and trajectory.npz")
    try:
        summary = json.loads(summary_path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as e:
        raise RunFolderError(f"{summary_path}: not a readable summary ({e})") from None
    if not isinstance(summary, dict) or "arena" not in summary or "body" not in summary:
        raise RunFolderError(f"{summary_path}: not a run's summary (no arena or body)")
    try:
        tr = Trajectory.load(traj_path)
    except (OSError, ValueError, KeyError, zipfile.BadZipFile, EOFError) as e:
        raise RunFolderError(f"{traj_path}: damaged or incomplete arrays ({type(e).__name__}: {e})") from None
    n = len(tr.t)
    bad = [k for k, v in tr.arrays().items() if len(v) != n]
    if n == 0 or bad:
        raise RunFolderError(f"{traj_path}: damaged arrays (no steps, or columns of other lengths: {bad})")
    return summary, tr


def world_config(summary: dict[str, Any]) -> EpisodeConfig:
    """The run's world: arena, body and control rate from its summary (the rest does not change what is drawn)."""
    keys = ("arena", "arena_opts", "body", "body_opts", "control_hz")
    try:
        return EpisodeConfig.from_spec({k: summary[k] for k in keys if summary.get(k) is not None})
    except (TypeError, ValueError) as e:
        raise RunFolderError(f"the run's summary names a world neurowalk cannot build: {e}") from None


def load_replay(folder: str | Path, max_frames: int = MAX_FRAMES) -> Replay:
    """The replay of the run in ``folder`` (see the module doc); :class:`RunFolderError` for a bad folder."""
    folder = Path(folder)
    summary, tr = read_run(folder)
    cfg = world_config(summary)
    scenery = Scenery(cfg)
    stride = max(1, math.ceil(len(tr.t) / max_frames))
    frames = np.arange(0, len(tr.t), stride)
    if not scenery.fits(tr):
        raise RunFolderError(f"{folder / 'trajectory.npz'}: its qpos does not fit the {cfg.body} model")
    pos, quat, ray_from, ray_to = scenery.poses(tr.rows(0, len(tr.t)) if stride == 1 else tr.map(lambda v: v[frames]))
    wedged = [(int(w["start"]), int(w["end"])) for w in summary.get("wedged") or []]
    title = f"{cfg.arena}, {cfg.body}, {summary.get('controller', '?')}, {len(tr.t)} steps"
    return Replay(
        title, float(cfg.control_hz), tr.t, frames, scenery.fixed, scenery.parts, pos, quat, scenery.path(tr),
        ray_from, ray_to, tr.inputs, tr.outputs, tr.b, tr.q, summary, wedged,
    )  # fmt: skip


class Scenery:
    """What a run's world looks like: the fixed parts (the arena), the robot's parts, and where they are at a step.

    Args:
        cfg: the run's config (its arena, body and their options make the world).
    """

    def __init__(self, cfg: EpisodeConfig) -> None:
        arena, body, _ = build(cfg)
        self.model: mujoco.MjModel | None = getattr(body, "model", None)
        if self.model is not None:
            self.fixed, self.parts, self._bodies = _physics_parts(self.model)
            self._sites = [self.model.site(name).id for name in anatomy.US_SENSORS]
            self._data = mujoco.MjData(self.model)
            names = [self.model.numeric(i).name for i in range(self.model.nnumeric)]
            reach = [self.model.numeric(n).data[0] for n in names if n.endswith("/us_range")]
            self.reach = float(reach[0]) if reach else 0.4
        else:
            self.cal = body.cal
            self.fixed, self.parts = _planar_parts(arena, self.cal)
            self.reach = float(self.cal.us_range)

    def fits(self, tr: Trajectory) -> bool:
        """Whether ``tr`` was recorded in this world (a MuJoCo body's qpos has the model's size and is finite)."""
        return self.model is None or (tr.qpos.shape[1] == self.model.nq and bool(np.isfinite(tr.qpos).all()))

    def path(self, tr: Trajectory) -> np.ndarray:
        """(T, 3) the trunk's position at each row of ``tr``, m (a planar body's a little above the floor)."""
        if self.model is not None:
            return tr.qpos[:, :3].copy()
        return np.column_stack([tr.pose[:, :2], np.full(len(tr.t), 0.05)])

    def poses(self, tr: Trajectory) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """For each row of ``tr``: the parts' positions (n, P, 3) m and orientations (n, P, 4) wxyz, and the two
        rays' origins and ends (n, 2, 3) m (as long as the echo, or the range without one)."""
        if self.model is not None:
            pos, quat, ray_from, ray_dir = self._physics_poses(tr.qpos)
        else:
            pos, quat, ray_from, ray_dir = _planar_poses(self.cal, tr.pose)
        length = np.where(np.isfinite(tr.us_distance), tr.us_distance, self.reach)
        return pos, quat, ray_from, ray_from + ray_dir * length[..., None]

    def _physics_poses(self, qpos: np.ndarray) -> tuple[np.ndarray, ...]:
        model, data, n = self.model, self._data, len(qpos)
        pos, quat = np.empty((n, len(self.parts), 3)), np.empty((n, len(self.parts), 4))
        ray_from, ray_dir = np.empty((n, 2, 3)), np.empty((n, 2, 3))
        for i, qp in enumerate(qpos):
            data.qpos[:] = qp
            mujoco.mj_kinematics(model, data)
            pos[i], quat[i] = data.xpos[self._bodies], data.xquat[self._bodies]
            ray_from[i] = data.site_xpos[self._sites]
            ray_dir[i] = data.site_xmat[self._sites].reshape(2, 3, 3)[:, :, 2]  # a rangefinder looks along its z
        return pos, quat, ray_from, ray_dir


def _rgb(model: mujoco.MjModel, g: int) -> tuple[tuple[int, int, int], float]:
    rgba = model.mat_rgba[model.geom_matid[g]] if model.geom_matid[g] >= 0 else model.geom_rgba[g]
    return tuple(round(255 * float(c)) for c in rgba[:3]), float(rgba[3])  # type: ignore[return-value]


def _physics_parts(model: mujoco.MjModel) -> tuple[list[tuple[Part, np.ndarray, np.ndarray]], list[Part], np.ndarray]:
    """The fixed parts (posed), the moving parts (one per body and colour) and each moving part's body id."""
    fixed: list[tuple[Part, np.ndarray, np.ndarray]] = []
    groups: dict[tuple[int, tuple[int, int, int], float], list[Mesh]] = {}
    for g in range(model.ngeom):
        if model.geom_group[g] >= VISIBLE_GROUPS or model.geom_type[g] == mujoco.mjtGeom.mjGEOM_PLANE:
            continue
        rgb, alpha = _rgb(model, g)
        mesh = geom_mesh(model, g)
        if alpha == 0 or mesh is None:
            continue
        body = int(model.geom_bodyid[g])
        if model.body_weldid[body] == 0:  # welded to the world: the arena
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) or f"geom{g}"
            fixed.append((Part(name, mesh, rgb, alpha), np.zeros(3), np.array([1.0, 0, 0, 0])))
        else:
            groups.setdefault((body, rgb, alpha), []).append(mesh)
    keys = sorted(groups)
    parts = [Part(f"body{b}_{i}", merge(groups[(b, rgb, a)]), rgb, a) for i, (b, rgb, a) in enumerate(keys)]
    return fixed, parts, np.array([k[0] for k in keys], dtype=int)


def _planar_parts(arena: ArenaSpec, cal: Any) -> tuple[list[tuple[Part, np.ndarray, np.ndarray]], list[Part]]:
    """The arena's boxes (posed) and the planar robot's footprint (its calibration's circles, as flat discs)."""
    fixed = [
        (Part(f"box{i}", box_mesh(b.sx / 2, b.sy / 2, b.h / 2), (150, 150, 150)), np.array([b.x, b.y, b.h / 2]),
         yaw_quat(b.yaw))
        for i, b in enumerate(arena.boxes)
    ]  # fmt: skip
    discs = [cylinder_mesh(r, 0.02, centre=(x, y, 0.04)) for x, y, r in np.asarray(cal.circles, dtype=float)]
    return fixed, [Part("footprint", merge(discs), (60, 90, 160))]


def _planar_poses(cal: Any, pose: np.ndarray) -> tuple[np.ndarray, ...]:
    """The footprint's pose and the rays' origins and unit directions (from the calibration) on ``pose`` (n, 3)."""
    n = len(pose)
    pos = np.column_stack([pose[:, :2], np.zeros(n)])[:, None, :]
    quat = np.stack([yaw_quat(y) for y in pose[:, 2]])[:, None, :] if n else np.zeros((0, 1, 4))
    c, s = np.cos(pose[:, 2]), np.sin(pose[:, 2])
    rays = np.asarray(cal.rays, dtype=float)  # (2, 4): origin x, y and direction in the trunk frame
    ray_from, ray_dir = np.zeros((n, 2, 3)), np.zeros((n, 2, 3))
    for k in range(2):
        ox, oy, dx, dy = rays[k]
        ray_from[:, k] = np.column_stack([pose[:, 0] + c * ox - s * oy, pose[:, 1] + s * ox + c * oy, np.full(n, 0.1)])
        ray_dir[:, k, 0], ray_dir[:, k, 1] = c * dx - s * dy, s * dx + c * dy
    return pos, quat, ray_from, ray_dir
