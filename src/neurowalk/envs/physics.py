"""``neurowalk/ExplorePhysics-v0``: the exploration task of ``Explore-v0`` on the MuJoCo AMOSII.

The same environments, observation, reward, truncation and ``info`` as :mod:`neurowalk.envs.explore`, on the
19-joint physics robot (20 physics substeps per 0.1 s control step). With ``action="steering"`` (default) the action
is the steering pair (O1, O2) in [-1, 1]^2 and the locomotion network (CPG, PSN, VRNs, motor map: the networks'
own) turns it into the 19 joint targets; with ``action="joints"`` the action is the 19 joint targets themselves
(rad, actuator order :data:`neurowalk.anatomy.ACTUATORS`, within the actuators' control ranges), for low-level
learning. ``info["contacts"]`` counts the steps in which the trunk or a leg touched an obstacle.
``render_mode="rgb_array"`` renders MuJoCo's offscreen view from a camera that follows the trunk (640 x 480; needs
EGL or OSMesa, see :mod:`neurowalk.render`); ``"human"`` shows the overhead picture of the arena and path.
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np
from gymnasium import spaces

from neurowalk.arenas import ArenaSpec, make_arena
from neurowalk.body.amosii import AmosII
from neurowalk.body.amosii_params import TRUNK_BODY
from neurowalk.body.amosii_sensors import obstacle_contact, trunk_pose
from neurowalk.controller import FixedController
from neurowalk.envs.task import ExploreTask
from neurowalk.render import offscreen_gl

ACTIONS: tuple[str, ...] = ("steering", "joints")


class ExplorePhysicsEnv(ExploreTask):
    """AMOSII in MuJoCo in a random Table 2 environment (see the module text).

    Args:
        arena, arena_opts, max_steps, noise, render_mode: as :class:`~neurowalk.envs.explore.ExploreEnv`.
        action: ``"steering"`` (O1, O2) through the locomotion network, or ``"joints"`` (19 joint targets, rad).
        control_hz: control steps per second (10: the authors' simulator; 27: the real robot); the physics step is
            fitted to it (``body.physics.set_control_rate``), the networks keep their step semantics.
    """

    def __init__(
        self,
        arena: str | None = None,
        arena_opts: dict[str, Any] | None = None,
        max_steps: int = 2000,
        noise: float = 0.02,
        render_mode: str | None = None,
        action: str = "steering",
        control_hz: float = 10.0,
    ) -> None:
        if action not in ACTIONS:
            raise ValueError(f"unknown action {action!r}; expected one of {', '.join(ACTIONS)}")
        if isinstance(control_hz, bool) or not isinstance(control_hz, int | float) or not 0 < control_hz <= 1000:
            raise ValueError(f"control_hz must be a number in (0, 1000] Hz, got {control_hz!r}")
        self.control_hz = float(control_hz)
        super().__init__(arena, arena_opts, max_steps, noise, render_mode)
        self.action_kind = action
        if action == "steering":
            self.action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float64)
        else:
            model = AmosII(make_arena("open")).model
            lo, hi = model.actuator_ctrlrange[:, 0].copy(), model.actuator_ctrlrange[:, 1].copy()
            self.action_space = spaces.Box(lo, hi, dtype=np.float64)
        self.body: AmosII | None = None
        self._ctrl: FixedController | None = None
        self._renderer: Any = None

    def render(self) -> np.ndarray | None:
        """``rgb_array``: (480, 640, 3) uint8, MuJoCo's view of the robot; ``human``: the overhead picture."""
        if self.render_mode != "rgb_array" or self.body is None:
            return super().render()
        if self._renderer is None:
            offscreen_gl()  # no display: EGL, chosen where rendering starts (importing neurowalk chooses nothing)
            self._renderer = mujoco.Renderer(self.body.model, 480, 640)
            self._camera = mujoco.MjvCamera()
            self._camera.type = mujoco.mjtCamera.mjCAMERA_TRACKING
            self._camera.trackbodyid = self.body.model.body(TRUNK_BODY).id
            self._camera.distance, self._camera.elevation, self._camera.azimuth = 1.3, -30.0, 135.0
        self._renderer.update_scene(self.body.data, camera=self._camera)
        return self._renderer.render()

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
        super().close()

    def _start(self, arena: ArenaSpec, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
        if self._renderer is not None:  # a new model: a new renderer on the next render()
            self._renderer.close()
            self._renderer = None
        self.body = AmosII(arena, noise=self.noise, control_hz=self.control_hz)
        self.body.reset(rng)
        self._ctrl = FixedController((-1.0, -1.0))
        self._ctrl.reset()
        self._obs = self.body.observe()
        return self._obs.us_distance, trunk_pose(self.body.model, self.body.data)

    def _advance(self, action: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        body, ctrl = self.body, self._ctrl
        assert body is not None and ctrl is not None
        if self.action_kind == "steering":
            ctrl.steering[:] = action
            targets = ctrl.act(self._obs)
        else:
            targets = action
        body.apply(targets)
        body.advance()
        self.contacts += int(obstacle_contact(body.model, body.data))
        self._obs = body.observe()
        return self._obs.us_distance, trunk_pose(body.model, body.data)
