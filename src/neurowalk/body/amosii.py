"""AMOSII in MuJoCo as a body of the control loop: reset in an arena, observe, act, advance.

One control step = ``n_substeps`` physics steps, the physics step fitted to the control rate at build
(:func:`set_control_rate`).
Observations are copies; sensor noise (the original's coloured noise, on the ultrasonic signal,
joint angles and foot contacts) comes from the run's Generator. The ultrasonic noise acts on the
normalised signal US = max(0, 1 - d/range) as in the original, so a little of it reaches the
network even with nothing in range.
"""

from __future__ import annotations

import mujoco
import numpy as np

from neurowalk.arenas.spec import ArenaSpec
from neurowalk.body.amosii_mjcf import (
    BodyParams,
    amosii_xml,
    ground_heights,
    joint_qpos_indices,
    obstacle_height,
    trunk_pose,
    up_z,
)
from neurowalk.body.amosii_params import STAND_KEY
from neurowalk.body.amosii_sensors import sensed, sensor_layout
from neurowalk.body.common import place_at_start
from neurowalk.body.noise import ColoredNoise
from neurowalk.body.obstacle_slots import padded_world
from neurowalk.body.physics import mujoco_warnings, set_control_rate
from neurowalk.observation import Observation

_SENSORS_OFF = int(mujoco.mjtDisableBit.mjDSBL_SENSOR)


class AmosII:
    """The simulated robot in an arena.

    Args:
        arena: where it walks.
        params: body parameters.
        control_hz: control rate (Hz).
        noise: strength of the coloured sensor noise (0 switches it off).
        scan_obstacles: read the obstacle-height sensor every step (costs about 25 µs).
        pad_boxes: if given, build the arena's padded model with room for this many boxes (see
            :mod:`~neurowalk.body.obstacle_slots`): the model :mod:`neurowalk.sim.batch` runs for this
            arena, bit for bit the same physics. None: the plain model.
    """

    name = "amosii"
    action = "targets"  # what apply() takes (neurowalk.body.registry)

    def __init__(
        self,
        arena: ArenaSpec,
        params: BodyParams | None = None,
        *,
        control_hz: float = 10.0,
        noise: float = 0.02,
        scan_obstacles: bool = False,
        pad_boxes: int | None = None,
    ) -> None:
        self.arena = arena
        self.params = params or BodyParams()
        world = arena.to_mjcf() if pad_boxes is None else padded_world(arena, pad_boxes)
        self.model = mujoco.MjModel.from_xml_string(amosii_xml(self.params, world=world))
        self.data = mujoco.MjData(self.model)
        self.control_hz = control_hz
        self.n_substeps = set_control_rate(self.model, control_hz)
        self.scan_obstacles = scan_obstacles
        self._qidx = joint_qpos_indices(self.model)
        self._us_range = self.params.us_range
        self._noise = ColoredNoise(2 + len(self._qidx) + 6, strength=noise)
        self._key = self.model.key(STAND_KEY).id

    def reset(self, rng: np.random.Generator) -> None:
        """Standing pose at the arena's start pose, at rest; noise drawn from ``rng`` from now on."""
        m, d = self.model, self.data
        mujoco.mj_resetDataKeyframe(m, d, self._key)
        place_at_start(d.qpos, self.arena.start)
        mujoco.mj_forward(m, d)
        self._noise.reset(rng)

    @property
    def qidx(self) -> np.ndarray:
        """(19,) qpos addresses of the joints, actuator order."""
        return self._qidx

    @property
    def noise(self) -> ColoredNoise:
        """The sensor noise source: channels 0-1 ultrasonic, then the 19 joints, then the 6 foot contacts."""
        return self._noise

    def observe(self) -> Observation:
        """Sensor readings now (copies, noisy)."""
        m, d = self.model, self.data
        n = self._noise.step()
        dist, foot = sensed(sensor_layout(m), d.sensordata, self._us_range, n)
        nj = len(self._qidx)
        return Observation(
            us_distance=dist,
            foot_contact=foot,
            joint_angles=d.qpos[self._qidx] + n[2 : 2 + nj],
            obstacle_height=obstacle_height(m, d) if self.scan_obstacles else 0.0,
            ground_height=ground_heights(m, d) if self.scan_obstacles else np.zeros(2),
            pose=trunk_pose(m, d),
            time=d.time,
        )

    def apply(self, targets: np.ndarray) -> None:
        """Set the 19 joint targets (rad, actuator order)."""
        self.data.ctrl[:] = targets

    def advance(self) -> None:
        """One control step of physics: its sensors are computed in the last physics step only.

        ``mj_step`` computes the sensors of the state it starts from; those of the first ``n_substeps - 1`` steps
        are never read, so they are switched off there (the ultrasonic rays are most of a sensor update). The
        physics does not read sensors: the state and the sensor data after the control step are bit for bit those
        of ``n_substeps`` plain steps (tested).
        """
        m, n = self.model, self.n_substeps
        if n > 1:
            flags = m.opt.disableflags
            m.opt.disableflags = flags | _SENSORS_OFF
            try:
                mujoco.mj_step(m, self.data, nstep=n - 1)
            finally:
                m.opt.disableflags = flags
        mujoco.mj_step(m, self.data)

    def up_z(self) -> float:
        """z component of the trunk's up vector (1 = upright)."""
        return up_z(self.model, self.data)

    def true_joint_angles(self) -> np.ndarray:
        """(19,) joint angles without noise (rad, actuator order)."""
        return self.data.qpos[self._qidx].copy()

    def warnings(self) -> dict[str, int]:
        """MuJoCo warnings raised so far, by name (empty when none)."""
        return mujoco_warnings(self.data)
