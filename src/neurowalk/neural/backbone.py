"""Backbone joint control for climbing, and the climbable/non-climbable decision.

The original network (reference/original_code_facts.md §6, Goldschmidt et al. 2014) leans the front
segment up about 25 s after the ultrasonic sensors see something, and front-foot contact brings it
down. Here the trigger is the obstacle-height sensor (the stand-in for the paper's laser range
finder), which also decides what is climbable:

* **climbable step ahead**: ``min_height < h_ahead <= climbable`` (m). Higher obstacles are walls:
  the sensory network avoids them as before. While a climbable step is ahead (and no wall), the
  ultrasonic inputs are masked (read as "no echo"), so that the robot walks onto the step instead
  of turning away from it.
* **lean up** (``+lean_per_m · h`` rad, at most ``max_lean``) while a climbable step is ahead and the
  front tip is not yet over it: the front segment and front legs rise over the edge.
* **lean down** (``down`` rad) once the front tip is over the step (terrain under it higher than
  ``min_height``) and the trunk centre is not: with the front legs on the step this lifts the rear
  segment's front end over the edge.
* **level** (0) otherwise, in particular once the trunk centre is over the step.
* **press down** (``down`` rad for ``press_steps``) after ``stall_steps`` of leaning up without the
  front getting over: the front is caught at the edge (3 of 10 seeds at 0.08 m without it); pressing
  down pulls it over, then the lean up resumes if needed.

The command is low-pass filtered (rate ``smoothing`` per control step), like the original's output
neuron. Heights are relative to the lowest sole, so once all feet are up the step reads flat.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

PHASES: tuple[str, ...] = ("level", "up", "down")


@dataclass(frozen=True, kw_only=True)
class BackboneParams:
    """Parameters of the backbone joint control (heights in m, angles in rad)."""

    min_height: float = 0.02  # lower terrain changes are ignored (walked over)
    climbable: float = 0.12  # highest obstacle treated as a step; higher ones are walls
    lean_per_m: float = 7.5  # rad of upward lean per metre of step height (0.06 m -> 26°)
    max_lean: float = math.radians(45.0)  # the joint's limit
    down: float = math.radians(-30.0)  # lean while the front is over the step and the centre is not
    smoothing: float = 0.2  # low-pass rate of the command per control step
    stall_steps: int = 150  # control steps of leaning up without the front getting over before a press-down
    press_steps: int = 50  # control steps of a press-down (lean down) after a stall

    def __post_init__(self) -> None:
        if not 0.0 <= self.min_height < self.climbable:
            raise ValueError(
                f"BackboneParams needs 0 <= min_height < climbable, got {self.min_height}, {self.climbable}"
            )
        if not 0.0 < self.smoothing <= 1.0:
            raise ValueError(f"BackboneParams.smoothing must be in (0, 1], got {self.smoothing!r}")


class BackboneControl:
    """Backbone joint command (rad, + leans the front segment up) from the terrain readings.

    Attributes (after the last :meth:`step`): ``phase`` (index into :data:`PHASES`), ``command``
    (rad), ``climbing`` (the ultrasonic inputs are masked).
    """

    def __init__(self, params: BackboneParams | None = None) -> None:
        self.params = params or BackboneParams()
        self.reset()

    def reset(self) -> None:
        """Level, not climbing."""
        self.command = 0.0
        self.phase = 0
        self.climbing = False
        self.up_for = 0  # control steps since the front last was over a step or level ground ahead
        self.pressing = 0  # control steps left of a press-down

    def climbable_ahead(self, height_ahead: float) -> bool:
        """Whether an obstacle of ``height_ahead`` m is a step to climb (not a wall, not flat)."""
        p = self.params
        return p.min_height < height_ahead <= p.climbable

    def step(self, height_ahead: float, ground: np.ndarray) -> float:
        """One control step: ``height_ahead`` (m), ``ground`` (2,) heights under front tip and centre (m)."""
        p = self.params
        front_over = ground[0] > p.min_height
        centre_over = ground[1] > p.min_height
        ahead = self.climbable_ahead(height_ahead)
        if front_over and not centre_over:
            self.phase, target = 2, p.down
        elif self.pressing > 0:
            self.pressing -= 1
            self.phase, target = 2, p.down
        elif ahead and not front_over:
            self.phase, target = 1, min(p.max_lean, p.lean_per_m * height_ahead)
        else:
            self.phase, target = 0, 0.0
        # Leaning up for long without the front getting over: the front is stuck at the edge; press down.
        self.up_for = self.up_for + 1 if ahead and not front_over else 0
        if self.up_for > p.stall_steps:
            self.pressing, self.up_for = p.press_steps, 0
        self.climbing = ahead
        self.command += p.smoothing * (target - self.command)
        return self.command
