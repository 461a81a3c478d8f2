"""Cheap readers of a compiled AMOSII model's state, for every control step.

Names are looked up once per model (cached weakly, keyed by the ``MjModel``); each reader then
only indexes arrays. Every reader returns new arrays or floats, never views into ``MjData``, and
reads what the last ``mj_step``/``mj_forward`` computed.

Obstacle height (stands in for AMOSII's laser range finder): rays in the front segment's
sagittal plane are cast from one point ``scanner_z`` above the trunk centre, 1 mm ahead of the
front face, at pitches from steeply down to 45° up (sites ``height_ray_<k>``, +z = ray). Each
hit whose horizontal distance from that point is within ``scanner_lookahead`` gives a world
point; its height above the ground (the lowest sole) is a height of the terrain ahead. The
reading is the largest such height (0 when nothing rises above the ground): exact for the top of
a step lower than the scanner; for a face taller than the rays reach (about 0.25-0.3 m at a
0.25 m distance) it is a lower bound. Robot geoms are never hit (rays stay in the trunk's
sagittal plane, and the front segment is excluded).

Ground heights (the same scanner looking straight down, world -z): the height of the terrain under
the front tip and under the trunk centre above the lowest sole. They tell a climbing controller
whether its front, then its middle, is already over a step.

Obstacle contact: whether any geom of the robot (trunk, legs, feet) touches a geom that is neither the
robot's nor a floor plane (a box, a wall, a step), from the contacts of the last collision pass.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass

import mujoco
import numpy as np

from neurowalk import anatomy
from neurowalk.body.amosii_params import (
    FRONT_BODY,
    NUMERIC_PREFIX,
    SCANNER_SITE_PREFIX,
    TRUNK_BODY,
    UP_SENSOR,
    foot_name,
)
from neurowalk.body.common import noisy_distance
from neurowalk.compiled import jit

__all__ = [
    "foot_contacts",
    "ground_heights",
    "joint_qpos_indices",
    "obstacle_contact",
    "obstacle_height",
    "read_us",
    "trunk_pose",
    "up_z",
]


@dataclass(frozen=True, eq=False)
class _Layout:
    """Indices into a compiled model's arrays, found once by name."""

    qpos: np.ndarray  # (19,) qpos addresses, actuator order
    us: np.ndarray  # (2,) sensordata addresses of US_L, US_R
    touch: np.ndarray  # (6,) sensordata addresses of the foot touch sensors, LEGS order
    up: int  # sensordata address of the trunk up vector's z component
    trunk: int  # body id of the trunk
    front: int  # body id of the front segment (excluded from the scanner's rays)
    scanner: np.ndarray  # (n,) site ids of the scanner rays
    feet: np.ndarray  # (6,) geom ids of the feet, LEGS order
    robot_geom: np.ndarray  # (ngeom,) bool: the geom belongs to the robot
    obstacle_geom: np.ndarray  # (ngeom,) bool: the geom is neither the robot's nor a plane
    foot_radius: float  # m
    us_range: float  # m
    force_full: float  # N
    lookahead: float  # m


_LAYOUTS: weakref.WeakKeyDictionary[mujoco.MjModel, _Layout] = weakref.WeakKeyDictionary()


def _numeric(model: mujoco.MjModel, key: str) -> float:
    return float(model.numeric(NUMERIC_PREFIX + key).data[0])


def _sensor_adr(model: mujoco.MjModel, name: str) -> int:
    return int(model.sensor_adr[model.sensor(name).id])


def _build_layout(model: mujoco.MjModel) -> _Layout:
    joints = [model.joint(name).id for name in anatomy.ACTUATORS]
    n_rays = sum(
        1
        for i in range(model.nsite)
        if mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_SITE, i).startswith(SCANNER_SITE_PREFIX)
    )
    feet = np.array([model.geom(foot_name(g)).id for g in anatomy.LEGS])
    robot = model.body_rootid[model.geom_bodyid] == model.body(TRUNK_BODY).id
    return _Layout(
        qpos=model.jnt_qposadr[joints].copy(),
        us=np.array([_sensor_adr(model, n) for n in anatomy.US_SENSORS]),
        touch=np.array([_sensor_adr(model, foot_name(g)) for g in anatomy.LEGS]),
        up=_sensor_adr(model, UP_SENSOR) + 2,
        trunk=model.body(TRUNK_BODY).id,
        front=model.body(FRONT_BODY).id,
        scanner=np.array([model.site(f"{SCANNER_SITE_PREFIX}{k}").id for k in range(n_rays)]),
        feet=feet,
        robot_geom=robot,
        obstacle_geom=~robot & (model.geom_type != mujoco.mjtGeom.mjGEOM_PLANE),
        foot_radius=float(model.geom_size[feet[0], 0]),
        us_range=_numeric(model, "us_range"),
        force_full=_numeric(model, "contact_force_full"),
        lookahead=_numeric(model, "scanner_lookahead"),
    )


def sensor_layout(model: mujoco.MjModel) -> _Layout:
    layout = _LAYOUTS.get(model)
    if layout is None:
        layout = _LAYOUTS[model] = _build_layout(model)
    return layout


def joint_qpos_indices(model: mujoco.MjModel) -> np.ndarray:
    """Return the qpos addresses of the 19 joints, shape (19,), actuator order (``data.qpos[idx]`` in rad)."""
    return sensor_layout(model).qpos.copy()


def read_us(model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """Ultrasonic distances in m, shape (2,), order (US_L, US_R); ``inf`` for no echo in range."""
    return us_distances(sensor_layout(model), data.sensordata)


def us_distances(lay: _Layout, sensordata: np.ndarray) -> np.ndarray:
    """Ultrasonic distances in m (..., 2) from MuJoCo's sensor data (..., nsensordata) of one world or of many;
    ``inf`` for no echo in range."""
    d = sensordata[..., lay.us]
    return np.where((d < 0.0) | (d > lay.us_range), np.inf, d)


def foot_contacts(model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """Foot contact per leg in [0, 1], shape (6,), ``anatomy.LEGS`` order.

    The normal force on each foot divided by ``contact_force_full`` and clipped to 1.
    """
    return contacts(sensor_layout(model), data.sensordata)


def contacts(lay: _Layout, sensordata: np.ndarray) -> np.ndarray:
    """Foot contacts in [0, 1] (..., 6) from MuJoCo's sensor data (..., nsensordata) of one world or of many."""
    return np.minimum(sensordata[..., lay.touch] / lay.force_full, 1.0)


def sensed(lay: _Layout, sensordata: np.ndarray, us_range: float, noise: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """What AmosII's controller reads, of one world or of many (the CPU loop's and the lock-step worlds' one sensor
    model): the noisy ultrasonic distances (..., 2) in m (``inf``: no echo) and the noisy foot contacts (..., 6) in
    [0, 1], from MuJoCo's sensor data (..., nsensordata) and the step's sensor noise (..., 2 + 19 + 6: ultrasonic,
    joints, feet; :class:`~neurowalk.body.noise.ColoredNoise`); ``us_range``: the network's ultrasonic range, m."""
    if sensordata.ndim == 2:  # many worlds (the lock-step worlds' every step: no reshaping)
        dist, foot = np.empty((len(sensordata), 2)), np.empty((len(sensordata), 6))
        _sensed(lay.us, lay.touch, lay.us_range, lay.force_full, sensordata, us_range, noise, dist, foot)
        return dist, foot
    lead = sensordata.shape[:-1]
    dist, foot = np.empty((*lead, 2)), np.empty((*lead, 6))
    sd, nz = sensordata.reshape(-1, sensordata.shape[-1]), noise.reshape(-1, noise.shape[-1])
    _sensed(lay.us, lay.touch, lay.us_range, lay.force_full, sd, us_range, nz, dist.reshape(-1, 2), foot.reshape(-1, 6))
    return dist, foot


@jit
def _sensed(
    us: np.ndarray,
    touch: np.ndarray,
    us_max: float,
    force_full: float,
    sensordata: np.ndarray,
    us_range: float,
    noise: np.ndarray,
    dist: np.ndarray,
    foot: np.ndarray,
) -> None:
    """:func:`sensed` of m worlds (sensordata (m, nsensordata), noise (m, channels)) into dist (m, 2), foot (m, 6):
    the arithmetic of :func:`us_distances`, :func:`contacts` and the noise, element by element, in one call."""
    feet = noise.shape[1] - 6
    for i in range(sensordata.shape[0]):
        for r in range(2):
            d = sensordata[i, us[r]]
            raw = math.inf if (d < 0.0 or d > us_max) else d
            dist[i, r] = noisy_distance(raw, us_range, noise[i, r])
        for g in range(6):
            c = min(sensordata[i, touch[g]] / force_full, 1.0) + noise[i, feet + g]
            foot[i, g] = min(max(c, 0.0), 1.0)


def obstacle_contact(model: mujoco.MjModel, data: mujoco.MjData) -> bool:
    """Whether the robot's trunk or a leg touches an obstacle (any geom but the robot's and floor planes)."""
    if data.ncon == 0:
        return False
    lay = sensor_layout(model)
    g = data.contact.geom[: data.ncon]  # (ncon, 2) geom ids
    robot, obstacle = lay.robot_geom[g], lay.obstacle_geom[g]
    return bool(np.any((robot[:, 0] & obstacle[:, 1]) | (robot[:, 1] & obstacle[:, 0])))


def up_z(model: mujoco.MjModel, data: mujoco.MjData) -> float:
    """World z component of the trunk's up axis (1 upright, 0 on its side, -1 upside down)."""
    return float(data.sensordata[sensor_layout(model).up])


@jit
def trunk_poses(xpos: np.ndarray, xmat: np.ndarray, trunk: int, out: np.ndarray) -> None:
    """:func:`trunk_pose` of many worlds into ``out`` (n, 3), from their ``xpos`` (n, nbody, 3) and ``xmat`` (n,
    nbody, 9): the same arithmetic (``atan2`` of the heading), bit for bit."""
    for i in range(out.shape[0]):
        out[i, 0], out[i, 1] = xpos[i, trunk, 0], xpos[i, trunk, 1]
        out[i, 2] = math.atan2(xmat[i, trunk, 3], xmat[i, trunk, 0])


def trunk_pose(model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """Trunk-centre pose (x m, y m, yaw rad), shape (3,), yaw of the heading in (-π, π]."""
    lay = sensor_layout(model)
    pos, mat = data.xpos[lay.trunk], data.xmat[lay.trunk]
    return np.array([pos[0], pos[1], math.atan2(mat[3], mat[0])])


def obstacle_height(model: mujoco.MjModel, data: mujoco.MjData) -> float:
    """Height in m of the terrain ahead above the lowest sole (0 when flat); see module doc."""
    lay = sensor_layout(model)
    origin = data.site_xpos[lay.scanner[0]]
    vec = data.site_xmat[lay.scanner][:, 2::3]  # (n, 3) world ray directions: site z axes
    n = len(lay.scanner)
    dist = np.empty(n)
    geomid = np.empty(n, dtype=np.int32)
    cutoff = 4.0 * lay.lookahead
    mujoco.mj_multiRay(model, data, origin, vec.ravel(), None, 1, lay.front, geomid, dist, None, n, cutoff)
    hit = dist >= 0.0
    if not hit.any():
        return 0.0
    points = origin + dist[hit, None] * vec[hit]
    near = np.hypot(points[:, 0] - origin[0], points[:, 1] - origin[1]) <= lay.lookahead
    if not near.any():
        return 0.0
    ground = data.geom_xpos[lay.feet, 2].min() - lay.foot_radius
    return max(0.0, float(points[near, 2].max() - ground))


def _down_height(model: mujoco.MjModel, data: mujoco.MjData, origin: np.ndarray, exclude: int, ground: float) -> float:
    down = np.array([0.0, 0.0, -1.0])
    geomid = np.zeros(1, dtype=np.int32)
    dist = mujoco.mj_ray(model, data, origin, down, None, 1, exclude, geomid)
    if dist < 0.0:
        return 0.0
    return max(0.0, float(origin[2] - dist - ground))


def ground_heights(model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """(2,) heights in m of the terrain under the front tip and under the trunk centre, above the lowest sole."""
    lay = sensor_layout(model)
    ground = data.geom_xpos[lay.feet, 2].min() - lay.foot_radius
    front = _down_height(model, data, data.site_xpos[lay.scanner[0]].copy(), lay.front, ground)
    centre = _down_height(model, data, data.xpos[lay.trunk].copy(), lay.trunk, ground)
    return np.array([front, centre])
