"""Gymnasium environments: single against vectorised, in the same run: ``Explore-v0`` and ``ExplorePhysics-v0``.

Measures environment steps per second of

* ``single``: one :class:`~neurowalk.envs.explore.ExploreEnv`, stepped from Python (``--single-steps`` steps);
* ``vector``: :class:`~neurowalk.envs.vector.ExploreVectorEnv` with ``--copies`` copies (``gymnasium.make_vec(...,
  vectorization_mode="vector_entry_point")``), ``--vector-steps`` calls of ``step`` inside an episode;
* ``vector_with_resets``: the same through whole episodes of ``--max-steps`` steps, so that every copy's automatic
  reset (a new random environment) is counted too.

and of the MuJoCo AMOSII (``physics``):

* for each N of ``--physics-copies`` (2, 8, 16): :class:`~neurowalk.envs.physics_vector.ExplorePhysicsVectorEnv`
  with N copies, physics on ``--nthread`` threads, ``--physics-steps`` calls of ``step`` inside an episode, against
  :class:`~neurowalk.envs.physics.ExplorePhysicsEnv` stepped through the same N episodes one after another (the
  same work, bit for bit), the two timed in alternating stretches; ``physics_share`` is the part of the vector
  environment's time spent in ``Batch.step``. With few copies the slowest copy of each step sets the pace.

and, idle and with another process spinning on one core (``busy_core``, as when an RL learner runs beside the
environments), the vectorised environment on 1 and on all of numba's threads, and the vectorised physics
environment (16 copies) on 1 and 2 MuJoCo threads (``threads``: medians over alternating repeats).

Actions are random steering pairs drawn beforehand. Reported: steps per second of each, the ratios against the
single environment, the threads numba and MuJoCo's batch used. Run: ``python benchmarks/bench_envs.py [--copies
1024] [--out out/bench]``; writes ``envs.json``.
"""

from __future__ import annotations

import argparse
import contextlib
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
from neurowalk.experiments.bench import busy_core


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


def physics_rates(copies: int, steps: int, nthread: int, rounds: int = 10) -> tuple[float, float, float]:
    """Steps/s of ExplorePhysicsEnv and of ExplorePhysicsVectorEnv with ``copies`` copies on the same episodes, and
    the share of the latter's time spent in ``Batch.step``.

    The vector environment runs copies from seeds 0 .. copies - 1; one single environment per copy runs that copy's
    episode (the same seed and actions: the same trajectory, bit for bit), one after another. The two are timed in
    ``rounds`` alternating stretches of the ``steps`` steps, so that a change in the machine's load touches both.
    """
    singles = [ExplorePhysicsEnv(max_steps=steps + 1) for _ in range(copies)]
    vector = ExplorePhysicsVectorEnv(copies, max_steps=steps + 1, nthread=nthread)
    for i, env in enumerate(singles):
        env.reset(seed=i)
    vector.reset(seed=0)
    acts = np.random.default_rng(1).uniform(-1, 1, size=(steps + 1, copies, 2))
    for i, env in enumerate(singles):  # compile, warm
        env.step(acts[0, i])
    vector.step(acts[0])
    vector.physics_s = 0.0
    single_s = vector_s = 0.0
    for stretch in np.array_split(acts[1:], rounds):
        t0 = time.perf_counter()
        for i, env in enumerate(singles):
            for a in stretch[:, i]:
                env.step(a)
        t1 = time.perf_counter()
        for a in stretch:
            vector.step(a)
        t2 = time.perf_counter()
        single_s, vector_s = single_s + t1 - t0, vector_s + t2 - t1
    return copies * steps / single_s, copies * steps / vector_s, vector.physics_s / vector_s


def physics_vector_rate(copies: int, steps: int, nthread: int) -> float:
    """Steps/s of ExplorePhysicsVectorEnv with ``copies`` copies, physics on ``nthread`` threads."""
    env = ExplorePhysicsVectorEnv(copies, max_steps=steps + 1, nthread=nthread)
    env.reset(seed=0)
    acts = np.random.default_rng(1).uniform(-1, 1, size=(steps + 1, copies, 2))
    env.step(acts[0])
    t0 = time.perf_counter()
    for a in acts[1:]:
        env.step(a)
    return copies * steps / (time.perf_counter() - t0)


def thread_rates(copies: int, steps: int, max_steps: int, physics_steps: int, repeats: int = 3) -> dict:
    """Idle and with one core busy: the vector environment on 1 and on all numba threads, the physics vector
    environment (16 copies) on 1 and 2 threads; medians of ``repeats`` rounds of 1, 2, 2, 1 threads."""
    most = numba.config.NUMBA_NUM_THREADS
    out: dict = {"threading_layer": None, "numba_threads": [1, most], "physics_nthread": [1, 2], "physics_copies": 16}
    for load in ("idle", "busy_core"):
        vec: dict[int, list[float]] = {1: [], most: []}
        phys: dict[int, list[float]] = {1: [], 2: []}
        with busy_core() if load == "busy_core" else contextlib.nullcontext():
            for _ in range(repeats):
                for n in (1, most, most, 1):  # in both orders: a drift of the load touches both alike
                    numba.set_num_threads(n)
                    vec[n].append(vector_rate(copies, steps, max_steps, resets=False))
                numba.set_num_threads(most)
                for n in (1, 2, 2, 1):
                    phys[n].append(physics_vector_rate(16, physics_steps, n))
        v = {n: float(np.median(r)) for n, r in vec.items()}
        p = {n: float(np.median(r)) for n, r in phys.items()}
        out[load] = {
            "vector_steps_per_s": {str(n): r for n, r in v.items()},
            f"vector_{most}_threads_over_1": v[most] / v[1],
            "physics_vector_steps_per_s": {str(n): r for n, r in p.items()},
            "physics_vector_2_threads_over_1": p[2] / p[1],
        }
    out["threading_layer"] = numba.threading_layer()
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--copies", type=int, default=1024)
    ap.add_argument("--single-steps", type=int, default=20_000)
    ap.add_argument("--vector-steps", type=int, default=500)
    ap.add_argument("--max-steps", type=int, default=2000)
    ap.add_argument("--physics-copies", type=lambda s: [int(n) for n in s.split(",")], default=[2, 8, 16])
    ap.add_argument("--physics-steps", type=int, default=300)
    ap.add_argument("--thread-steps", type=int, default=1500, help="steps of each measurement of the threads section")
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
    physics: dict = {"nthread": args.nthread, "steps": args.physics_steps, "runs": []}
    for copies in args.physics_copies:
        one, many, share = physics_rates(copies, args.physics_steps, args.nthread)
        physics["runs"].append({"copies": copies, "single_steps_per_s": one, "vector_steps_per_s": many,
                                "vector_over_single": many / one, "physics_share": share})  # fmt: skip
    result["physics"] = physics
    result["threads"] = thread_rates(args.copies, args.thread_steps, args.max_steps, args.physics_steps)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "envs.json").write_text(json.dumps(result, indent=2) + "\n")
    print(f"single env: {single:,.0f} steps/s")
    print(
        f"vector env, {args.copies} copies: {vector:,.0f} steps/s ({vector / single:.0f}x); through whole "
        f"{args.max_steps}-step episodes with their resets: {with_resets:,.0f} steps/s ({with_resets / single:.0f}x)"
    )
    for row in physics["runs"]:
        one, many, share = row["single_steps_per_s"], row["vector_steps_per_s"], row["physics_share"]
        print(f"physics: single env {one:,.0f} steps/s; vector env, {row['copies']} copies on {args.nthread} threads: "
              f"{many:,.0f} steps/s ({many / one:.2f}x; {share:.0%} of its time in Batch.step)")  # fmt: skip
    th = result["threads"]
    for load in ("idle", "busy_core"):
        r = th[load]
        print(f"{load} ({th['threading_layer']}): vector env {r['vector_steps_per_s']} steps/s by threads; physics "
              f"vector env {r['physics_vector_steps_per_s']} by threads")  # fmt: skip


if __name__ == "__main__":
    main()
