"""Numbers and MJCF names of the simulated AMOSII body (no MuJoCo import here).

Dimensions, masses, joint ranges and servo limits follow the original LPZRobots model
(``reference/original_code_facts.md`` §5.2 and §7). Every angle is in radians and in the controller
sign convention of :mod:`neurowalk.anatomy` (TC + forward, CTr + up, FTi + extension, BJ + up);
zero pose = every leg straight, horizontal, pointing laterally.

Frames: x = the robot's heading, y = its left, z = up; the trunk centre is the middle of the
0.43 m trunk box (it lies in the rear segment, which carries the free joint).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from neurowalk import anatomy

_DEG = math.pi / 180.0

# MJCF names that are not joint or actuator names (those come from ``anatomy``).
TRUNK_BODY = "trunk"
"""Rear trunk segment: the free body; its frame origin is the trunk centre."""
FRONT_BODY = "front"
"""Front trunk segment, hinged to the trunk by ``BJ``; it carries the front legs and the sensors."""
IMU_SITE = "imu"
UP_SENSOR = "trunk_up"
"""``framezaxis`` sensor of the trunk: its world z component is :func:`up_z`."""
SCANNER_SITE_PREFIX = "height_ray_"
"""Sites ``height_ray_0 ...`` of the obstacle-height scanner: one origin, one ray per site (+z)."""
STAND_KEY = "stand"
"""Keyframe whose ``ctrl`` holds the standing pose (its qpos is qpos0, which already stands)."""
NUMERIC_PREFIX = "amosii/"
"""Prefix of the ``<custom><numeric>`` fields that carry sensor settings inside the model."""


def foot_name(leg: str) -> str:
    """Name of the foot geom, the foot site and the foot touch sensor of ``leg``, e.g. ``foot_R1``."""
    if leg not in anatomy.LEGS:
        raise ValueError(f"unknown leg {leg!r}; expected one of {anatomy.LEGS}")
    return f"foot_{leg}"


def _rad(lo_deg: float, hi_deg: float) -> tuple[float, float]:
    return (lo_deg * _DEG, hi_deg * _DEG)


@dataclass(frozen=True, kw_only=True)
class BodyParams:
    """Every number of the AMOSII body, in SI units (m, kg, s, rad, N, N·m).

    Override with ``dataclasses.replace``. Angles are in the controller sign convention.
    ``backbone_x`` (the hinge position) is derived: the front segment ends at the front face.
    """

    # Trunk: two boxes joined by the backbone hinge (pitch).
    trunk_length: float = 0.43  # m, rear face to front face
    trunk_width: float = 0.07  # m
    trunk_height: float = 0.065  # m
    front_length: float = 0.12  # m, front segment, ahead of the backbone hinge
    front_mass: float = 0.837  # kg, front segment (without its legs)
    rear_mass: float = 2.163  # kg, rear/centre segment (without its legs)
    # Legs. Attachment points relative to the trunk centre.
    leg_x: tuple[float, float, float] = (0.175, 0.025, -0.165)  # m, front, middle, hind
    leg_y: float = 0.035  # m, lateral offset of the attachment (side face)
    leg_z: float = 0.0325  # m, height of the attachment above the trunk centre (top face)
    shoulder_length: float = 0.045  # m, fixed to the trunk, points laterally
    shoulder_radius: float = 0.0129  # m
    coxa_length: float = 0.035  # m, TC joint (vertical axis) to CTr joint
    coxa_radius: float = 0.0172  # m
    femur_length: float = 0.06  # m, CTr joint to FTi joint
    femur_radius: float = 0.0129  # m
    tibia_length: float = 0.115  # m, FTi joint to the sole, foot included
    tibia_radius: float = 0.013  # m
    foot_radius: float = 0.015  # m, sphere at the tibia tip
    # Masses as the authors' simulator applies them (original_code_facts.md §13): 6.70 kg in all. Its configured
    # shoulder masses (6 x 0.192 kg) go to a transform without a body and never act: the shoulders weigh nothing.
    link_mass: float = 0.19205  # kg, each coxa, femur and tibia
    foot_mass: float = 0.04043  # kg, each foot
    shoulder_mass: float = 0.0  # kg, each shoulder (fixed to the trunk)
    # Joint ranges (rad, controller sign); they are also the servos' command ranges.
    tc_range_outer: tuple[float, float] = _rad(-70.0, 70.0)  # rad, TC of front and hind legs
    tc_range_middle: tuple[float, float] = _rad(-60.0, 60.0)  # rad, TC of middle legs
    ctr_range: tuple[float, float] = _rad(-75.0, 75.0)  # rad
    fti_range: tuple[float, float] = _rad(-130.0, -20.0)  # rad
    bj_range: tuple[float, float] = _rad(-45.0, 45.0)  # rad
    # Standing pose: mid walking range of TC; CTr and FTi at stance values.
    stand_tc: tuple[float, float, float] = (25.0 * _DEG, 0.0, -35.0 * _DEG)  # rad, front/mid/hind
    stand_ctr: float = 45.0 * _DEG  # rad
    stand_fti: float = -125.0 * _DEG  # rad
    start_clearance: float = 0.001  # m, soles above the floor at the start
    # Position servos (MuJoCo ``position`` actuators).
    leg_kp: float = 30.0  # N·m/rad
    leg_kv: float = 1.0  # N·m·s/rad
    leg_force: float = 26.75  # N·m, torque limit (the original servo power)
    bj_kp: float = 90.0  # N·m/rad, about the legs' kp scaled by the power ratio
    bj_kv: float = 3.0  # N·m·s/rad
    bj_force: float = 80.26  # N·m
    armature: float = 0.005  # kg·m², rotor inertia added to every hinge (a servo's rotor, reflected by its gears)
    # Each servo follows its target through a first-order lag of this time constant (s; 0: none), as a servo does
    # (the authors' simulated servo is a lag of 1 / 5.24 s before its speed limit): a jump of the target no longer
    # whips the legs in one physics step, and a 10 ms step integrates the gait as a 2.5 ms one does
    # (docs/performance.md, "One physics for every run"). MuJoCo's position actuator ``timeconst``.
    servo_timeconst: float = 0.03  # s
    # Optional passive compliance of every hinge about the standing pose (0, 0 = off).
    joint_stiffness: float = 0.0  # N·m/rad
    joint_damping: float = 0.0  # N·m·s/rad
    # Contact. MuJoCo combines frictions with max: keep the floor low, set the feet.
    foot_friction: float = 1.0  # sliding friction coefficient of the feet
    body_friction: float = 0.5  # sliding friction of all other robot geoms
    floor_friction: float = 0.1  # sliding friction of the floor plane
    timestep: float = 0.01  # s, physics step: the authors' simulator's (10 physics steps per 10 Hz control step)
    solver_iterations: int = 20  # most solver iterations per physics step (MuJoCo's default 100)
    solver_tolerance: float = 1e-6  # the solver stops when its cost improves by less than this (MuJoCo's 1e-8)
    # MuJoCo's integrator (one of INTEGRATORS): "discrete" takes the servos' stiffness and damping into the step's
    # implicit update ("implicitfast" their damping only).
    integrator: str = "discrete"
    solver: str = "Newton"  # MuJoCo's constraint solver: one of SOLVERS (MuJoCo Warp has no PGS)
    # The friction cone (one of CONES). Elliptic: with the pyramid the robot climbs less (and with a foot friction of
    # 2 or more the trunk sinks).
    cone: str = "elliptic"
    # MuJoCo's constraint Jacobian: one of JACOBIANS. Its layout changes no physics, only the cost (MuJoCo Warp
    # takes it dense: its sparse path does not repeat a run bit for bit).
    jacobian: str = "sparse"
    contact_timeconst: float = 0.02  # s, time constant of every contact (geom solref, damping ratio 1; MuJoCo's 0.02)
    # Ultrasonic sensors: rays from 1 mm ahead of the front face, yawed outward.
    us_yaw: float = 35.0 * _DEG  # rad, outward yaw of each ray
    us_range: float = 0.40  # m, farther echoes read as none
    us_y: float = 0.0175  # m, lateral offset of each sensor
    us_z: float = 0.0  # m, height above the trunk centre
    us_ahead: float = 0.001  # m, gap between the front face and the sensor sites
    # Foot contact: touch force (N) that reads as full contact 1.0.
    contact_force_full: float = 10.0  # N
    # Obstacle-height scanner (stands in for the laser range finder): a fan of rays in the
    # sagittal plane from one point above the front face; pitch > 0 looks up.
    scanner_z: float = 0.10  # m, height of the fan's origin above the trunk centre
    scanner_pitches: tuple[float, ...] = tuple(
        d * _DEG for d in (-60, -45, -35, -28, -22, -17, -13, -9, -5, 0, 10, 20, 30, 45)
    )  # rad
    scanner_lookahead: float = 0.40  # m, horizontal reach counted as "ahead"

    def __post_init__(self) -> None:
        """Check every field; raise ValueError naming the first bad one."""
        for name, allowed in (
            ("integrator", INTEGRATORS),
            ("solver", SOLVERS),
            ("cone", CONES),
            ("jacobian", JACOBIANS),
        ):
            if getattr(self, name) not in allowed:
                _bad(name, getattr(self, name), f"must be one of {', '.join(allowed)}")
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name in ("integrator", "solver", "cone", "jacobian"):
                continue
            n = _TUPLE_LENGTHS.get(f.name)
            if n is not None and not (isinstance(v, tuple) and len(v) == n):
                _bad(f.name, v, f"must be a tuple of {n} numbers")
            values = v if isinstance(v, tuple) else (v,)
            if not all(isinstance(x, int | float) and math.isfinite(x) for x in values):
                _bad(f.name, v, "must be finite numbers")
            if f.name.startswith("stand_") or isinstance(v, tuple) or f.name in _SIGNED:
                continue  # checked below, or any sign is fine
            if f.name in _NONNEGATIVE:
                if v < 0.0:
                    _bad(f.name, v, "must be >= 0")
            elif v <= 0.0:
                _bad(f.name, v, "must be > 0")
        if not isinstance(self.solver_iterations, int) or isinstance(self.solver_iterations, bool):
            _bad("solver_iterations", self.solver_iterations, "must be a whole number >= 1")
        for name in ("tc_range_outer", "tc_range_middle", "ctr_range", "fti_range", "bj_range"):
            lo, hi = getattr(self, name)
            if not lo < hi:
                _bad(name, (lo, hi), "must be (lo, hi) with lo < hi")
        if not _inside(0.0, self.bj_range):
            _bad("bj_range", self.bj_range, "must contain 0 (the standing backbone angle)")
        self._check_geometry()
        self._check_pose()

    def _check_geometry(self) -> None:
        if not self.front_length < self.trunk_length:
            _bad("front_length", self.front_length, "must be shorter than trunk_length")
        half = self.trunk_length / 2.0
        front, middle, hind = self.leg_x
        if not (self.backbone_x < front < half and -half < hind < middle < self.backbone_x):
            _bad("leg_x", self.leg_x, "must be hind < middle < backbone hinge < front, on the trunk")
        if self.leg_y > self.trunk_width / 2.0:
            _bad("leg_y", self.leg_y, "must not exceed half of trunk_width")
        if self.us_y >= self.trunk_width / 2.0:
            _bad("us_y", self.us_y, "must be less than half of trunk_width")
        if not 2.0 * self.foot_radius < self.tibia_length:
            _bad("tibia_length", self.tibia_length, "must exceed the foot diameter")
        if not self.us_yaw < math.pi / 2.0:
            _bad("us_yaw", self.us_yaw, "must be in (0, π/2)")
        if not self.scanner_pitches or not all(abs(p) < math.pi / 2 for p in self.scanner_pitches):
            _bad("scanner_pitches", self.scanner_pitches, "must be non-empty, each in (-π/2, π/2)")

    def _check_pose(self) -> None:
        for name, value, rng in (
            ("stand_tc", self.stand_tc[0], self.tc_range_outer),
            ("stand_tc", self.stand_tc[1], self.tc_range_middle),
            ("stand_tc", self.stand_tc[2], self.tc_range_outer),
            ("stand_ctr", self.stand_ctr, self.ctr_range),
            ("stand_fti", self.stand_fti, self.fti_range),
        ):
            if not _inside(value, rng):
                _bad(name, value, f"must lie inside the joint range {rng}")
        if stand_height(self) - self.trunk_height / 2.0 <= 0.0:
            _bad("stand_ctr", self.stand_ctr, "with stand_fti puts the trunk on the floor")

    @property
    def backbone_x(self) -> float:
        """Backbone hinge x from the trunk centre (m): the front face minus ``front_length``."""
        return self.trunk_length / 2.0 - self.front_length

    @property
    def total_mass(self) -> float:
        """Mass of the whole robot (kg)."""
        per_leg = self.shoulder_mass + 3 * self.link_mass + self.foot_mass
        return self.front_mass + self.rear_mass + len(anatomy.LEGS) * per_leg


INTEGRATORS: tuple[str, ...] = ("implicitfast", "discrete", "implicit", "RK4", "Euler")
"""MuJoCo's integrators by their MJCF names (``<option integrator=...>``)."""
SOLVERS: tuple[str, ...] = ("Newton", "PGS", "CG")
"""MuJoCo's constraint solvers by their MJCF names (``<option solver=...>``)."""
CONES: tuple[str, ...] = ("elliptic", "pyramidal")
"""MuJoCo's friction cones by their MJCF names (``<option cone=...>``)."""
JACOBIANS: tuple[str, ...] = ("sparse", "dense", "auto")
"""MuJoCo's constraint Jacobians by their MJCF names (``<option jacobian=...>``)."""

_NONNEGATIVE = frozenset({"joint_stiffness", "joint_damping", "body_friction", "shoulder_mass", "servo_timeconst"})
_SIGNED = frozenset({"us_z"})
_TUPLE_LENGTHS = {"leg_x": 3, "stand_tc": 3} | {
    name: 2 for name in ("tc_range_outer", "tc_range_middle", "ctr_range", "fti_range", "bj_range")
}


def _inside(x: float, rng: tuple[float, float]) -> bool:
    return rng[0] <= x <= rng[1]


def _bad(name: str, value: object, why: str) -> None:
    raise ValueError(f"BodyParams.{name} {why}, got {value!r}")


def tc_range(params: BodyParams, leg: str) -> tuple[float, float]:
    """TC joint range (rad) of ``leg``: the middle legs have their own."""
    return params.tc_range_middle if anatomy.LEG_POSITION[leg] == 1 else params.tc_range_outer


def stand_height(params: BodyParams) -> float:
    """Trunk-centre height above the soles (m) in the standing pose, the trunk level."""
    p = params
    knee = p.leg_z + p.femur_length * math.sin(p.stand_ctr)
    foot_centre = knee + (p.tibia_length - p.foot_radius) * math.sin(p.stand_ctr + p.stand_fti)
    return -(foot_centre - p.foot_radius)


def standing_pose(params: BodyParams | None = None) -> np.ndarray:
    """Joint targets of the standing pose, shape (19,), rad, actuator order, controller sign."""
    p = BodyParams() if params is None else params
    pose = np.zeros(anatomy.N_ACTUATORS)
    for leg in anatomy.LEGS:
        pose[anatomy.joint_index("TC", leg)] = p.stand_tc[anatomy.LEG_POSITION[leg]]
        pose[anatomy.joint_index("CTr", leg)] = p.stand_ctr
        pose[anatomy.joint_index("FTi", leg)] = p.stand_fti
    pose[anatomy.BJ_INDEX] = 0.0
    return pose
