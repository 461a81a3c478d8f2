"""``neurowalk/Explore-v0``: explore a random Table 2 environment on the planar surrogate, steered by an agent.

The task of the paper's Table 2 for a policy: the same body the networks are scored on, the same sensors, the
same environments (9 x 9 m walled field, 2-20 boxes of 1 x 1 m at random positions and rotations, the start
cleared; a new one per reset, drawn from the reset seed; ``arena=``/``arena_opts=`` fix one).

- Observation: (2,) float64, the two ultrasonic distances (left, right) in m at the current step, with the
  coloured sensor noise of the body; no echo (``inf``) is reported as the sensor range (0.4 m, the box's upper
  bound). What the networks see, before their input mapping.
- Action: (2,) float64 in [-1, 1], the steering pair (O1, O2) fed to the same calibrated locomotion mapping as the
  networks' outputs (-1, -1: straight ahead; O1 = 1: turn right; O2 = 1: turn left; both 1: backwards).
- Reward: the area newly covered, 0.0625 m^2 for each 0.25 m grid cell the trunk centre enters for the first time
  in the episode (the coverage of :func:`neurowalk.metrics.coverage`), else 0.
- Termination: never. Truncation: after ``max_steps`` control steps (default 2000, 200 s at 10 Hz).
- ``info``: ``pose`` (x m, y m, yaw rad), ``coverage`` (share of the arena's free 0.25 m cells visited),
  ``stuck`` (Table 2's rule on the last 3000 steps: within a 0.5 m disc; False before 3000 steps) and
  ``contacts`` (collision overlaps resolved so far).
- ``render_mode``: ``"rgb_array"`` (an overhead picture of the arena and the path) or ``"human"`` (the same in a
  window).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces

from neurowalk.arenas import ArenaSpec
from neurowalk.body.surrogate import Surrogate
from neurowalk.envs.task import BOXES, CELL, EXTENT, SIZE, ExploreTask

__all__ = ["BOXES", "CELL", "EXTENT", "SIZE", "ExploreEnv"]


class ExploreEnv(ExploreTask):
    """The planar surrogate in a random Table 2 environment (see the module text for spaces, reward, info).

    Args:
        arena: a fixed arena by name (see ``neurowalk arenas``) instead of a random Table 2 environment per reset.
        arena_opts: its options.
        max_steps: control steps per episode (10 Hz).
        noise: strength of the coloured ultrasonic noise (0 to 1; the runs' default 0.02).
        render_mode: None, ``"rgb_array"`` or ``"human"``.
    """

    def __init__(
        self,
        arena: str | None = None,
        arena_opts: dict[str, Any] | None = None,
        max_steps: int = 2000,
        noise: float = 0.02,
        render_mode: str | None = None,
    ) -> None:
        super().__init__(arena, arena_opts, max_steps, noise, render_mode)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float64)
        self._body: Surrogate | None = None

    def _start(self, arena: ArenaSpec, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
        body = self._body = Surrogate(arena, noise=self.noise)
        body.reset([rng])
        return body.sense()[0][0], body.pose[0].copy()

    def _advance(self, action: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        body = self._body
        assert body is not None
        body.apply(np.asarray(action, dtype=float)[None])
        body.advance()
        self.contacts = body.contacts
        return body.sense()[0][0], body.pose[0].copy()
