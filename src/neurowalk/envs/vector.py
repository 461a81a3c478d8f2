"""``neurowalk/Explore-v0`` vectorised: N surrogate copies stepped in one compiled call.

``gymnasium.make_vec("neurowalk/Explore-v0", num_envs=N, vectorization_mode="vector_entry_point")`` gives
:class:`ExploreVectorEnv`: the task, spaces and reward of :class:`~neurowalk.envs.explore.ExploreEnv` for each
copy, observations (N, 2), rewards, terminations and truncations (N,), and ``info`` with ``pose`` (N, 3),
``coverage`` (N,) and ``contacts`` (N,). Copy i's environment and sensor noise come from its own seed (``reset(seed=
s)`` gives copy i the seed s + i; later episodes draw theirs from the vector environment's generator), so a copy's
episode does not depend on the other copies. Its noise is drawn by a counter-based generator in the compiled step,
not by NumPy's, so a copy's readings differ from those of the single environment with the same seed (the same
statistics). Autoreset: next step (Gymnasium's default): the step after a copy's last one resets it and returns its
first observation, with reward 0. Table 2's ``stuck`` flag is in the single environment only.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numba
import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from neurowalk.arenas import ArenaSpec, make_arena
from neurowalk.body import surrogate_kernel as kern
from neurowalk.body.surrogate import NOISE_TAU, box_rows, load_calibration
from neurowalk.envs.explore import BOXES, CELL, EXTENT, SIZE, ExploreEnv
from neurowalk.envs.vector_kernel import free_mask, uniform, vector_step
from neurowalk.sim.table2 import table2_arena, table2_option, table2_seed

MAX_BOXES = 64  # obstacle rows per copy (Table 2: at most 20 boxes and 4 walls)


def copy_seeds(env: VectorEnv, seed: int | list[int] | None) -> list[int]:
    """The reset seed of each copy of ``env``: ``seed + i``, or ``seed[i]`` for a list, or fresh ones drawn from the
    environment's generator for None; seeds that generator (with the first copy's seed), from which later episodes
    draw theirs."""
    n = env.num_envs
    if isinstance(seed, list | tuple | np.ndarray):
        if len(seed) != n:
            raise ValueError(f"seed must be one int or {n} ints, got {len(seed)}")
        seeds = [int(s) for s in seed]
    else:
        seeds = None if seed is None else [int(seed) + i for i in range(n)]
    VectorEnv.reset(env, seed=None if seeds is None else seeds[0])
    if seeds is None:
        base = int(env.np_random.integers(2**62))
        seeds = [base + i for i in range(n)]
    return seeds


class ExploreVectorEnv(VectorEnv):
    """N copies of ``neurowalk/Explore-v0`` in one compiled step (see the module text).

    Args:
        num_envs: copies.
        arena, arena_opts, max_steps, noise: as :class:`~neurowalk.envs.explore.ExploreEnv` (a fixed arena must be
            bounded: coverage is counted on its grid).
    """

    metadata: ClassVar[dict[str, Any]] = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": []}

    def __init__(
        self,
        num_envs: int = 1,
        arena: str | None = None,
        arena_opts: dict[str, Any] | None = None,
        max_steps: int = 2000,
        noise: float = 0.02,
    ) -> None:
        if isinstance(num_envs, bool) or not isinstance(num_envs, int | np.integer) or num_envs < 1:
            raise ValueError(f"num_envs must be a whole number >= 1, got {num_envs!r}")
        single = ExploreEnv(arena=arena, arena_opts=arena_opts, max_steps=max_steps, noise=noise)  # checks them
        self.num_envs = int(num_envs)
        self.single_observation_space, self.single_action_space = single.observation_space, single.action_space
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.arena_name, self.arena_opts, self.max_steps, self.noise = arena, dict(arena_opts or {}), max_steps, noise
        cal = self.cal = load_calibration()
        n = self.num_envs
        self.motion = cal.motion()
        self.ks = np.zeros(n, dtype=np.int64)
        self.states = np.zeros((n, kern.RUN_STATE))
        self.rings = np.zeros((n, cal.delay_steps + 1, self.motion.shape[2]))
        self.boxes = np.zeros((n, MAX_BOXES, 6))
        self.nboxes = np.zeros(n, dtype=np.int64)
        self.keys = np.zeros(n, dtype=np.uint64)
        self.origin = np.zeros((n, 2))
        self.grid_cells = None  # (gx, gy), fixed by the first arena
        self.covered = np.zeros(n, dtype=np.int64)
        self.free_count = np.zeros(n, dtype=np.int64)
        self.obs = np.zeros((n, 2))
        self.reward = np.zeros(n)
        self.pose = np.zeros((n, 3))
        self.contacts = np.zeros(n, dtype=np.int64)
        self.done = np.zeros(n, dtype=bool)
        self.reach = kern.reach_of(cal.circles)
        self.omega = 2.0 * math.pi / cal.sway_period_steps
        self.gain = math.sqrt(NOISE_TAU) * noise  # the surrogate's coloured noise
        self.visited: np.ndarray | None = None
        self.free: np.ndarray | None = None
        self.scratch = np.zeros((numba.config.NUMBA_NUM_THREADS, self.motion.shape[2] + 4))

    def reset(
        self, *, seed: int | list[int] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Every copy anew: copy i from seed ``seed + i`` (or ``seed[i]``); None draws fresh seeds.
        ``options={"table2": i}``: copy k in Table 2's environment i + k (``[i0, i1, ...]``: one each), as
        :meth:`ExploreEnv.reset <neurowalk.envs.explore.ExploreEnv.reset>` takes it."""
        seeds = copy_seeds(self, seed)
        table = table2_option(options, self.num_envs)
        for i, s in enumerate(seeds):
            self._start(i, s, None if table is None else table2_arena(table[i], table2_seed(options or {})))
        self.done[:] = False
        return self.obs.copy(), self._info()

    def step(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        """One control step of every copy (those whose episode ended last step are reset instead)."""
        a = np.asarray(actions, dtype=float)
        if a.shape != (self.num_envs, 2):
            raise ValueError(f"actions must have shape ({self.num_envs}, 2), got {a.shape}")
        if not np.all(np.isfinite(a)) or np.any(np.abs(a) > 1.0):
            bad = a[~np.all(np.isfinite(a) & (np.abs(a) <= 1.0), axis=1)][0]
            raise ValueError(f"actions must be finite numbers in [-1, 1], got {bad.tolist()!r}")
        restart = np.flatnonzero(self.done)
        cal = self.cal
        vector_step(
            self.ks,
            self.states,
            self.rings,
            a,
            self.boxes,
            self.nboxes,
            self.keys,
            cal.circles,
            cal.rays,
            cal.us_range,
            cal.grid,
            self.motion,
            cal.alpha(),
            cal.startup_steps,
            1.0 / cal.control_hz,
            self.omega,
            cal.sway_phase,
            self.gain,
            NOISE_TAU,
            self.reach,
            self.origin,
            CELL,
            self.visited,
            self.free,
            self.covered,
            self.obs,
            self.reward,
            self.pose,
            self.contacts,
            self.scratch,
        )
        truncated = self.ks >= self.max_steps
        reward = self.reward.copy()
        for i in restart:  # next-step autoreset: this step starts their new episode
            self._start(int(i), int(self.np_random.integers(2**62)))
            reward[i], truncated[i] = 0.0, False
        self.done = truncated.copy()
        return self.obs.copy(), reward, np.zeros(self.num_envs, dtype=bool), truncated, self._info()

    def _start(self, i: int, seed: int, table: ArenaSpec | None = None) -> None:
        """Copy i at the start of a new episode drawn from ``seed`` (in arena ``table`` where given); its first
        observation into ``obs[i]``."""
        rng = np.random.default_rng(seed)
        if table is not None:
            arena = table
        elif self.arena_name is None:
            arena = make_arena(
                "random", rng=rng, n_boxes=int(rng.integers(BOXES[0], BOXES[1] + 1)), extent=EXTENT, size=SIZE
            )
        else:
            arena = make_arena(self.arena_name, rng=rng, **self.arena_opts)
        self._layout(i, arena)
        self.ks[i], self.contacts[i], self.covered[i] = 0, 0, 0
        self.states[i] = 0.0
        self.states[i, kern.X], self.states[i, kern.Y], self.states[i, kern.YAW] = arena.start
        self.rings[i] = 0.0
        self.keys[i] = np.uint64(seed % 2**64)
        self.pose[i] = arena.start
        cal = self.cal
        x0, y0 = self.origin[i]
        c = (math.floor((arena.start[0] - x0) / CELL), math.floor((arena.start[1] - y0) / CELL))
        self.visited[i, c[0], c[1]] = True  # type: ignore[index]
        self.covered[i] = int(self.free[i, c[0], c[1]])  # type: ignore[index]
        seen = np.zeros(2)
        noise = np.array([uniform(self.keys[i], 0), uniform(self.keys[i], 1)])
        kern.sense(
            0,
            self.states[i],
            self.boxes[i, : self.nboxes[i]],
            cal.rays,
            cal.us_range,
            self.omega,
            cal.sway_phase,
            noise,
            self.gain,
            NOISE_TAU,
            seen,
        )
        self.obs[i] = np.minimum(seen, cal.us_range)

    def _layout(self, i: int, arena: ArenaSpec) -> None:
        if arena.bounds is None:
            raise ValueError(f"the vector environment needs a bounded arena (coverage grid), got {arena.name!r}")
        rows = box_rows(arena)
        if len(rows) > MAX_BOXES:
            raise ValueError(f"arena {arena.name!r} has {len(rows)} obstacles; a vector copy holds {MAX_BOXES}")
        self.boxes[i, : len(rows)], self.nboxes[i] = rows, len(rows)
        x0, x1, y0, y1 = arena.bounds
        cells = (math.ceil((x1 - x0) / CELL), math.ceil((y1 - y0) / CELL))
        if self.visited is None:
            self.grid_cells = cells
            self.visited = np.zeros((self.num_envs, *cells), dtype=bool)
            self.free = np.zeros((self.num_envs, *cells), dtype=bool)
        g = self.visited.shape[1:]
        if cells[0] > g[0] or cells[1] > g[1]:
            raise ValueError(f"arena {arena.name!r} is larger than the first copy's ({cells} > {g} cells)")
        self.origin[i] = (x0, y0)
        self.visited[i] = False
        nx, ny = len(np.arange(x0 + CELL / 2, x1, CELL)), len(np.arange(y0 + CELL / 2, y1, CELL))  # as free_cells
        free_mask(self.boxes[i], len(rows), x0, y0, CELL, nx, ny, self.free[i])  # type: ignore[index]
        self.free_count[i] = int(self.free[i].sum())  # type: ignore[index]

    def _info(self) -> dict[str, Any]:
        return {
            "pose": self.pose.copy(),
            "coverage": self.covered / np.maximum(self.free_count, 1),
            "contacts": self.contacts.copy(),
        }
