"""What ``neurowalk calibrate`` measures and on which bodies: the steering grid, the run lengths, the step changes,
and the two subjects (:data:`SUBJECTS`), AMOSII (for the body ``surrogate``) and the wheeled robot
(``surrogate-wheeled``)."""

from __future__ import annotations

from dataclasses import dataclass

from neurowalk.body.wheeled import CHASSIS_BODY
from neurowalk.experiments.calibration.fit import LAG_DELAYS, LAG_TAUS

GRID: tuple[float, ...] = (-1.0, -0.5, -0.3, -0.2, -0.1, 0.0, 0.1, 0.2, 0.3, 0.5, 1.0)
HELD_OUT: tuple[float, ...] = (-0.75, -0.4, -0.15, -0.05, 0.05, 0.15, 0.4, 0.75)
WARMUP = 300  # control steps before measuring (the CPG post-processing settles within ~90)
WINDOW = 612  # control steps measured: 7 gait cycles of 87.5 steps
STEPS_AFTER = 300  # control steps recorded after a step change
FORWARD = (-1.0, -1.0)  # steering of free walking: no obstacle -> inputs -1 -> outputs -1
STEP_CHANGES: tuple[tuple[tuple[float, float], tuple[float, float]], ...] = (
    (FORWARD, (-1.0, 1.0)),  # forward -> turn
    (FORWARD, (1.0, -1.0)),  # forward -> the other turn
    ((-1.0, 1.0), (1.0, -1.0)),  # one turn -> the other
    ((1.0, -1.0), FORWARD),  # turn -> forward
    ((0.0, 0.0), FORWARD),  # stop -> forward
    (FORWARD, (1.0, 1.0)),  # forward -> backward
)
CONTROL_HZ = 10.0  # Hz, the control rate the calibration is measured at


@dataclass(frozen=True)
class Subject:
    """A physics body that ``neurowalk calibrate`` measures (at its default options), and how.

    Attributes:
        body: its registry name. surrogate: the planar body it calibrates (whose data file it writes).
        chassis: the MJCF body whose frame is the pose (the surrogate's footprint and rays are in that frame).
        gait: steered through the locomotion network, its trunk rocking with the gait (the sway is fitted); else
            the steering pair goes to ``apply`` directly and the stored sway is 0.
        box_circle_m: None: a box is a chain of circles as wide as the box along its x axis (AMOSII's narrow
            trunk boxes); a number: the box's outline in circles of at most that radius (m; a wide chassis).
        delays, taus: the lag fit's grid (control steps, s). startup_stride: control steps between the start-up
            candidates. how: the method in words (for the file's meta data).
    """

    body: str
    surrogate: str
    chassis: str
    gait: bool
    box_circle_m: float | None
    delays: tuple[int, ...]
    taus: tuple[float, ...]
    startup_stride: int
    how: str


DEFAULT_SUBJECT = "amosii"  # what `neurowalk calibrate` measures without --body: the paper's robot
NO_SWAY_PERIOD = float(WINDOW)  # control steps: the stored period of a body without a gait (its amplitude is 0)
SUBJECTS: dict[str, Subject] = {
    "amosii": Subject(
        "amosii",
        "surrogate",
        "trunk",
        True,
        None,
        LAG_DELAYS,
        LAG_TAUS,
        5,
        "AMOSII (MuJoCo, open arena, no noise) driven by constant steering through the locomotion network; "
        f"velocity = mean body-frame velocity over {WINDOW} control steps (7 gait cycles) after {WARMUP} steps; "
        f"lag = delay + first-order lag fitted to {len(STEP_CHANGES)} step changes of the steering "
        f"({STEPS_AFTER} steps each; mean error {{lag:.3f}} m); start-up fitted on a forward run from reset; "
        "footprint and rays from the MJCF in the standing pose; yaw sway = sqrt(2) x std of the detrended yaw over "
        "the same window, its period and phase fitted on the forward run.",
    ),
    "wheeled": Subject(
        "wheeled",
        "surrogate-wheeled",
        CHASSIS_BODY,
        False,
        0.04,
        tuple(range(9)),
        (0.0, 0.05, 0.1, 0.2, 0.3, 0.5, 1.0, 2.0),
        1,
        "the wheeled robot (MuJoCo, scale 1, open arena, no noise) driven by constant steering applied to its "
        f"wheels directly (no locomotion network); velocity = mean body-frame velocity over {WINDOW} control steps "
        f"after {WARMUP} steps; lag = delay + first-order lag fitted to {len(STEP_CHANGES)} step changes of the "
        f"steering ({STEPS_AFTER} steps each; mean error {{lag:.3f}} m); start-up fitted on a forward run from "
        "reset; footprint from the MJCF at rest (the chassis box's outline in circles of 4 cm, the wheels' in "
        "circles of their half width, the casters), rays from its US_L and US_R sites; no gait, so no yaw sway: "
        f"amplitude 0 (the largest measured, sqrt(2) x std of the detrended yaw, is in sway_measured_max_rad), "
        f"period {NO_SWAY_PERIOD:g} steps and phase 0 (unused).",
    ),
}


def subject(body: str) -> Subject:
    """The calibration subject of physics body ``body``; ValueError names a body that has none."""
    if body not in SUBJECTS:
        raise ValueError(f"cannot calibrate body {body!r}; expected one of {', '.join(SUBJECTS)}")
    return SUBJECTS[body]
