"""``neurowalk/ExplorePhysics-v0`` vectorised: N MuJoCo AMOSII copies stepped together by ``mujoco.batch``.

``gymnasium.make_vec("neurowalk/ExplorePhysics-v0", num_envs=N, vectorization_mode="vector_entry_point")`` gives
:class:`ExplorePhysicsVectorEnv`: the task, spaces and reward of :class:`~neurowalk.envs.physics.ExplorePhysicsEnv`
for each copy, observations (N, 2), rewards, terminations and truncations (N,), and ``info`` with ``pose`` (N, 3),
``coverage`` (N,), ``stuck`` (N,) and ``contacts`` (N,). Each copy runs its arena's padded model
(:mod:`~neurowalk.body.obstacle_slots`) in one persistent ``mujoco.batch.Batch`` on ``nthread`` threads; the
locomotion networks of all copies take one compiled call (:class:`~neurowalk.sim.batch_control.BatchControllers`),
the sensing and coverage another (:mod:`~neurowalk.envs.vector_kernel`). Copy i's episode after ``reset(seed=s)``
is, bit for bit, that of the single environment reset with seed s + i (``seed[i]`` for a list) given the same
actions: the same arena and noise draws from the same Generator, the same physics, the same arithmetic. Later
episodes draw their seeds from the vector environment's generator. Autoreset: next step (Gymnasium's default): the
step after a copy's last one resets it and returns its first observation, with reward 0.

Obstacle contacts: the batch binds no contact list, so a compiled bounding-sphere test picks the copies that may
touch a box, and only their ``MjData`` is read (``Batch.get_data``) for
:func:`~neurowalk.body.amosii_sensors.obstacle_contact`.
"""

from __future__ import annotations

import math
import time
from typing import Any, ClassVar

import mujoco
import mujoco.batch
import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from neurowalk.arenas import ArenaSpec, make_arena
from neurowalk.body.amosii import AmosII
from neurowalk.body.amosii_sensors import obstacle_contact, sensor_layout, trunk_poses
from neurowalk.body.amosii_worlds import AmosIIWorlds
from neurowalk.controller import FixedController
from neurowalk.envs.physics import ExplorePhysicsEnv
from neurowalk.envs.task import BOXES, CELL, EXTENT, SIZE, STUCK_RADIUS, STUCK_WINDOW, US_RANGE
from neurowalk.envs.vector import copy_seeds
from neurowalk.envs.vector_kernel import count_cells, first_bad_row, near_obstacles, reported
from neurowalk.sim.batch import BatchPhysics
from neurowalk.sim.batch_control import BatchControllers
from neurowalk.sim.table2 import table2_arena, table2_option, table2_seed


class _Copies(BatchPhysics, AmosIIWorlds):
    """The copies as AMOSII's worlds over the environment's persistent batch: AMOSII's own sensing and sensor noise
    (:class:`~neurowalk.body.amosii_worlds.AmosIIWorlds`), the batch's physics
    (:class:`~neurowalk.sim.batch.BatchPhysics`); the environment resets a copy when its episode ends."""

    def __init__(self, batch: mujoco.batch.Batch, proto: AmosII, n: int, noise: float) -> None:
        super().__init__([proto.arena] * n, [noise] * n, proto.model, proto.params, proto.n_substeps)
        self.bind_batch(batch)


class ExplorePhysicsVectorEnv(VectorEnv):
    """N copies of ``neurowalk/ExplorePhysics-v0`` in one physics batch (see the module text).

    Args:
        num_envs: copies.
        arena, arena_opts, max_steps, noise, action: as :class:`~neurowalk.envs.physics.ExplorePhysicsEnv` (the
            cells of an unbounded arena are counted in Python sets, per copy and step: slower).
        nthread: physics threads (the calling thread is one of them).
        control_hz: control steps per second, as :class:`~neurowalk.envs.physics.ExplorePhysicsEnv`'s.

    Each copy keeps its own model and ``MjData`` (a persistent batch): about 4 MB of memory per copy.

    Attributes:
        physics_s: seconds spent so far in ``Batch.step`` (the rest of ``step`` is sensing and bookkeeping).
    """

    metadata: ClassVar[dict[str, Any]] = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": []}

    def __init__(
        self,
        num_envs: int = 1,
        arena: str | None = None,
        arena_opts: dict[str, Any] | None = None,
        max_steps: int = 2000,
        noise: float = 0.02,
        action: str = "steering",
        nthread: int = 2,
        control_hz: float = 10.0,
    ) -> None:
        for name, value in (("num_envs", num_envs), ("nthread", nthread)):
            if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
                raise ValueError(f"{name} must be a whole number >= 1, got {value!r}")
        single = ExplorePhysicsEnv(
            arena=arena, arena_opts=arena_opts, max_steps=max_steps, noise=noise, action=action, control_hz=control_hz
        )
        self.control_hz = single.control_hz
        n = self.num_envs = int(num_envs)
        self.single_observation_space, self.single_action_space = single.observation_space, single.action_space
        self.observation_space = batch_space(self.single_observation_space, n)
        self.action_space = batch_space(self.single_action_space, n)
        self._low, self._high = self.single_action_space.low, self.single_action_space.high  # type: ignore[attr-defined]
        self.arena_name, self.arena_opts, self.action_kind = arena, dict(arena_opts or {}), action
        self.max_steps, self.noise = int(max_steps), float(noise)
        # room for the most boxes of any arena (Table 2: 20 boxes and the 4 walls, which ArenaSpec.boxes holds too)
        widest = self._arena(np.random.default_rng(0), n_boxes=BOXES[1])
        self.slots = len(widest.boxes)
        proto = AmosII(widest, noise=self.noise, pad_boxes=self.slots, control_hz=self.control_hz)
        self.models: list[mujoco.MjModel] = [proto.model] * n
        self.arenas: list[ArenaSpec | None] = [None] * n
        self.batch = mujoco.batch.Batch(proto.model, n, int(nthread), True)  # persistent: contacts via get_data
        self.copies = _Copies(self.batch, proto, n, self.noise)  # AMOSII senses itself in every copy
        self.n_substeps = proto.n_substeps
        self.physics_s = 0.0
        lay, self._trunk = self.copies.layout, self.copies.trunk
        self._qpos, self._ctrl = self.copies.qpos, self.copies.ctrl
        self._xpos, self._xmat, self._geom_xpos = self.copies.xpos, self.copies.xmat, self.batch.bind("geom_xpos")
        self._data = mujoco.MjData(proto.model)  # one copy's MjData, read when it may touch an obstacle
        self.controllers = BatchControllers([FixedController((-1.0, -1.0)) for _ in range(n)])
        self.controllers.reset([None] * n)
        self._dist = np.zeros((n, 2))  # what the fixed controllers are shown (they read no sensors)
        n_robot, n_obst = int(lay.robot_geom.sum()), int(lay.obstacle_geom.sum())  # the same in every padded model
        self._robot, self._robot_r = np.zeros((n, n_robot), dtype=np.int64), np.zeros((n, n_robot))
        self._obst = np.zeros((n, n_obst), dtype=np.int64)
        # the obstacles as boxes: centres (m), rotations, half sizes (m), growth (m) (see near_obstacles)
        self._box_c, self._box_r, self._box_h = (np.zeros((n, n_obst, d)) for d in (3, 9, 3))
        self._box_g = np.zeros((n, n_obst))
        self.ks, self.contacts, self.covered = (np.zeros(n, dtype=np.int64) for _ in range(3))
        self.free_count = np.zeros(n, dtype=np.int64)
        self.obs, self.reward, self.pose = np.zeros((n, 2)), np.zeros(n), np.zeros((n, 3))
        self.origin = np.zeros((n, 2))  # m, corner of each copy's coverage grid
        self.done, self.stuck, self._outside, self._near = (np.zeros(n, dtype=bool) for _ in range(4))
        self._all = (np.zeros(0, dtype=np.int64), np.arange(n))  # (restarting, live) when none restarts
        self.visited, self.free = np.zeros((n, 0, 0), dtype=bool), np.zeros((n, 0, 0), dtype=bool)
        self._extra: list[set[tuple[int, int]]] = [set() for _ in range(n)]  # visited cells off the grid
        self._ring = np.zeros((n, STUCK_WINDOW if self.max_steps + 1 >= STUCK_WINDOW else 0, 2))

    def reset(
        self, *, seed: int | list[int] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Every copy anew: copy i from seed ``seed + i`` (or ``seed[i]``); None draws fresh seeds.
        ``options={"table2": i}``: copy k in Table 2's environment i + k (``[i0, i1, ...]``: one each), as
        :meth:`ExplorePhysicsEnv.reset <neurowalk.envs.physics.ExplorePhysicsEnv.reset>` takes it."""
        seeds = copy_seeds(self, seed)
        table = table2_option(options, self.num_envs)
        arenas = None if table is None else [table2_arena(t, table2_seed(options or {})) for t in table]
        self._start(np.arange(self.num_envs), seeds, arenas)
        self._sense()
        self.done[:] = False
        return self.obs.copy(), self._info()

    def step(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        """One control step (0.1 s) of every copy (those whose episode ended last step are reset instead)."""
        if self.arenas[0] is None:
            raise RuntimeError("call reset() before step()")
        a = np.asarray(actions, dtype=float)
        shape = (self.num_envs, *self._low.shape)
        if a.shape != shape:
            raise ValueError(f"actions must have shape {shape}, got {a.shape}")
        i = first_bad_row(a, self._low, self._high)
        if i >= 0:
            raise ValueError(
                f"actions must be finite numbers within the action space's bounds, got {a[i].tolist()!r} (copy {i})"
            )
        if self.action_kind == "steering":
            self.controllers.outputs[:] = a  # the fixed copies' steering
            self._ctrl[:] = self.controllers.step(self._dist)
        else:
            self._ctrl[:] = a
        t0 = time.perf_counter()
        self.batch.step(nstep=self.n_substeps)  # every copy: those restarting are reset below
        self.physics_s += time.perf_counter() - t0
        restart, live = (np.flatnonzero(self.done), np.flatnonzero(~self.done)) if self.done.any() else self._all
        if restart.size:  # next-step autoreset: this step starts their new episode
            self._start(restart, [int(self.np_random.integers(2**62)) for _ in restart])
        self._sense()
        off = count_cells(
            live,
            self.pose,
            self.origin,
            CELL,
            self.visited,
            self.free,
            self.covered,
            self.ks,
            self.reward,
            self._outside,
            self._ring,
            STUCK_RADIUS,
            self.stuck,
        )
        near = near_obstacles(
            live,
            self._geom_xpos,
            self._robot,
            self._robot_r,
            self._box_c,
            self._box_r,
            self._box_h,
            self._box_g,
            self._near,
        )
        for i in live[self._near[live]] if near else ():  # only the copies within touching distance of a box
            self.contacts[i] += obstacle_contact(self.models[i], self.batch.get_data(int(i), self._data))
        for i in live[self._outside[live]] if off else ():  # off the coverage grid (an unbounded arena): a set
            self._visit(int(i))
        truncated = self.ks >= self.max_steps  # (0 steps taken by the copies just started)
        reward = self.reward.copy()
        if restart.size:
            reward[restart] = 0.0
        self.done = truncated
        return self.obs.copy(), reward, np.zeros(self.num_envs, dtype=bool), truncated.copy(), self._info()

    # -- internals ---------------------------------------------------------------------------------------------
    def _arena(self, rng: np.random.Generator, n_boxes: int | None = None) -> ArenaSpec:
        """The episode's arena drawn from ``rng``, as ExploreTask.reset draws it (``n_boxes``: force the count)."""
        if self.arena_name is not None:
            return make_arena(self.arena_name, rng=rng, **self.arena_opts)
        n = int(rng.integers(BOXES[0], BOXES[1] + 1)) if n_boxes is None else n_boxes
        return make_arena("random", rng=rng, n_boxes=n, extent=EXTENT, size=SIZE)

    def _start(self, ids: np.ndarray, seeds: list[int], arenas: list[ArenaSpec] | None = None) -> None:
        """Copies ``ids`` at the start of new episodes drawn from ``seeds`` (in ``arenas`` where given, one per copy):
        their physics at the start pose, their sensor noise from the episode's Generator, their poses; the next
        :meth:`_sense` gives their first observations."""
        rngs = []
        for k, (i, seed) in enumerate(zip(ids, seeds, strict=True)):
            rng = np.random.default_rng(seed)  # = gymnasium.utils.seeding.np_random(seed), as the single env's
            arena = self._arena(rng) if arenas is None else arenas[k]
            if len(arena.boxes) > self.slots:
                raise ValueError(f"arena {arena.name!r} has {len(arena.boxes)} boxes; the models hold {self.slots}")
            model = AmosII(arena, noise=self.noise, pad_boxes=self.slots, control_hz=self.control_hz).model
            self.models[i], self.arenas[i] = model, arena
            rngs.append(rng)  # the body's noise from now on
            lay = sensor_layout(model)
            robot, obst = np.flatnonzero(lay.robot_geom), np.flatnonzero(lay.obstacle_geom)
            self._robot[i], self._obst[i] = robot, obst
            self._robot_r[i] = model.geom_rbound[robot] + model.geom_margin[robot]
            box = model.geom_type[obst] == mujoco.mjtGeom.mjGEOM_BOX
            self._box_h[i] = np.where(box[:, None], model.geom_size[obst], 0.0)
            self._box_g[i] = model.geom_margin[obst] + np.where(box, 0.0, model.geom_rbound[obst])
            self._grid(int(i), arena)
            self.controllers.reset_copy(int(i))
            self.copies.arenas[i] = arena
        self.batch.set_models(self.models)
        self.copies.reset_physics(ids)
        for i in ids:  # the obstacles' places (static)
            data = self.batch.get_data(int(i), self._data)
            self._box_c[i], self._box_r[i] = data.geom_xpos[self._obst[i]], data.geom_xmat[self._obst[i]]
        self.copies.noise.reset(rngs, ids)
        trunk_poses(self._xpos, self._xmat, self._trunk, self.pose)
        self.ks[ids], self.contacts[ids], self.covered[ids], self.stuck[ids] = 0, 0, 0, False
        for i in ids:
            self._visit(int(i))
            if self._ring.shape[1]:
                self._ring[i, 0] = self.pose[i, :2]

    def _sense(self) -> None:
        """Every copy's observation (AMOSII's own noisy distances, no echo reported as the range) and pose."""
        dist, _ = self.copies.sense()
        reported(dist, US_RANGE, self.obs)
        trunk_poses(self._xpos, self._xmat, self._trunk, self.pose)

    def _grid(self, i: int, arena: ArenaSpec) -> None:
        """Copy i's coverage grid: origin, free cells (those of the single env's set), nothing visited.

        An unbounded arena has no grid (its cells go to the set of cells off the grid) and no free cells.
        """
        self.visited[i], self.free[i], self.free_count[i], self._extra[i] = False, False, 0, set()
        if arena.bounds is None:
            self.origin[i] = 0.0  # as ExploreTask's
            return
        x0, x1, y0, y1 = arena.bounds
        cells = (math.ceil((x1 - x0) / CELL), math.ceil((y1 - y0) / CELL))
        if cells[0] > self.visited.shape[1] or cells[1] > self.visited.shape[2]:  # grow every copy's grid
            size = (self.num_envs, max(cells[0], self.visited.shape[1]), max(cells[1], self.visited.shape[2]))
            for name in ("visited", "free"):
                grown = np.zeros(size, dtype=bool)
                old = getattr(self, name)
                grown[:, : old.shape[1], : old.shape[2]] = old
                setattr(self, name, grown)
        self.origin[i] = (x0, y0)
        free = np.floor((arena.free_cells(CELL) - self.origin[i]) / CELL).astype(int)  # as ExploreTask._cell
        self.free[i, free[:, 0], free[:, 1]] = True
        self.free_count[i] = int(self.free[i].sum())

    def _visit(self, i: int) -> None:
        """Count copy i's cell at its start pose, or its cell off the grid after a step, as ExploreTask's sets."""
        cx, cy = (int(c) for c in np.floor((self.pose[i, :2] - self.origin[i]) / CELL).astype(int))
        if 0 <= cx < self.visited.shape[1] and 0 <= cy < self.visited.shape[2]:
            self.visited[i, cx, cy] = True
            self.covered[i] = int(self.free[i, cx, cy])
        elif (cx, cy) not in self._extra[i]:  # a new cell off the grid: rewarded, never free
            self._extra[i].add((cx, cy))
            self.reward[i] = CELL * CELL

    def _info(self) -> dict[str, Any]:
        c, f = self.covered, self.free_count  # no free cells (an unbounded arena): NaN, as the single env
        coverage = c / f if f.all() else np.divide(c, f, out=np.full(f.shape, math.nan), where=f > 0)
        return {
            "pose": self.pose.copy(),
            "coverage": coverage,
            "stuck": self.stuck.copy(),
            "contacts": self.contacts.copy(),
        }
