"""The wheeled robot in MuJoCo as a body of the control loop: reset in an arena, observe, steer, advance.

It mirrors :class:`~neurowalk.body.amosii.AmosII`'s interface, but ``apply`` takes the steering pair (O1, O2)
(``action = "steering"``) and drives the wheels with it, Table 1's signs kept: the right wheel from O1, the left
from O2, wheel angular velocity target -O·omega_max (after clipping O to [-1, 1]). So (-1, -1) drives forward,
(1, 1) backward, (-1, 1) turns left, (1, -1) turns right and (0, 0) stops; the amplitude sets the speed.

Observations carry the two ultrasonic distances with AMOSII's coloured noise treatment (the noise acts on the
normalised signal US = max(0, 1 - d/range), from the run's Generator), the chassis pose and the time; the robot has
no feet, joints or obstacle scanner, so foot contacts, joint angles and heights read zero. The distances are in the
robot's own units, metres divided by ``scale`` (its sensor range always reads 0.4): so the networks' distance scale
(0.05-0.4) means the same for a robot of any size, as a small robot's own sensors are made for its size; poses stay
in metres.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from neurowalk import anatomy
from neurowalk.arenas.spec import ArenaSpec
from neurowalk.body.common import noisy_distance, place_at_start
from neurowalk.body.noise import ColoredNoise
from neurowalk.body.physics import mujoco_warnings, set_control_rate
from neurowalk.body.wheeled import (
    CHASSIS_BODY,
    LEFT_WHEEL,
    NUMERIC_PREFIX,
    REST_KEY,
    RIGHT_WHEEL,
    WheeledParams,
    wheeled_xml,
)
from neurowalk.observation import Observation

__all__ = ["Wheeled", "chassis_pose", "read_us"]


def chassis_pose(model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """Chassis pose (x m, y m, yaw rad), shape (3,): the middle of the wheel axle, yaw of the heading in (-π, π]."""
    b = model.body(CHASSIS_BODY).id
    pos, mat = data.xpos[b], data.xmat[b]
    return np.array([pos[0], pos[1], math.atan2(mat[3], mat[0])])


def read_us(model: mujoco.MjModel, data: mujoco.MjData, us_range: float | None = None) -> np.ndarray:
    """Ultrasonic distances in m, shape (2,), order (US_L, US_R); ``inf`` for no echo within ``us_range`` m.

    ``us_range`` defaults to the range the model carries (``<numeric name="wheeled/us_range">``).
    """
    if us_range is None:
        us_range = float(model.numeric(NUMERIC_PREFIX + "us_range").data[0])
    adr = [model.sensor_adr[model.sensor(name).id] for name in anatomy.US_SENSORS]
    d = data.sensordata[adr]
    return np.where((d < 0.0) | (d > us_range), np.inf, d)


class Wheeled:
    """The differential-drive robot in an arena.

    Args:
        arena: where it drives.
        params: the robot's numbers (default ``WheeledParams()``: AMOSII's footprint, speed and sensors).
        control_hz: control rate (Hz); the physics step (0.01 s) is fitted to it (``set_control_rate``).
        noise: strength of the coloured ultrasonic noise (0 switches it off).
    """

    name = "wheeled"
    action = "steering"
    """What :meth:`apply` takes: the steering pair (O1, O2), not joint targets."""

    def __init__(
        self, arena: ArenaSpec, params: WheeledParams | None = None, *, control_hz: float = 10.0, noise: float = 0.02
    ) -> None:
        self.arena = arena
        self.params = params or WheeledParams()
        self.model = mujoco.MjModel.from_xml_string(wheeled_xml(self.params, world=arena.to_mjcf()))
        self.data = mujoco.MjData(self.model)
        self.control_hz = control_hz
        self.n_substeps = set_control_rate(self.model, control_hz)
        m = self.model
        self._us_adr = tuple(int(m.sensor_adr[m.sensor(name).id]) for name in anatomy.US_SENSORS)
        self._us_range = self.params.scaled("us_range")
        self._unit = self.params.scale  # m per body unit: readings are reported in the body's own units
        self._omega_max = self.params.omega_max
        self._right = m.actuator(RIGHT_WHEEL).id
        self._left = m.actuator(LEFT_WHEEL).id
        self._chassis = m.body(CHASSIS_BODY).id
        self._key = m.key(REST_KEY).id
        self._noise = ColoredNoise(2, strength=noise)

    def reset(self, rng: np.random.Generator) -> None:
        """Standing on the wheels at the arena's start pose, at rest, wheels stopped; noise drawn from ``rng``."""
        m, d = self.model, self.data
        if self._key >= 0:
            mujoco.mj_resetDataKeyframe(m, d, self._key)
        else:  # a user's model without a keyframe (neurowalk.body.user_mjcf)
            mujoco.mj_resetData(m, d)
        place_at_start(d.qpos, self.arena.start)
        mujoco.mj_forward(m, d)
        self._noise.reset(rng)

    @property
    def qidx(self) -> np.ndarray | None:
        """qpos addresses of the joints the body records (a legged user model's 19), or None (wheels)."""
        return getattr(self, "_qidx", None)

    @property
    def noise(self) -> ColoredNoise:
        """The sensor noise source (channels 0-1: the ultrasonic sensors)."""
        return self._noise

    def pose(self) -> np.ndarray:
        """(3,) chassis pose now (x m, y m, yaw rad), without noise."""
        pos, mat = self.data.xpos[self._chassis], self.data.xmat[self._chassis]
        return np.array([pos[0], pos[1], math.atan2(mat[3], mat[0])])

    def observe(self) -> Observation:
        """Sensor readings now (copies, the ultrasonic distances noisy)."""
        d, r = self.data, self._us_range
        noise = self._noise.step()
        dist = np.empty(2)
        for i, adr in enumerate(self._us_adr):  # compiled scalar reading: cheaper than small-array numpy
            raw = float(d.sensordata[adr])  # -1: no hit
            dist[i] = noisy_distance(raw if 0.0 <= raw <= r else math.inf, r, noise[i]) / self._unit
        return Observation(
            us_distance=dist,
            foot_contact=np.zeros(len(anatomy.LEGS)),
            joint_angles=np.zeros(anatomy.N_ACTUATORS),
            pose=self.pose(),
            time=d.time,
        )

    def apply(self, steering: np.ndarray) -> None:
        """Set the wheel speeds from the steering pair (O1, O2), shape (2,), each clipped to [-1, 1].

        Right wheel target -O1·omega_max, left -O2·omega_max (rad/s, + rolls forward).

        Raises:
            ValueError: if ``steering`` is not two finite numbers.
        """
        s = np.asarray(steering, dtype=float)
        if s.shape != (2,) or not (math.isfinite(s[0]) and math.isfinite(s[1])):
            raise ValueError(f"steering must be two finite numbers (O1, O2), got {steering!r}")
        o1, o2 = min(1.0, max(-1.0, float(s[0]))), min(1.0, max(-1.0, float(s[1])))
        ctrl = self.data.ctrl
        ctrl[self._right] = -o1 * self._omega_max
        ctrl[self._left] = -o2 * self._omega_max

    def advance(self) -> None:
        """One control step of physics (``n_substeps`` physics steps)."""
        mujoco.mj_step(self.model, self.data, nstep=self.n_substeps)

    def up_z(self) -> float:
        """z component of the chassis's up vector (1 = upright)."""
        return float(self.data.xmat[self._chassis, 8])

    def true_joint_angles(self) -> np.ndarray:
        """(19,) zeros: the robot has none of AMOSII's joints."""
        return np.zeros(anatomy.N_ACTUATORS)

    def warnings(self) -> dict[str, int]:
        """MuJoCo warnings raised so far, by name (empty when none)."""
        return mujoco_warnings(self.data)
