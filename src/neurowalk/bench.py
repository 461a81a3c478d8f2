"""``neurowalk bench``: the performance figures of the project, measured side by side in one run.

Every number is a rate or a ratio against a baseline measured in the same run on the same machine:

* physics: control steps per second of the single closed loop (AMOSII, random arena, plastic network),
  and bare ``mj_step`` physics steps per second on the same model;
* surrogate: environment steps per second of the planar surrogate on the same arenas and network, in
  one process and over a process pool, and its ratio to the physics control-step rate;
* batch physics: aggregate physics steps per second of ``mujoco.batch`` on 1 and ``cores`` threads
  against the single loop on the same runs;
* Table 2 on the surrogate: wall time of the 50-environment table on a process pool.
"""

from __future__ import annotations

import os
import platform
import tempfile
import time
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

import neurowalk

ARENA_OPTS = {"n_boxes": 10, "extent": 9.0, "size": 0.6}


def physics_rates(steps: int, seeds: int) -> dict[str, float]:
    """Control steps/s of the single loop and bare mj_step steps/s on the same model (wall time, no build)."""
    from neurowalk.sim.episode import EpisodeConfig, build, run_episode

    cfgs = [EpisodeConfig(arena="random", arena_opts=ARENA_OPTS, steps=steps, seed=s) for s in range(seeds)]
    run_episode(EpisodeConfig(arena="open", steps=5))  # warm the compiled kernels
    wall = sum(run_episode(c).summary["wall_time_s"] for c in cfgs)
    _, body, _ = build(cfgs[0])
    m, d = body.model, body.data  # type: ignore[union-attr]
    body.reset(np.random.default_rng(0))  # type: ignore[arg-type]
    n = steps * body.n_substeps  # type: ignore[union-attr]
    t0 = time.perf_counter()
    mujoco.mj_step(m, d, nstep=n)
    bare = n / (time.perf_counter() - t0)
    return {"control_steps_per_s": steps * seeds / wall, "bare_mj_step_per_s": bare,
            "substeps_per_control_step": body.n_substeps}  # type: ignore[union-attr]  # fmt: skip


def _surrogate_run(seed: int, steps: int) -> float:
    from neurowalk.sim.episode import EpisodeConfig, run_episode

    cfg = EpisodeConfig(arena="random", arena_opts=ARENA_OPTS, body="surrogate", steps=steps, seed=seed)
    return run_episode(cfg).summary["wall_time_s"]


def surrogate_rates(steps: int, envs: int, workers: int) -> dict[str, float]:
    """Environment steps/s of the surrogate: in-loop rate in one process, and end-to-end over a pool."""
    from concurrent.futures import ProcessPoolExecutor

    _surrogate_run(0, 100)  # compile / load the numba cache
    loop = sum(_surrogate_run(s, steps) for s in range(envs))
    t0 = time.perf_counter()
    with ProcessPoolExecutor(max_workers=workers) as pool:
        list(pool.map(_surrogate_run, range(envs, envs + envs * workers * 2), [steps] * envs * workers * 2))
    pool_wall = time.perf_counter() - t0
    return {"env_steps_per_s_one_process": steps * envs / loop,
            "env_steps_per_s_pool": steps * envs * workers * 2 / pool_wall, "pool_workers": workers}  # fmt: skip


def table2_time(workers: int) -> dict[str, float]:
    """Wall time of the 50-environment Table 2 on the surrogate (fresh store, full length runs)."""
    from neurowalk.experiments.table2 import run

    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        res = run(out=Path(tmp), workers=workers)
        wall = time.perf_counter() - t0
    return {"wall_s": wall, "environments": 50, "runs": 150, "steps_per_run": res.summary["steps"],
            "plastic_success": res.summary["counts"]["plastic"]["success"]}  # fmt: skip


def run_bench(*, quick: bool = False, workers: int | None = None, progress: bool = True) -> dict[str, Any]:
    """All figures; ``quick`` shortens every measurement (for tests)."""
    from neurowalk.sim.batch import measure_throughput

    cores = os.cpu_count() or 1
    workers = workers or min(cores, 8)
    steps, seeds = (200, 1) if quick else (2000, 3)
    phys = physics_rates(steps, seeds)
    sur = surrogate_rates(2000 if quick else 20000, 2 if quick else 10, workers)
    batch: dict[str, Any] = {}
    for nthread in sorted({1, workers}):
        b = measure_throughput(n_copies=2 if quick else 8, steps=50 if quick else 300, nthread=nthread)
        batch[f"nthread_{nthread}"] = b
    out = {
        "machine": {"cores": cores, "platform": platform.platform(), "python": platform.python_version(),
                    "mujoco": mujoco.__version__, "neurowalk": neurowalk.__version__},
        "physics": phys,
        "surrogate": sur,
        "surrogate_vs_physics": {
            "one_process": sur["env_steps_per_s_one_process"] / phys["control_steps_per_s"],
            "pool": sur["env_steps_per_s_pool"] / phys["control_steps_per_s"],
            "aim": 1000,
        },
        "batch_physics": {
            **batch,
            "speedup_vs_single_loop": {k: v.get("speedup") for k, v in batch.items()},
            "aim": f"close to the number of cores ({cores})",
        },
        "quick": quick,
    }  # fmt: skip
    if not quick:
        out["table2_surrogate"] = table2_time(workers)
        out["table2_surrogate"]["aim_s"] = 60
    return out
