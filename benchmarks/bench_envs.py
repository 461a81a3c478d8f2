"""Gymnasium environments: single against vectorised, in the same run: ``Explore-v0`` and ``ExplorePhysics-v0``.

Measures environment steps per second of

* ``single``: one :class:`~neurowalk.envs.explore.ExploreEnv`, stepped from Python (``--single-steps`` steps);
* ``vector``: :class:`~neurowalk.envs.vector.ExploreVectorEnv` with ``--copies`` copies (``gymnasium.make_vec(...,
  vectorization_mode="vector_entry_point")``), ``--vector-steps`` calls of ``step`` inside an episode;
* ``vector_with_resets``: the same through whole episodes of ``--max-steps`` steps, so that every copy's automatic
  reset (a new random environment) is counted too.

and of the MuJoCo AMOSII (``physics``):

* ``single``: one :class:`~neurowalk.envs.physics.ExplorePhysicsEnv` (``--physics-steps`` steps in each of the
  arenas of seeds 0-3);
* ``vector``: :class:`~neurowalk.envs.physics_vector.ExplorePhysicsVectorEnv` with N copies for each N of
  ``--physics-copies`` (2, 8, 16), physics on ``--nthread`` threads, ``--physics-steps`` calls of ``step``
  inside an episode; ``physics_share`` is the part of its time spent in ``Batch.step``.

Actions are random steering pairs drawn beforehand. Reported: steps per second of each, the ratios against the
single environment, the threads numba and MuJoCo's batch used. Run: ``python benchmarks/bench_envs.py [--copies
1024] [--out out/bench]``; writes ``envs.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numba
import numpy as np

from neurowalk.envs.explore import ExploreEnv
from neurowalk.envs.physics import ExplorePhysicsEnv
from neurowalk.envs.physics_vector import ExplorePhysicsVectorEnv
from neurowalk.envs.vector import ExploreVectorEnv


def single_rate(steps: int) -> float:
    env = ExploreEnv(max_steps=steps + 1)
    env.reset(seed=0)
    acts = np.random.default_rng(0).uniform(-1, 1, size=(steps, 2))
    env.step(acts[0])
    t0 = time.perf_counter()
    for a in acts:
        env.step(a)
    return steps / (time.perf_counter() - t0)


def vector_rate(copies: int, steps: int, max_steps: int, resets: bool) -> float:
    env = ExploreVectorEnv(copies, max_steps=max_steps)
    env.reset(seed=0)
    acts = np.random.default_rng(1).uniform(-1, 1, size=(64, copies, 2))
    env.step(acts[0])  # compile, warm
    n = max_steps + 1 if resets else steps  # a whole episode and the reset step after it
    env.reset(seed=1)
    t0 = time.perf_counter()
    for k in range(n):
        env.step(acts[k % 64])
    return copies * n / (time.perf_counter() - t0)


def physics_single_rate(steps: int, seeds: int = 4) -> float:
    """Steps/s of one ExplorePhysicsEnv, ``steps`` steps in each arena of seeds 0 .. seeds - 1 (resets not timed)."""
    env = ExplorePhysicsEnv(max_steps=steps + 1)
    acts = np.random.default_rng(0).uniform(-1, 1, size=(steps, 2))
    wall = 0.0
    for seed in range(seeds):
        env.reset(seed=seed)
        t0 = time.perf_counter()
        for a in acts:
            env.step(a)
        wall += time.perf_counter() - t0
    return seeds * steps / wall


def physics_vector_rate(copies: int, steps: int, nthread: int) -> tuple[float, float]:
    """Steps/s of ExplorePhysicsVectorEnv (copies from seeds 0 .. copies - 1) and its share of time in physics."""
    env = ExplorePhysicsVectorEnv(copies, max_steps=steps + 2, nthread=nthread)
    env.reset(seed=0)
    acts = np.random.default_rng(1).uniform(-1, 1, size=(steps + 1, copies, 2))
    env.step(acts[0])  # compile, warm
    env.physics_s = 0.0
    t0 = time.perf_counter()
    for a in acts[1:]:
        env.step(a)
    wall = time.perf_counter() - t0
    return copies * steps / wall, env.physics_s / wall


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--copies", type=int, default=1024)
    ap.add_argument("--single-steps", type=int, default=20_000)
    ap.add_argument("--vector-steps", type=int, default=500)
    ap.add_argument("--max-steps", type=int, default=2000)
    ap.add_argument("--physics-copies", type=lambda s: [int(n) for n in s.split(",")], default=[2, 8, 16])
    ap.add_argument("--physics-steps", type=int, default=200)
    ap.add_argument("--nthread", type=int, default=2, help="physics threads of the vectorised physics environment")
    ap.add_argument("--out", type=Path, default=Path("out/bench"))
    args = ap.parse_args()
    single = single_rate(args.single_steps)
    vector = vector_rate(args.copies, args.vector_steps, args.max_steps, resets=False)
    with_resets = vector_rate(args.copies, args.vector_steps, args.max_steps, resets=True)
    result = {"single_steps_per_s": single, "vector_steps_per_s": vector, "vector_with_resets_steps_per_s": with_resets,
              "vector_over_single": vector / single, "vector_with_resets_over_single": with_resets / single,
              "copies": args.copies, "max_steps": args.max_steps, "numba_threads": numba.config.NUMBA_NUM_THREADS,
              "cores": os.cpu_count()}  # fmt: skip
    physics_single = physics_single_rate(args.physics_steps)
    physics = {"single_steps_per_s": physics_single, "nthread": args.nthread, "steps": args.physics_steps,
               "vector": []}  # fmt: skip
    for copies in args.physics_copies:
        rate, share = physics_vector_rate(copies, args.physics_steps, args.nthread)
        physics["vector"].append({"copies": copies, "steps_per_s": rate, "vector_over_single": rate / physics_single,
                                  "physics_share": share})  # fmt: skip
    result["physics"] = physics
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "envs.json").write_text(json.dumps(result, indent=2) + "\n")
    print(f"single env: {single:,.0f} steps/s")
    print(
        f"vector env, {args.copies} copies: {vector:,.0f} steps/s ({vector / single:.0f}x); through whole "
        f"{args.max_steps}-step episodes with their resets: {with_resets:,.0f} steps/s ({with_resets / single:.0f}x)"
    )
    print(f"physics, single env: {physics_single:,.0f} steps/s")
    for row in physics["vector"]:
        rate, ratio, share = row["steps_per_s"], row["vector_over_single"], row["physics_share"]
        print(f"physics, vector env, {row['copies']} copies on {args.nthread} threads: {rate:,.0f} steps/s "
              f"({ratio:.2f}x; {share:.0%} of its time in Batch.step)")  # fmt: skip


if __name__ == "__main__":
    main()
