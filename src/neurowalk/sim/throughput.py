"""``mujoco.batch`` against the CPU loop on the same runs, measured side by side (``neurowalk bench``, tests)."""

from __future__ import annotations

import time
from typing import Any

from neurowalk.sim.batch import MujocoBatchWorlds
from neurowalk.sim.episode import EpisodeConfig, run_episode

__all__ = ["measure_throughput"]


def measure_throughput(
    n_copies: int = 8,
    steps: int = 300,
    nthread: int = 2,
    *,
    arena: str = "random",
    controller: str = "plastic",
    baseline: bool = True,
) -> dict[str, Any]:
    """Physics throughput of a batch against the single loop on the same runs, measured side by side.

    Runs ``n_copies`` configs (seeds 0, 1, ...) of ``arena`` and ``controller`` for ``steps`` control steps
    as one batch on ``nthread`` threads and, if ``baseline``, one after another with ``run_episode``. Wall
    times exclude building (model compilation, arenas); the first batch call also compiles the controller
    kernels if numba's cache is cold, so call it once before timing anything that matters.

    Returns:
        A JSON-able dict: ``n_copies``, ``steps``, ``nthread``, ``n_substeps``, ``physics_steps`` (all copies),
        ``batch_wall_s``, ``batch_build_s``, ``batch_physics_s`` / ``batch_control_s`` (time in
        ``Batch.step`` / in sensing, controllers and recording), ``batch_physics_steps_per_s`` (aggregate,
        whole loop), and with the baseline ``single_wall_s``, ``single_physics_steps_per_s`` and
        ``speedup`` (single wall time / batch wall time).
    """
    configs = [EpisodeConfig(arena=arena, controller=controller, steps=steps, seed=s) for s in range(n_copies)]
    t0 = time.perf_counter()
    be = MujocoBatchWorlds(configs, nthread=nthread)
    t1 = time.perf_counter()
    be.run()
    wall = time.perf_counter() - t1
    physics_steps = n_copies * steps * be.n_substeps
    out: dict[str, Any] = {
        "n_copies": n_copies,
        "steps": steps,
        "nthread": nthread,
        "arena": arena,
        "controller": controller,
        "n_substeps": be.n_substeps,
        "physics_steps": physics_steps,
        "batch_wall_s": wall,
        "batch_build_s": t1 - t0,
        "batch_physics_s": be.timing["physics"],
        "batch_control_s": be.timing["control"],
        "batch_physics_steps_per_s": physics_steps / wall,
    }
    if baseline:
        single = sum(run_episode(cfg).summary["wall_time_s"] for cfg in configs)
        out.update(single_wall_s=single, single_physics_steps_per_s=physics_steps / single, speedup=single / wall)
    return out
