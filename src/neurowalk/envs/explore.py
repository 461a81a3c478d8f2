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

import math
from typing import Any, ClassVar

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from neurowalk import metrics
from neurowalk.arenas import ArenaSpec, make_arena
from neurowalk.body.surrogate import Surrogate, Walker, load_calibration

CELL = 0.25  # m, side of a coverage cell
STUCK_WINDOW, STUCK_RADIUS = 3000, 0.5  # Table 2's rule: steps, m
BOXES, EXTENT, SIZE = (2, 20), 9.0, 1.0  # Table 2's environments (neurowalk.experiments.random_envs)


class ExploreEnv(gym.Env[np.ndarray, np.ndarray]):
    """The planar surrogate in a random Table 2 environment (see the module text for spaces, reward, info).

    Args:
        arena: a fixed arena by name (see ``neurowalk arenas``) instead of a random Table 2 environment per reset.
        arena_opts: its options.
        max_steps: control steps per episode (10 Hz).
        noise: strength of the coloured ultrasonic noise (0 to 1; the runs' default 0.02).
        render_mode: None, ``"rgb_array"`` or ``"human"``.
    """

    metadata: ClassVar[dict[str, Any]] = {"render_modes": ["rgb_array", "human"], "render_fps": 10}

    def __init__(self, arena: str | None = None, arena_opts: dict[str, Any] | None = None, max_steps: int = 2000,
                 noise: float = 0.02, render_mode: str | None = None) -> None:  # fmt: skip
        if isinstance(max_steps, bool) or not isinstance(max_steps, int | np.integer) or max_steps < 1:
            raise ValueError(f"max_steps must be a whole number >= 1, got {max_steps!r}")
        if isinstance(noise, bool) or not isinstance(noise, int | float) or not 0 <= noise <= 1:
            raise ValueError(f"noise must be a number in [0, 1], got {noise!r}")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"unknown render_mode {render_mode!r}; expected rgb_array or human")
        if arena is None and arena_opts:
            raise ValueError("arena_opts go with arena=NAME (the random Table 2 environments take none)")
        if arena is not None:
            make_arena(arena, rng=np.random.default_rng(0), **(arena_opts or {}))  # raises on a bad name or option
        self.arena_name, self.arena_opts = arena, dict(arena_opts or {})
        self.max_steps, self.noise, self.render_mode = int(max_steps), float(noise), render_mode
        self.us_range = load_calibration().us_range
        self.observation_space = spaces.Box(0.0, self.us_range, shape=(2,), dtype=np.float64)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float64)
        self.arena: ArenaSpec | None = None
        self._walker: Walker | None = None
        self._figure: Any = None

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[np.ndarray, dict[str, Any]]:  # fmt: skip
        """A new episode: a new environment (unless fixed) and the robot at its start, drawn from ``seed``."""
        super().reset(seed=seed)
        rng = self.np_random
        if self.arena_name is None:
            n_boxes = int(rng.integers(BOXES[0], BOXES[1] + 1))
            self.arena = make_arena("random", rng=rng, n_boxes=n_boxes, extent=EXTENT, size=SIZE)
        else:
            self.arena = make_arena(self.arena_name, rng=rng, **self.arena_opts)
        self._walker = Walker(Surrogate(self.arena, noise=self.noise), rng)
        self._poses = np.full((self.max_steps + 1, 3), np.nan)
        self._poses[0] = self._walker.pose
        self._origin = np.array([self.arena.bounds[0], self.arena.bounds[2]]) if self.arena.bounds else np.zeros(2)
        self._free = self._cells(self.arena.free_cells(CELL)) if self.arena.bounds else set()
        self._visited = {self._cell(self._walker.pose)}
        return self._observe(), self._info()

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        """One control step (0.1 s) with steering ``action`` (O1, O2) in [-1, 1]."""
        if self._walker is None:
            raise RuntimeError("call reset() before step()")
        a = np.asarray(action, dtype=float)
        if a.shape != (2,):
            raise ValueError(f"action must have shape (2,) (O1, O2), got shape {a.shape}: {action!r}")
        if not np.all(np.isfinite(a)) or np.any(np.abs(a) > 1.0):
            raise ValueError(f"action must be two finite numbers in [-1, 1], got {a.tolist()!r}")
        pose = self._walker.act(a[0], a[1])
        k = self._walker.k
        self._poses[k] = pose
        cell = self._cell(pose)
        reward = 0.0 if cell in self._visited else CELL * CELL
        self._visited.add(cell)
        obs = self._observe()
        if self.render_mode == "human":
            self.render()
        return obs, reward, False, k >= self.max_steps, self._info()

    def render(self) -> np.ndarray | None:
        """``rgb_array``: (height, width, 3) uint8 overhead picture; ``human``: the same in a window."""
        if self.render_mode is None or self.arena is None or self._walker is None:
            return None
        from neurowalk.plotting import draw_arena, pyplot

        plt = pyplot()
        if self._figure is None:
            self._figure = plt.figure(figsize=(4, 4), dpi=80)
        fig = self._figure
        fig.clf()
        ax = fig.add_subplot(1, 1, 1)
        draw_arena(ax, self.arena, self._poses[: self._walker.k + 1])
        ax.set_title(f"step {self._walker.k}, coverage {self._info()['coverage']:.0%}")
        fig.canvas.draw()
        if self.render_mode == "human":
            plt.pause(1.0 / self.metadata["render_fps"])
            return None
        return np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()

    def close(self) -> None:
        if self._figure is not None:
            from neurowalk.plotting import pyplot

            pyplot().close(self._figure)
            self._figure = None

    def _observe(self) -> np.ndarray:
        seen = self._walker.sense()  # type: ignore[union-attr]
        return np.where(np.isfinite(seen), np.minimum(seen, self.us_range), self.us_range)

    def _cell(self, pose: np.ndarray) -> tuple[int, int]:
        i, j = np.floor((pose[:2] - self._origin) / CELL).astype(int)
        return int(i), int(j)

    def _cells(self, centres: np.ndarray) -> set[tuple[int, int]]:
        return {self._cell(c) for c in centres}

    def _info(self) -> dict[str, Any]:
        w = self._walker
        assert w is not None
        k = w.k
        stuck = k + 1 >= STUCK_WINDOW and metrics.trapped(self._poses[k + 1 - STUCK_WINDOW : k + 1],
                                                           window=STUCK_WINDOW, radius=STUCK_RADIUS)  # fmt: skip
        coverage = len(self._visited & self._free) / len(self._free) if self._free else math.nan
        return {"pose": w.pose.copy(), "coverage": coverage, "stuck": bool(stuck), "contacts": w.contacts}
