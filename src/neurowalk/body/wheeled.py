"""A differential-drive robot in MuJoCo with AMOSII's footprint, speed and ultrasonic sensors (``--body wheeled``).

The model: a free chassis box (its frame origin is the middle of the wheel axle, ``wheel_radius`` above the
floor), two driven wheels on hinges about the chassis y axis (``wheel_R``, ``wheel_L``: cylinders, velocity
servos with a torque limit), two passive caster spheres fixed under the front and rear of the chassis (low
friction: they slide), and the rangefinders ``US_L`` and ``US_R`` on the front face. Steering (O1, O2) drives the
wheels directly (see :class:`~neurowalk.body.wheeled_body.Wheeled`): no legs, no locomotion network.

Numbers taken from AMOSII (``BodyParams()``, stand keyframe), so that arenas and the network's distance scale carry
over at ``scale`` = 1:

- Footprint: the exact world x-y bounding box of every AMOSII geom (trunk boxes, leg capsules, feet) in the standing
  pose: x from -0.2344 to +0.2301 m about the trunk centre, y within ±0.1898 m, i.e. 0.4644 m x 0.3796 m. The wheel
  axle sits where AMOSII's trunk centre is (``front`` = 0.2301 m behind the front face); the wheels' outer faces are
  the footprint's sides.
- Forward speed at full forward command (steering (-1, -1)): 0.01415 m/s, AMOSII's measured forward speed at that
  steering in the surrogate calibration before issue 51 (``body/data/calibration.json``, ``velocity[0][0][0]``;
  0.01435 m/s at the physics of issue 51). The wheel speed
  limit is ``omega_max`` = speed / wheel_radius (0.472 rad/s by default). Turning on the spot at (-1, 1) is then
  2·speed / track = 0.0787 rad/s in theory (track 0.3596 m), where AMOSII turns at
  0.045 rad/s (calibration, steering (-1, 1)): an axle as wide as the footprint cannot turn as slowly as the hexapod
  at full wheel speed.
- Ultrasonic sensors: ±0.0175 m to the sides, yawed 35° outward, range 0.40 m, at 0.03855 m above the floor
  (AMOSII's trunk-centre height standing, where its sensors sit). The sites sit ``us_inset`` = 2 mm behind the
  front face, inside the chassis box: a rangefinder ignores the geoms of its own body, so the rays never hit the
  robot, and they still start outside an obstacle that the front face presses against (a site 1 mm ahead of the
  face, as on AMOSII, whose feet keep it off walls, would start inside the wall and read its far side). Readings
  are from the sites: 2.4 mm more than from the face along a ray.
- Mass: 6.69948 kg in all (AMOSII's, as the authors' simulator applies it).

``scale`` multiplies every length (footprint, wheels, casters, centre of mass, sensor offsets, height and range)
and the forward speed, so the wheels' angular speeds stay as they are; the servo gain, torque limit and rotor
inertia are multiplied by ``scale`` too (the same push at the treads, the same servo response time), masses are
not. ``scale`` = 0.1 gives a Khepera-sized robot (4.6 cm x 3.8 cm) driving at 1.4 mm/s with a 4 cm sensor range
(note that :func:`neurowalk.neural.sensory.distance_to_input` maps 0.05-0.40 m whatever the body).

Support: the robot rests on its two wheels and the rear caster (the chassis's centre of mass is ``com_x`` = 2 cm
behind the axle, so the rear caster carries about a tenth of the weight); the front caster hangs ``caster_gap`` =
2 mm above the floor and catches the chassis when it pitches forward. Four supports at one height would leave the
wheels nearly unloaded in MuJoCo's soft contact model (they slipped).

Physics settings: timestep 0.01 s (10 physics steps per 10 Hz control step, as AMOSII's),
implicitfast integrator, pyramidal friction cone (cheaper than smaller steps or the elliptic cone, and stable here;
0.02 s runs about twice as fast again, but a ``scale`` 0.1 robot then rocks 2° in pitch). The wheel servos are
MuJoCo ``velocity`` actuators (kv 5 N·m·s/rad, torque limit 0.5 N·m at scale 1) on hinges with 0.05 kg·m² of
armature at scale 1 (a geared motor's reflected rotor inertia): below the torque limit implicitfast integrates the
servo's damping implicitly, and at the limit one step changes the wheel speed by at most torque·timestep/armature =
0.1 rad/s, so the servo never chatters between its limits (``motor_kv`` must not exceed armature/timestep). Robot
geoms use ``solimp`` 0.99 (hard contacts): the wheels sink 0.02 mm rather than 0.2 mm into the floor, which would
shrink a 3 mm wheel's rolling radius at ``scale`` 0.1. Steady forward speed is within 1% of ``speed`` at scales
0.05 to 4; turning on the spot reaches about 98% of 2·speed/track (the two-rim cylinder contacts scrub).

Contacts: the floor has its own collision bit (contype = conaffinity = 4); wheels and casters collide with the
floor and with arena geoms (MuJoCo's default bit 1), the chassis only with arena geoms (so a scaled-down robot never
drags its belly), and robot geoms never with each other. Wheels and casters carry ``priority`` 1, so their own
frictions (wheel grip 1.0, caster 0.01) hold on any floor or box whatever its friction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from neurowalk import anatomy
from neurowalk.body.amosii_mjcf import SCENE_HEAD

__all__ = [
    "CASTER_PREFIX",
    "CHASSIS_BODY",
    "LEFT_WHEEL",
    "NUMERIC_PREFIX",
    "REST_KEY",
    "RIGHT_WHEEL",
    "WheeledParams",
    "wheeled_xml",
]

_DEG = math.pi / 180.0

CHASSIS_BODY = "chassis"
"""The free body; its frame origin is the middle of the wheel axle."""
RIGHT_WHEEL = "wheel_R"
"""Body, hinge joint, geom and actuator of the right wheel (driven by O1)."""
LEFT_WHEEL = "wheel_L"
"""Body, hinge joint, geom and actuator of the left wheel (driven by O2)."""
CASTER_PREFIX = "caster_"
"""Caster sphere geoms ``caster_front`` and ``caster_rear`` (fixed to the chassis)."""
REST_KEY = "rest"
"""Keyframe: standing on the wheels at the origin, facing +x, at rest, wheels commanded still."""
NUMERIC_PREFIX = "wheeled/"
"""Prefix of the ``<custom><numeric>`` fields that carry the sensor range and wheel speed limit inside the model."""

_FLOOR_BIT = 4  # collision bit of the floor plane only
_ROBOT_BIT = 2  # contype of every robot geom: robot geoms collide with nothing of their own
_ARENA_BIT = 1  # MuJoCo's default contype/conaffinity, which arena geoms keep


@dataclass(frozen=True, kw_only=True)
class WheeledParams:
    """Every number of the wheeled robot, in SI units (m, kg, s, rad, N·m), at ``scale`` = 1.

    Lengths and ``speed`` are given for ``scale`` = 1; the model uses them multiplied by ``scale`` (see
    :meth:`scaled`). Override with ``dataclasses.replace``.
    """

    scale: float = 1.0  # multiplies every length and the forward speed
    # Chassis: a box spanning AMOSII's standing footprint.
    length: float = 0.4644  # m, footprint extent along x (front face to rear face)
    width: float = 0.3796  # m, footprint extent along y (outer face of one wheel to the other's)
    front: float = 0.2301  # m, front face ahead of the wheel axle
    height: float = 0.065  # m, chassis box height (AMOSII's trunk height), centred on the sensor height
    mass: float = 6.69948  # kg, whole robot (AMOSII's total mass, BodyParams().total_mass)
    # Driven wheels.
    wheel_radius: float = 0.03  # m
    wheel_width: float = 0.02  # m
    wheel_gap: float = 0.004  # m, between a wheel's inner face and the chassis side
    wheel_mass: float = 0.2  # kg, each
    wheel_friction: float = 1.0  # sliding friction of the wheel treads
    speed: float = 0.01415  # m/s, forward speed at full forward command (AMOSII's, calibration.json)
    motor_kv: float = 5.0  # N·m·s/rad, velocity servo gain (times ``scale``)
    motor_torque: float = 0.5  # N·m, motor torque limit, forcerange (times ``scale``): 33 N of push at the treads
    wheel_armature: float = 0.05  # kg·m², reflected rotor inertia of each geared wheel motor (times ``scale``)
    com_x: float = -0.02  # m, chassis centre of mass ahead of the axle (< 0: behind it, toward the rear caster)
    # Passive casters (front and rear, on the centre line; massless, part of the chassis).
    caster_radius: float = 0.01  # m
    caster_gap: float = 0.002  # m, front caster above the floor at rest (the rear one touches)
    caster_friction: float = 0.01  # sliding friction: the casters slide
    # Ultrasonic sensors (AMOSII's yaw, range, spacing and height): rays from just behind the front face.
    us_yaw: float = 35.0 * _DEG  # rad, outward yaw of each ray
    us_range: float = 0.40  # m, farther echoes read as none
    us_y: float = 0.0175  # m, lateral offset of each sensor
    us_height: float = 0.03855  # m, above the floor (AMOSII's standing trunk-centre height)
    us_inset: float = 0.002  # m, sensor sites behind the front face, inside the chassis (see the module doc)
    start_clearance: float = 0.0005  # m, wheels and casters above the floor at the rest pose
    timestep: float = 0.01  # s, physics step

    def __post_init__(self) -> None:
        """Check every field; raise ValueError naming the first bad one."""
        for f in fields(self):
            v = getattr(self, f.name)
            if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
                _bad(f.name, v, "must be a finite number")
            if f.name in _SIGNED:
                continue
            if f.name in _NONNEGATIVE:
                if v < 0.0:
                    _bad(f.name, v, "must be >= 0")
            elif v <= 0.0:
                _bad(f.name, v, "must be > 0")
        if not self.us_yaw < math.pi / 2.0:
            _bad("us_yaw", self.us_yaw, "must be in (0, π/2)")
        if not self.us_inset < self.length:
            _bad("us_inset", self.us_inset, "must be less than length (the sensors sit in the chassis)")
        if not self.front < self.length - self.wheel_radius:
            _bad("front", self.front, "must leave room for the wheels behind the axle (front < length - wheel_radius)")
        if not self.wheel_radius < self.front:
            _bad("wheel_radius", self.wheel_radius, "must be less than front (the wheels must fit under the chassis)")
        if not self.chassis_width > 2.0 * self.us_y:
            _bad(
                "width",
                self.width,
                "leaves no chassis between the wheels for the sensors (width - 2 wheel_width "
                "- 2 wheel_gap must exceed 2 us_y)",
            )
        if not self.us_height - self.height / 2.0 < 2.0 * self.caster_radius:
            _bad(
                "caster_radius",
                self.caster_radius,
                "must reach the chassis bottom (2 caster_radius > us_height - height/2)",
            )
        if not 4.0 * self.caster_radius < self.length:
            _bad("caster_radius", self.caster_radius, "must fit twice along the chassis (4 caster_radius < length)")
        if not self.motor_kv <= self.wheel_armature / self.timestep:
            _bad(
                "motor_kv",
                self.motor_kv,
                "must be <= wheel_armature / timestep, or the servo chatters at its torque limit",
            )
        if not self.chassis_mass > 0.0:
            _bad("mass", self.mass, "must exceed the wheels' masses")
        if not self.front - self.length + 2.0 * self.caster_radius < self.com_x < 0.0:
            _bad("com_x", self.com_x, "must lie between the rear caster and the axle (the robot rests on them)")
        if not self.caster_gap < self.caster_radius:
            _bad("caster_gap", self.caster_gap, "must be less than caster_radius")

    @property
    def chassis_width(self) -> float:
        """Width of the chassis box between the wheels (m, at scale 1)."""
        return self.width - 2.0 * (self.wheel_width + self.wheel_gap)

    @property
    def chassis_mass(self) -> float:
        """Mass of the chassis with its casters (kg): ``mass`` less the wheels."""
        return self.mass - 2.0 * self.wheel_mass

    @property
    def track(self) -> float:
        """Distance between the wheels' mid-planes (m, scaled)."""
        return self.scale * (self.width - self.wheel_width)

    @property
    def omega_max(self) -> float:
        """Wheel angular speed at full command (rad/s): speed / wheel_radius, the same at every scale."""
        return self.speed / self.wheel_radius

    def scaled(self, name: str) -> float:
        """Length or speed field ``name`` multiplied by ``scale`` (m or m/s)."""
        if name not in _SCALED:
            raise ValueError(f"WheeledParams.{name} is not a length or speed")
        return self.scale * getattr(self, name)


_NONNEGATIVE = frozenset({"wheel_gap", "caster_gap", "caster_friction", "us_inset", "start_clearance"})
_SIGNED = frozenset({"com_x"})
_SCALED = frozenset(
    {"length", "width", "front", "height", "wheel_radius", "wheel_width", "wheel_gap", "speed", "com_x"}
    | {"caster_radius", "caster_gap", "us_range", "us_y", "us_height", "us_inset", "start_clearance"}
)


def _bad(name: str, value: object, why: str) -> None:
    raise ValueError(f"WheeledParams.{name} {why}, got {value!r}")


def _n(*values: float) -> str:
    """Numbers as an MJCF attribute value."""
    return " ".join(f"{v:.9g}" for v in values)


def _robot(p: WheeledParams) -> str:
    """The robot's body tree at the rest pose (origin, facing +x), wheels ``start_clearance`` above the floor."""
    s = p.scale
    r, hw = s * p.wheel_radius, s * p.wheel_width / 2.0
    length, front, height = s * p.length, s * p.front, s * p.height
    box_z = s * p.us_height - r  # chassis centre (and sensor) height in the chassis frame
    wheel_y = s * (p.width - p.wheel_width) / 2.0
    cr, width = s * p.caster_radius, s * p.chassis_width
    m = p.chassis_mass
    inertia = (m / 12.0 * (width**2 + height**2), m / 12.0 * (length**2 + height**2), m / 12.0 * (length**2 + width**2))
    lines = [
        f'    <body name="{CHASSIS_BODY}" pos="{_n(0, 0, r + s * p.start_clearance)}" childclass="wheeled">',
        '      <freejoint name="root"/>',
        f'      <inertial pos="{_n(s * p.com_x, 0, box_z)}" mass="{_n(m)}" diaginertia="{_n(*inertia)}"/>',
        f'      <geom name="{CHASSIS_BODY}" type="box" pos="{_n(front - length / 2.0, 0, box_z)}" '
        f'size="{_n(length / 2.0, width / 2.0, height / 2.0)}"/>',
    ]
    for name, x, gap in (("front", front - 2.0 * cr, s * p.caster_gap), ("rear", front - length + 2.0 * cr, 0.0)):
        lines.append(
            f'      <geom name="{CASTER_PREFIX}{name}" class="caster" type="sphere" size="{_n(cr)}" '
            f'pos="{_n(x, 0, cr - r + gap)}"/>'
        )
    x_us = front - s * p.us_inset
    for name, side in zip(anatomy.US_SENSORS, (1, -1), strict=True):  # (left, right)
        zaxis = _n(math.cos(p.us_yaw), side * math.sin(p.us_yaw), 0)
        lines.append(f'      <site name="{name}" pos="{_n(x_us, side * s * p.us_y, box_z)}" zaxis="{zaxis}"/>')
    for name, side in ((LEFT_WHEEL, 1), (RIGHT_WHEEL, -1)):
        lines += [
            f'      <body name="{name}" pos="{_n(0, side * wheel_y, 0)}">',
            f'        <joint name="{name}" type="hinge" axis="0 1 0"/>',
            f'        <geom name="{name}" class="wheel" type="cylinder" size="{_n(r, hw)}" zaxis="0 1 0" '
            f'mass="{_n(p.wheel_mass)}"/>',
            "      </body>",
        ]
    lines.append("    </body>")
    return "\n".join(lines)


def wheeled_xml(params: WheeledParams | None = None, world: str = "") -> str:
    """Full MJCF of the wheeled robot on a floor plane; ``world`` goes verbatim into <worldbody>.

    Args:
        params: the robot's numbers (default ``WheeledParams()``).
        world: MJCF elements (walls, boxes, steps) placed in the world body by an arena
            (``ArenaSpec.to_mjcf()``).

    Returns:
        A self-contained MJCF document (no includes, no mesh files). Its keyframe ``rest`` (= qpos0) stands the
        robot on its wheels at the origin facing +x, at rest; actuators ``wheel_R``, ``wheel_L`` (in that order)
        take wheel angular velocity targets in rad/s, + rolling forward.
    """
    p = params or WheeledParams()
    s = p.scale
    numeric = {"us_range": s * p.us_range, "omega_max": p.omega_max}
    custom = "\n".join(f'    <numeric name="{NUMERIC_PREFIX}{k}" data="{_n(v)}"/>' for k, v in numeric.items())
    wmax = p.omega_max
    tau = s * p.motor_torque
    servo = f'kv="{_n(s * p.motor_kv)}" ctrlrange="{_n(-wmax, wmax)}" forcerange="{_n(-tau, tau)}"'
    z0 = s * (p.wheel_radius + p.start_clearance)
    fric = "0.005 0.0001"  # torsional, rolling (unused with condim 3)
    touch_floor = _ARENA_BIT | _FLOOR_BIT
    return f"""<mujoco model="wheeled">
  <compiler angle="radian" autolimits="true"/>
  <option timestep="{_n(p.timestep)}" integrator="implicitfast" cone="pyramidal"/>
  <visual><global offwidth="1280" offheight="720"/></visual>
  <default>
    <default class="wheeled">
      <geom contype="{_ROBOT_BIT}" conaffinity="{_ARENA_BIT}" friction="0.5 {fric}" solimp="0.99 0.99 0.001" \
rgba=".6 .62 .68 1"/>
      <joint armature="{_n(s * p.wheel_armature)}"/>
      <site group="3" size="{_n(0.005 * s)}" rgba="1 .2 .2 .6"/>
      <default class="wheel">
        <geom conaffinity="{touch_floor}" priority="1" friction="{_n(p.wheel_friction)} {fric}" \
rgba=".15 .15 .15 1"/>
      </default>
      <default class="caster">
        <geom conaffinity="{touch_floor}" priority="1" friction="{_n(p.caster_friction)} {fric}" \
rgba=".8 .8 .8 1"/>
      </default>
    </default>
  </default>
{SCENE_HEAD.format(custom=custom)}
    <geom name="floor" type="plane" size="0 0 0.05" material="floor" contype="{_FLOOR_BIT}" \
conaffinity="{_FLOOR_BIT}" friction="0.1 {fric}"/>
{_robot(p)}
{world}
  </worldbody>
  <actuator>
    <velocity name="{RIGHT_WHEEL}" joint="{RIGHT_WHEEL}" {servo}/>
    <velocity name="{LEFT_WHEEL}" joint="{LEFT_WHEEL}" {servo}/>
  </actuator>
  <sensor>
{chr(10).join(f'    <rangefinder name="{n}" site="{n}"/>' for n in anatomy.US_SENSORS)}
  </sensor>
  <keyframe>
    <key name="{REST_KEY}" qpos="{_n(0, 0, z0, 1, 0, 0, 0, 0, 0)}" ctrl="0 0"/>
  </keyframe>
</mujoco>
"""
