"""The one MJCF writer of the simulated AMOSII hexapod, and its file export.

The model: a free rear trunk segment (the trunk centre is its frame origin) and a front segment
hinged to it by the pitch backbone joint ``BJ``; six legs of shoulder (fixed), coxa (``TC``,
vertical axis), femur (``CTr``) and tibia (``FTi``) ending in a spherical foot; 19 position
servos in ``anatomy.ACTUATORS`` order, so ``data.ctrl`` is in actuator order.

Sign conventions live in the hinge axes, mirrored per side, so every joint's qpos is already in
the controller's sign (TC + swings the foot toward +x, CTr + lifts it, FTi + straightens the
tibia, BJ + tilts the front segment up). Each hinge has ``ref`` = its standing angle and the
bodies are written in the standing pose, so qpos0 is the standing pose and a fresh ``MjData``
starts standing at rest just above the floor; reset with the ``stand`` keyframe to get the
standing ``ctrl`` too (``ctrl`` = 0 would command the straight, horizontal zero pose).

Sensors (names from ``anatomy`` and ``amosii_params``): rangefinders ``US_L`` and ``US_R``, touch
``foot_<leg>``, ``trunk_up`` (framezaxis), and the sites ``height_ray_<k>`` of the
obstacle-height scanner, cast from Python at control rate (see ``amosii_sensors``). Robot geoms
never collide with each other (contype 2, conaffinity 1); they collide with the floor and with
arena geoms that keep MuJoCo's default contype/conaffinity of 1.
"""

from __future__ import annotations

import math
import os
import tempfile
from pathlib import Path

import mujoco

from neurowalk import anatomy
from neurowalk.body.amosii_params import (
    FRONT_BODY,
    IMU_SITE,
    NUMERIC_PREFIX,
    SCANNER_SITE_PREFIX,
    STAND_KEY,
    TRUNK_BODY,
    UP_SENSOR,
    BodyParams,
    foot_name,
    stand_height,
    standing_pose,
    tc_range,
)
from neurowalk.body.amosii_sensors import (
    foot_contacts,
    ground_heights,
    joint_qpos_indices,
    obstacle_contact,
    obstacle_height,
    read_us,
    trunk_pose,
    up_z,
)

__all__ = [
    "BodyParams",
    "amosii_xml",
    "export_model",
    "foot_contacts",
    "ground_heights",
    "joint_qpos_indices",
    "obstacle_contact",
    "obstacle_height",
    "read_us",
    "stand_height",
    "standing_pose",
    "trunk_pose",
    "up_z",
]

_DEFAULT = BodyParams()


def _n(*values: float) -> str:
    """Numbers as an MJCF attribute value."""
    return " ".join(f"{v:.9g}" for v in values)


def _side(leg: str) -> int:
    """+1 for a leg on the left side (+y), -1 for one on the right."""
    return 1 if anatomy.LEG_SIDE[leg] == "L" else -1


def _leg(p: BodyParams, leg: str, parent_x: float, indent: str) -> tuple[str, str]:
    """(shoulder geom of the parent segment, leg body tree) of ``leg``, in the standing pose.

    Each hinge's axis carries the sign convention (left: TC about -z, CTr/FTi about +x; the
    right side mirrored), each body is rotated by its joint's standing angle, and ``ref`` is set
    to that angle so that qpos reads the controller angle.
    """
    s = _side(leg)
    pos = anatomy.LEG_POSITION[leg]
    ax, ay, az = p.leg_x[pos] - parent_x, s * p.leg_y, p.leg_z
    shoulder = (
        f'{indent}<geom name="shoulder_{leg}" type="capsule" size="{_n(p.shoulder_radius)}" '
        f'fromto="{_n(ax, ay, az, ax, ay + s * p.shoulder_length, az)}" '
        f'mass="{_n(p.shoulder_mass)}"/>'
    )
    tc_lo, tc_hi = tc_range(p, leg)
    hinges = (
        (
            "TC",
            "coxa",
            (ax, ay + s * p.shoulder_length, az),
            (0, 0, -s),
            p.stand_tc[pos],
            (tc_lo, tc_hi),
            p.coxa_length,
            p.coxa_radius,
        ),
        (
            "CTr",
            "femur",
            (0, s * p.coxa_length, 0),
            (s, 0, 0),
            p.stand_ctr,
            p.ctr_range,
            p.femur_length,
            p.femur_radius,
        ),
        (
            "FTi",
            "tibia",
            (0, s * p.femur_length, 0),
            (s, 0, 0),
            p.stand_fti,
            p.fti_range,
            p.tibia_length - p.foot_radius,
            p.tibia_radius,
        ),
    )
    lines: list[str] = []
    for depth, (joint, link, at, axis, angle, rng, length, radius) in enumerate(hinges):
        ind = indent + "  " * depth
        lines += [
            f'{ind}<body name="{link}_{leg}" pos="{_n(*at)}" axisangle="{_n(*axis, angle)}">',
            f'{ind}  <joint name="{anatomy.actuator_name(joint, leg)}" axis="{_n(*axis)}" '
            f'range="{_n(*rng)}" ref="{_n(angle)}" springref="{_n(angle)}"/>',
            f'{ind}  <geom name="{link}_{leg}" type="capsule" size="{_n(radius)}" '
            f'fromto="{_n(0, 0, 0, 0, s * length, 0)}" mass="{_n(p.link_mass)}"/>',
        ]
    ind = indent + "    " + "  "
    foot = _n(0, s * (p.tibia_length - p.foot_radius), 0)
    lines += [
        f'{ind}<geom name="{foot_name(leg)}" class="foot" type="sphere" '
        f'size="{_n(p.foot_radius)}" pos="{foot}" mass="{_n(p.foot_mass)}"/>',
        f'{ind}<site name="{foot_name(leg)}" size="{_n(1.2 * p.foot_radius)}" pos="{foot}"/>',
    ]
    lines += [indent + "  " * d + "</body>" for d in (2, 1, 0)]
    return shoulder, "\n".join(lines)


def _front_sensors(p: BodyParams, indent: str) -> str:
    """Sites of the ultrasonic sensors and of the obstacle-height scanner (front-segment frame)."""
    x = p.front_length + p.us_ahead
    lines = []
    for name, s in zip(anatomy.US_SENSORS, (1, -1), strict=True):  # (left, right)
        zaxis = _n(math.cos(p.us_yaw), s * math.sin(p.us_yaw), 0)
        lines.append(f'{indent}<site name="{name}" pos="{_n(x, s * p.us_y, p.us_z)}" zaxis="{zaxis}"/>')
    for k, pitch in enumerate(p.scanner_pitches):
        zaxis = _n(math.cos(pitch), 0, math.sin(pitch))
        lines.append(f'{indent}<site name="{SCANNER_SITE_PREFIX}{k}" pos="{_n(x, 0, p.scanner_z)}" zaxis="{zaxis}"/>')
    return "\n".join(lines)


def _robot(p: BodyParams) -> str:
    """Write the robot's body tree, standing, its soles ``start_clearance`` above the floor."""
    bx, half = p.backbone_x, p.trunk_length / 2.0
    rear_half = (bx + half) / 2.0
    shoulders: dict[str, list[str]] = {TRUNK_BODY: [], FRONT_BODY: []}
    legs: dict[str, list[str]] = {TRUNK_BODY: [], FRONT_BODY: []}
    for leg in anatomy.LEGS:
        on_front = anatomy.LEG_POSITION[leg] == 0
        parent, parent_x, ind = (FRONT_BODY, bx, " " * 8) if on_front else (TRUNK_BODY, 0.0, " " * 6)
        shoulder, tree = _leg(p, leg, parent_x, ind)
        shoulders[parent].append(shoulder)
        legs[parent].append(tree)
    z0 = stand_height(p) + p.start_clearance
    box = _n(rear_half, p.trunk_width / 2.0, p.trunk_height / 2.0)
    front_box = _n(p.front_length / 2.0, p.trunk_width / 2.0, p.trunk_height / 2.0)
    return "\n".join(
        [
            f'    <body name="{TRUNK_BODY}" pos="{_n(0, 0, z0)}" childclass="amosii">',
            '      <freejoint name="root"/>',
            f'      <geom name="trunk_rear" type="box" pos="{_n(bx - rear_half, 0, 0)}" '
            f'size="{box}" mass="{_n(p.rear_mass)}"/>',
            f'      <site name="{IMU_SITE}"/>',
            *shoulders[TRUNK_BODY],
            *legs[TRUNK_BODY],
            f'      <body name="{FRONT_BODY}" pos="{_n(bx, 0, 0)}">',
            f'        <joint name="{anatomy.BACKBONE}" axis="0 -1 0" range="{_n(*p.bj_range)}"/>',
            f'        <geom name="trunk_front" type="box" pos="{_n(p.front_length / 2, 0, 0)}" '
            f'size="{front_box}" mass="{_n(p.front_mass)}"/>',
            _front_sensors(p, " " * 8),
            *shoulders[FRONT_BODY],
            *legs[FRONT_BODY],
            "      </body>",
            "    </body>",
        ]
    )


def _actuators(p: BodyParams) -> str:
    leg_joints = {anatomy.actuator_name(j, g): (j, g) for j in anatomy.LEG_JOINTS for g in anatomy.LEGS}
    lines = []
    for name in anatomy.ACTUATORS:
        if name == anatomy.BACKBONE:
            kp, kv, force, rng = p.bj_kp, p.bj_kv, p.bj_force, p.bj_range
        else:
            joint, leg = leg_joints[name]
            rng = {"TC": tc_range(p, leg), "CTr": p.ctr_range, "FTi": p.fti_range}[joint]
            kp, kv, force = p.leg_kp, p.leg_kv, p.leg_force
        lag = f' timeconst="{_n(p.servo_timeconst)}"' if p.servo_timeconst > 0 else ""
        lines.append(
            f'    <position name="{name}" joint="{name}" kp="{_n(kp)}" kv="{_n(kv)}"{lag} '
            f'forcerange="{_n(-force, force)}" ctrlrange="{_n(*rng)}"/>'
        )
    return "\n".join(lines)


def _sensors() -> str:
    lines = [f'    <rangefinder name="{n}" site="{n}"/>' for n in anatomy.US_SENSORS]
    lines += [f'    <touch name="{foot_name(g)}" site="{foot_name(g)}"/>' for g in anatomy.LEGS]
    lines.append(f'    <framezaxis name="{UP_SENSOR}" objtype="site" objname="{IMU_SITE}"/>')
    return "\n".join(lines)


def _lagged_start(p: BodyParams) -> str:
    """The stand keyframe's servo states: each lagged target starts at the standing pose (none without a lag)."""
    return f' act="{_n(*standing_pose(p))}"' if p.servo_timeconst > 0 else ""


SCENE_HEAD = """  <asset>
    <texture name="grid" type="2d" builtin="checker" width="256" height="256" \
rgb1=".85 .85 .82" rgb2=".7 .72 .75"/>
    <material name="floor" texture="grid" texrepeat="4 4" texuniform="true"/>
  </asset>
  <custom>
{custom}
  </custom>
  <worldbody>
    <light name="sun" pos="0 0 4" dir="0 0 -1" directional="true"/>"""
"""The MJCF shared by the bodies' writers: the floor's checker material, the ``<custom>`` numerics (``custom``), the
opening of the worldbody and its light."""


def amosii_xml(params: BodyParams = _DEFAULT, *, world: str = "") -> str:
    """Full MJCF of AMOSII standing on a floor plane; ``world`` goes verbatim into <worldbody>.

    Args:
        params: the body's numbers.
        world: MJCF elements (walls, boxes, steps) placed in the world body by an arena.

    Returns:
        A self-contained MJCF document (no includes, no mesh files).
    """
    p = params
    numeric = {
        "us_range": p.us_range,
        "contact_force_full": p.contact_force_full,
        "scanner_lookahead": p.scanner_lookahead,
    }
    custom = "\n".join(f'    <numeric name="{NUMERIC_PREFIX}{k}" data="{_n(v)}"/>' for k, v in numeric.items())
    fric = "0.005 0.0001"  # torsional, rolling
    return f"""<mujoco model="amosii">
  <compiler angle="radian" autolimits="true"/>
  <option timestep="{_n(p.timestep)}" integrator="{p.integrator}" solver="{p.solver}" cone="{p.cone}" \
jacobian="{p.jacobian}" iterations="{p.solver_iterations}" tolerance="{_n(p.solver_tolerance)}"/>
  <visual><global offwidth="1280" offheight="720"/></visual>
  <default>
    <geom solref="{_n(p.contact_timeconst)} 1"/>
    <default class="amosii">
      <geom contype="2" conaffinity="1" friction="{_n(p.body_friction)} {fric}" rgba=".6 .62 .68 1"/>
      <joint armature="{_n(p.armature)}" stiffness="{_n(p.joint_stiffness)}" \
damping="{_n(p.joint_damping)}"/>
      <site group="3" size="0.005" rgba="1 .2 .2 .6"/>
      <default class="foot">
        <geom friction="{_n(p.foot_friction)} {fric}" rgba=".15 .15 .15 1"/>
      </default>
    </default>
  </default>
{SCENE_HEAD.format(custom=custom)}
    <geom name="floor" type="plane" size="0 0 0.05" material="floor" \
friction="{_n(p.floor_friction)} {fric}"/>
{_robot(p)}
{world}
  </worldbody>
  <actuator>
{_actuators(p)}
  </actuator>
  <sensor>
{_sensors()}
  </sensor>
  <keyframe>
    <key name="{STAND_KEY}" ctrl="{_n(*standing_pose(p))}"{_lagged_start(p)}/>
  </keyframe>
</mujoco>
"""


def export_model(path: str | os.PathLike[str], params: BodyParams = _DEFAULT, world: str = "") -> Path:
    """Write the self-contained MJCF to ``path`` atomically (compiled first; nothing half-written).

    Raises:
        ValueError: if the MJCF does not compile (e.g. a malformed ``world``).
    """
    xml = amosii_xml(params, world=world)
    mujoco.MjModel.from_xml_string(xml)  # raises ValueError before anything is written
    target = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(xml)
        os.chmod(tmp, 0o644)  # mkstemp makes it private; a model file is meant to be shared
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return target
