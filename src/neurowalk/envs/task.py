"""What the exploration environments share: the Table 2 environment per reset, the coverage reward, ``info``.

A body-specific environment supplies :meth:`ExploreTask._start` (build the body in the arena, return its first
readings and pose) and :meth:`ExploreTask._advance` (one control step with an action, return the readings and the
pose after it); this base checks settings and actions and keeps the coverage, the stuck flag and the rendering.
"""

from __future__ import annotations

import abc
import math
from typing import Any, ClassVar

import gymnasium as gym
import numpy as np

from neurowalk.arenas import ArenaSpec, make_arena
from neurowalk.compiled import jit
from neurowalk.plotting import draw_arena, pyplot, styled
from neurowalk.sim.table2 import BOXES, EXTENT, SIZE, table2_arena, table2_option, table2_seed

CELL = 0.25  # m, side of a coverage cell
STUCK_WINDOW, STUCK_RADIUS = 3000, 0.5  # Table 2's rule: steps, m
US_RANGE = 0.4  # m, the ultrasonic range: what "no echo" is reported as


class ExploreTask(gym.Env[np.ndarray, np.ndarray], abc.ABC):
    """Base of the exploration environments (see :mod:`neurowalk.envs.explore` for the task)."""

    metadata: ClassVar[dict[str, Any]] = {"render_modes": ["rgb_array", "human"], "render_fps": 10}

    def __init__(
        self,
        arena: str | None,
        arena_opts: dict[str, Any] | None,
        max_steps: int,
        noise: float,
        render_mode: str | None,
    ) -> None:
        if isinstance(max_steps, bool) or not isinstance(max_steps, int | np.integer) or max_steps < 1:
            raise ValueError(f"max_steps must be a whole number >= 1, got {max_steps!r}")
        if isinstance(noise, bool) or not isinstance(noise, int | float) or not 0 <= noise <= 1:
            raise ValueError(f"noise must be a number in [0, 1], got {noise!r}")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"unknown render_mode {render_mode!r}; expected one of {self.metadata['render_modes']}")
        if arena is None and arena_opts:
            raise ValueError("arena_opts go with arena=NAME (the random Table 2 environments take none)")
        if arena is not None:
            make_arena(arena, rng=np.random.default_rng(0), **(arena_opts or {}))  # raises on a bad name or option
        self.arena_name, self.arena_opts = arena, dict(arena_opts or {})
        self.max_steps, self.noise, self.render_mode = int(max_steps), float(noise), render_mode
        self.us_range = US_RANGE
        self.observation_space = gym.spaces.Box(0.0, US_RANGE, shape=(2,), dtype=np.float64)
        self.arena: ArenaSpec | None = None
        self.k = 0
        self.pose = np.zeros(3)
        self.contacts = 0
        self._figure: Any = None

    # -- what a body supplies -------------------------------------------------------------------------------------
    @abc.abstractmethod
    def _start(self, arena: ArenaSpec, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
        """Put the body at the arena's start; (first readings (2,) m, pose (3,))."""

    @abc.abstractmethod
    def _advance(self, action: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """One control step with a checked ``action``; (readings (2,) m, pose (3,) after it)."""

    # -- Gymnasium -------------------------------------------------------------------------------------------------
    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """A new episode: a new environment (unless fixed) and the robot at its start, drawn from ``seed``;
        ``options={"table2": i}`` (``"table2_seed": s``, default 0): Table 2's environment i instead, its arena and
        start pose as the figure runs it (:func:`neurowalk.sim.table2.table2_arena`)."""
        super().reset(seed=seed)
        rng = self.np_random
        table = table2_option(options)
        if table is not None:
            self.arena = table2_arena(table[0], table2_seed(options or {}))
        elif self.arena_name is None:
            n_boxes = int(rng.integers(BOXES[0], BOXES[1] + 1))
            self.arena = make_arena("random", rng=rng, n_boxes=n_boxes, extent=EXTENT, size=SIZE)
        else:
            self.arena = make_arena(self.arena_name, rng=rng, **self.arena_opts)
        seen, self.pose = self._start(self.arena, rng)
        self.k, self.contacts = 0, 0
        self._poses = np.full((self.max_steps + 1, 3), np.nan)
        self._poses[0] = self.pose
        bounds = self.arena.bounds
        self._origin = np.array([bounds[0], bounds[2]]) if bounds else np.zeros(2)
        self._free = {self._cell(c) for c in self.arena.free_cells(CELL)} if bounds else set()
        self._visited = {self._cell(self.pose)}
        self._covered = len(self._visited & self._free)  # visited free cells, kept up to date by step()
        return self._observation(seen), self._info()

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        """One control step (1 / control_hz s: 0.1 s at the default 10 Hz) with ``action``."""
        if self.arena is None:
            raise RuntimeError("call reset() before step()")
        a = np.asarray(action, dtype=float)
        space = self.action_space
        if a.shape != space.shape:
            raise ValueError(f"action must have shape {space.shape}, got shape {a.shape}: {action!r}")
        if not np.all(np.isfinite(a)) or np.any(a < space.low) or np.any(a > space.high):  # type: ignore[attr-defined]
            raise ValueError(f"action must be finite numbers within the action space's bounds, got {a.tolist()!r}")
        seen, self.pose = self._advance(a)
        self.k += 1
        self._poses[self.k] = self.pose
        cell = self._cell(self.pose)
        reward = 0.0
        if cell not in self._visited:
            reward = CELL * CELL
            self._visited.add(cell)
            self._covered += cell in self._free
        if self.render_mode == "human":
            self.render()
        return self._observation(seen), reward, False, self.k >= self.max_steps, self._info()

    @styled
    def render(self) -> np.ndarray | None:
        """``rgb_array``: (height, width, 3) uint8 overhead picture of the arena and path; ``human``: in a window."""
        if self.render_mode is None or self.arena is None:
            return None
        plt = pyplot()
        if self._figure is None:
            self._figure = plt.figure(figsize=(4, 4), dpi=80)
        fig = self._figure
        fig.clf()
        ax = fig.add_subplot(1, 1, 1)
        draw_arena(ax, self.arena, self._poses[: self.k + 1])
        ax.set_title(f"step {self.k}, coverage {self._info()['coverage']:.0%}")
        fig.canvas.draw()
        if self.render_mode == "human":
            plt.pause(1.0 / self.metadata["render_fps"])
            return None
        return np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()

    def close(self) -> None:
        if self._figure is not None:
            pyplot().close(self._figure)
            self._figure = None

    # -- shared bookkeeping ----------------------------------------------------------------------------------------
    def _observation(self, seen: np.ndarray) -> np.ndarray:
        return np.where(np.isfinite(seen), np.minimum(seen, US_RANGE), US_RANGE)

    def _cell(self, pose: np.ndarray) -> tuple[int, int]:
        i, j = np.floor((np.asarray(pose[:2]) - self._origin) / CELL).astype(int)
        return int(i), int(j)

    def _info(self) -> dict[str, Any]:
        k = self.k
        stuck = k + 1 >= STUCK_WINDOW and within_disc(self._poses[k + 1 - STUCK_WINDOW : k + 1], STUCK_RADIUS)
        coverage = self._covered / len(self._free) if self._free else math.nan
        return {"pose": self.pose.copy(), "coverage": coverage, "stuck": bool(stuck), "contacts": self.contacts}


@jit
def within_disc(pose: np.ndarray, radius: float) -> bool:
    """Whether every position of ``pose`` (T, >= 2) lies within ``radius`` (m) of their mean (as
    :func:`neurowalk.metrics.trapped`, compiled: the stuck flag is tested at every step)."""
    n = pose.shape[0]
    mx, my = 0.0, 0.0
    for i in range(n):
        mx += pose[i, 0]
        my += pose[i, 1]
    mx, my = mx / n, my / n
    r2 = radius * radius
    for i in range(n):  # noqa: SIM110 (a loop numba compiles; all() over a generator it does not)
        if (pose[i, 0] - mx) ** 2 + (pose[i, 1] - my) ** 2 > r2:
            return False
    return True
