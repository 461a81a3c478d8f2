"""What a body reports to a controller at one control step.

Every body (AMOSII in MuJoCo, the planar surrogate) fills the same :class:`Observation`, so one
control loop and one controller serve them all. Arrays are copies, never views into simulator
memory.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from neurowalk import anatomy

NO_ECHO: float = np.inf
"""Ultrasonic reading when nothing is within range (m)."""


def _zeros(n: int) -> np.ndarray:
    return np.zeros(n)


@dataclass(frozen=True, kw_only=True, slots=True)
class Observation:
    """Sensor readings at one control step.

    Attributes:
        us_distance: (2,) ultrasonic distances in m, order (left, right) = (US_L, US_R); ``inf``
            where no echo comes back within the sensor's range.
        foot_contact: (6,) foot contact signal in [0, 1], order ``anatomy.LEGS``.
        joint_angles: (19,) measured joint angles in rad, actuator order, controller sign.
        obstacle_height: height in m of the obstacle ahead (0 when none is seen).
        ground_height: (2,) height in m of the terrain under the front tip and under the trunk
            centre, above the lowest sole (0 on flat ground).
        pose: (3,) trunk pose (x m, y m, yaw rad) in the world frame.
        time: simulated time in s.
    """

    us_distance: np.ndarray
    foot_contact: np.ndarray = field(default_factory=lambda: _zeros(len(anatomy.LEGS)))
    joint_angles: np.ndarray = field(default_factory=lambda: _zeros(anatomy.N_ACTUATORS))
    obstacle_height: float = 0.0
    ground_height: np.ndarray = field(default_factory=lambda: _zeros(2))
    pose: np.ndarray = field(default_factory=lambda: _zeros(3))
    time: float = 0.0
