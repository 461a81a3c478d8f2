"""``neurowalk bench``: the performance figures of the project, measured side by side in one run.

Every number is a rate or a ratio against a baseline measured in the same run on the same machine:

* physics: control steps per second of the single closed loop (AMOSII, random arena, plastic network),
  and bare ``mj_step`` physics steps per second on the same model; the closed loop under the adopted physics
  against the former (implicitfast, Newton, light servo rotors: before issue 51) on the same run;
* surrogate: environment steps per second of the planar surrogate on the same arenas and network, in
  one process and over a process pool, and its ratio to the physics control-step rate; its end-to-end rate
  (build, simulate, summarise through ``run_episode``) as a fraction of its in-loop rate, on the same runs;
  and ``run_all`` (the one runner) on a pool of ``workers`` processes against one process, end to end;
* batch physics: aggregate physics steps per second of ``mujoco.batch`` on 1 and ``cores`` threads
  against the single loop on the same runs;
* Table 2 on the surrogate: wall time of the 50-environment table on a process pool;
* busy core: the parallel figures (``mujoco.batch`` on 1 and ``cores`` threads, the surrogate's pool against one
  process) again with another process spinning on one core for the whole measurement (:func:`busy_core`), as
  when a learner or a second job shares the machine.
"""

from __future__ import annotations

import contextlib
import os
import platform
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

import neurowalk
from neurowalk import profiling
from neurowalk.body.noise import BLOCK
from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.study import compute
from neurowalk.experiments.study_runs import run_all
from neurowalk.sim.config import DEFAULT_ENGINE
from neurowalk.sim.engines import ENGINES
from neurowalk.sim.episode import EpisodeConfig, build, run_episode
from neurowalk.sim.throughput import measure_throughput
from neurowalk.sim.warp_engine import WarpWorlds, device_name, resolve_device

ARENA_OPTS = {"n_boxes": 10, "extent": 9.0, "size": 0.6}


def _timed(fn: Callable[..., Any], *args: Any, **kwargs: Any) -> tuple[Any, float]:
    """``fn(*args, **kwargs)`` and its wall time (s)."""
    t0 = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - t0


def _batch(quick: bool, workers: int, baseline: bool = True) -> tuple[dict[str, Any], float]:
    """``mujoco.batch`` on 1 and ``workers`` threads (16 random arenas; 2 with ``quick``), by ``nthread_T``, and the
    aggregate rate on ``workers`` threads over that on 1."""
    n, steps = (2, 50) if quick else (16, 300)
    batch = {
        f"nthread_{t}": measure_throughput(n_copies=n, steps=steps, nthread=t, baseline=baseline)
        for t in sorted({1, workers})
    }
    rate = {k: b["batch_physics_steps_per_s"] for k, b in batch.items()}
    return batch, rate[f"nthread_{workers}"] / rate["nthread_1"]


@contextlib.contextmanager
def busy_core() -> Iterator[None]:
    """Another process spins on one core for the length of the block (it is killed at the end)."""
    hog = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    time.sleep(0.3)  # the interpreter starts and begins to spin
    try:
        yield
    finally:
        hog.kill()
        hog.wait()


def busy_parallel(quick: bool, workers: int) -> dict[str, Any]:
    """The parallel figures with one core busy: ``mujoco.batch`` on 1 and ``workers`` threads (16 random arenas),
    and the surrogate's ``run_all`` on ``workers`` processes against one; ``*_over_1``: the parallel rate over
    the serial one (at least 1: parallel work must not be slower than serial on a busy machine)."""
    with busy_core():
        batch, ratio = _batch(quick, workers, baseline=False)
        pool = surrogate_pool(2000 if quick else 20000, 4 if quick else 100, workers, 1 if quick else 3)
    return {
        "batch_physics": {**batch, f"nthread_{workers}_over_1": ratio},
        "surrogate_pool": pool,
        "how": "another process spins on one core (busy_core) during these measurements",
    }


def physics_rates(steps: int, seeds: int) -> dict[str, float]:
    """Control steps/s of the single loop and bare mj_step steps/s on the same model (wall time, no build)."""

    cfgs = [EpisodeConfig(arena="random", arena_opts=ARENA_OPTS, steps=steps, seed=s) for s in range(seeds)]
    run_episode(EpisodeConfig(arena="open", steps=5))  # warm the compiled kernels
    wall = sum(run_episode(c).summary["wall_time_s"] for c in cfgs)
    _, body, _ = build(cfgs[0])
    m, d = body.model, body.data  # type: ignore[union-attr]
    body.reset(np.random.default_rng(0))  # type: ignore[arg-type]
    n = steps * body.n_substeps  # type: ignore[union-attr]
    bare = n / _timed(mujoco.mj_step, m, d, nstep=n)[1]
    return {
        "control_steps_per_s": steps * seeds / wall,
        "bare_mj_step_per_s": bare,
        "substeps_per_control_step": body.n_substeps,
    }  # type: ignore[union-attr]


def _surrogate_run(seed: int, steps: int) -> float:

    return run_episode(_surrogate_configs(seed, 1, steps)[0]).summary["wall_time_s"]


def surrogate_rates(steps: int, envs: int, workers: int) -> dict[str, float]:
    """Environment steps/s of the surrogate: in-loop rate in one process, and end-to-end over the one runner's pool
    (its result store a temporary one)."""

    _surrogate_run(0, 100)  # compile / load the numba cache
    loop = sum(_surrogate_run(s, steps) for s in range(envs))
    _, pool_wall = _timed(run_all, _surrogate_configs(envs, envs * workers * 2, steps), workers=workers, progress=False)
    return {
        "env_steps_per_s_one_process": steps * envs / loop,
        "env_steps_per_s_pool": steps * envs * workers * 2 / pool_wall,
        "pool_workers": workers,
    }


def _surrogate_configs(first: int, count: int, steps: int) -> list[Any]:

    return [
        EpisodeConfig(arena="random", arena_opts=ARENA_OPTS, body="surrogate", steps=steps, seed=s)
        for s in range(first, first + count)
    ]


def surrogate_end_to_end(steps: int, envs: int) -> dict[str, float]:
    """The surrogate through ``run_episode`` (build, simulate, summarise) against its own simulation, same runs.

    Each run's in-loop time is its ``wall_time_s`` (the compiled loop, noise draws included); its end-to-end
    time is the whole ``run_episode`` call around it, so the two rates share the machine's state.
    """

    _surrogate_run(0, 100)  # compile / load the numba cache
    loop = total = 0.0
    for cfg in _surrogate_configs(0, envs, steps):
        ep, wall = _timed(run_episode, cfg)
        total += wall
        loop += ep.summary["wall_time_s"]
    return {
        "steps_per_run": steps,
        "runs": envs,
        "ms_per_run_in_loop": 1e3 * loop / envs,
        "ms_per_run_end_to_end": 1e3 * total / envs,
        "env_steps_per_s_in_loop": steps * envs / loop,
        "env_steps_per_s_end_to_end": steps * envs / total,
        "end_to_end_over_in_loop": loop / total,
        "aim": 0.7,
    }


def surrogate_pool(steps: int, runs: int, workers: int, repeats: int) -> dict[str, float]:
    """The surrogate end to end on ``runs`` runs: ``run_all`` (the one runner, its store in a temporary folder) on
    ``workers`` processes against one process.

    Median wall times over ``repeats``, one process and pool alternating (the pool starts its workers each time).
    """

    cfgs = _surrogate_configs(0, runs, steps)
    run_all(cfgs[:1], workers=1, progress=False)  # compile / load the numba cache here (the workers fork)
    one, pool = [], []
    for _ in range(repeats):
        for n, into in ((1, one), (workers, pool)):
            into.append(_timed(run_all, cfgs, workers=n, progress=False)[1])
    a, b = float(np.median(one)), float(np.median(pool))
    return {
        "steps_per_run": steps,
        "runs": runs,
        "workers": workers,
        "repeats": repeats,
        "one_process_wall_s": a,
        "pool_wall_s": b,
        "speedup": a / b,
        "aim": 0.9 * workers,
    }


def table2_time(workers: int, environments: int = 50) -> dict[str, float]:
    """Wall time of Table 2 on the surrogate over ``environments`` environments (fresh store, full length runs): what
    ``neurowalk figure table2 --seeds N`` costs to compute (the picture aside)."""
    with tempfile.TemporaryDirectory() as tmp:
        res, wall = _timed(compute, FIGURES["table2"], Settings(out=Path(tmp), workers=workers, seeds=environments))
    counts = res.summary["counts"]
    return {
        "wall_s": wall,
        "environments": environments,
        "runs": environments * len(counts),
        "steps_per_run": res.summary["steps"],
        "success": {name: c["success"] for name, c in counts.items()},
    }


def _bare(cfg: Any, targets: np.ndarray) -> float:
    """Wall time (s) of bare ``mj_step`` replaying joint ``targets`` (steps, 19) on the config's model."""

    _, body, _ = build(cfg)
    body.reset(np.random.default_rng(0))
    m, d, n = body.model, body.data, body.n_substeps
    t0 = time.perf_counter()
    for k in range(targets.shape[0]):
        d.ctrl[:] = targets[k]
        mujoco.mj_step(m, d, nstep=n)
    return time.perf_counter() - t0


def closed_loop_ratio(steps: int = 3000, repeats: int = 5) -> dict[str, Any]:
    """The closed loop (sensors, noise, plastic network, recording) against bare ``mj_step`` on the same model.

    The baseline replays the loop's own recorded joint targets open-loop (the same motions and contacts) with
    nothing but ``ctrl[:] = ...; mj_step(nstep)`` per control step. Median wall times over ``repeats``,
    interleaved; the budget of the ratio is 1.10.
    """

    cfg = EpisodeConfig(arena="box", controller="plastic", steps=steps, seed=0)
    run_episode(EpisodeConfig(arena="box", steps=5))  # warm the compiled kernels
    loops, bares = [], []
    for _ in range(repeats):
        ep = run_episode(cfg)
        loops.append(ep.summary["wall_time_s"])
        bares.append(_bare(cfg, ep.trajectory.targets))
    loop, base = float(np.median(loops)), float(np.median(bares))
    sim = steps / cfg.control_hz
    return {
        "steps": steps,
        "repeats": repeats,
        "simulated_time_s": sim,
        "closed_loop_wall_s": loop,
        "bare_mj_step_wall_s": base,
        "ratio_closed_loop_over_bare": loop / base,
        "ratio_budget": 1.10,
        "real_time_factor_closed_loop": sim / loop,
        "real_time_factor_bare": sim / base,
        "control_steps_per_s_closed_loop": steps / loop,
    }


#: The physics before issue 51 (AMOSII's body options): implicitfast and Newton on the elliptic cone at the same
#: 10 ms step, MuJoCo's contacts (0.02 s), servo rotors of 0.005 kg m^2.
FORMER_PHYSICS = {
    "integrator": "implicitfast",
    "solver": "Newton",
    "cone": "elliptic",
    "solver_tolerance": 1e-6,
    "armature": 0.005,
    "contact_timeconst": 0.02,
}


def physics_settings(steps: int = 3000, repeats: int = 5) -> dict[str, Any]:
    """The closed loop's control steps per second under the adopted physics (``BodyParams``' defaults: the 10 ms
    step, the discrete integrator, the pyramidal cone) and under the former (:data:`FORMER_PHYSICS`), on the same
    run (``box`` arena, plastic network), interleaved, medians over ``repeats``."""
    cfg = EpisodeConfig(arena="box", controller="plastic", steps=steps, seed=0)
    former = cfg.replace(body_opts=FORMER_PHYSICS)
    run_episode(EpisodeConfig(arena="box", steps=5))  # warm the compiled kernels
    walls: dict[str, list[float]] = {"adopted": [], "former": []}
    parts: dict[str, list[tuple[float, float]]] = {"adopted": [], "former": []}
    for _ in range(repeats):
        for name, c in (("adopted", cfg), ("former", former)):
            before = profiling.totals()["seconds"]
            walls[name].append(run_episode(c).summary["wall_time_s"])
            after = profiling.totals()["seconds"]
            parts[name].append(tuple(after.get(k, 0.0) - before.get(k, 0.0) for k in ("physics", "control")))
    rates = {k: steps / float(np.median(v)) for k, v in walls.items()}
    per_step = {  # microseconds of a control step: its physics steps, and the rest of the loop
        k: {part: 1e6 * float(np.median([p[i] for p in v])) / steps for i, part in enumerate(("physics", "control"))}
        for k, v in parts.items()
    }
    return {
        "steps": steps,
        "repeats": repeats,
        "former_body_opts": FORMER_PHYSICS,
        "control_steps_per_s_adopted": rates["adopted"],
        "control_steps_per_s_former": rates["former"],
        "adopted_over_former": rates["adopted"] / rates["former"],
        "aim": 1.3,
        "us_per_control_step": per_step,
        "physics_adopted_over_former": per_step["former"]["physics"] / per_step["adopted"]["physics"],
        "what_limits_it": "a control step is its physics steps and the rest of the loop (sensors, networks, rows "
        "recorded); the adopted solver makes a physics step cheaper, and the rest stays as it was",
    }


def lockstep_rates(
    worlds: tuple[int, ...] = (1, 64, 1024, 4096),
    steps: int = 5,
    *,
    engine: str = "warp",
    device: str | None = None,
    threads: int = 2,
    arena: str = "random",
    progress: bool = True,
) -> dict[str, Any]:
    """The closed loop of lock-step worlds: world-steps/s and where a world-step's time goes, for each number of
    worlds, on MuJoCo Warp (``engine`` "warp", on ``device``) or ``mujoco.batch`` (on ``threads`` threads).

    Worlds run the plastic network in ``arena``: "random" (random arenas as :func:`physics_rates`, one model per
    world on ``mujoco.batch``) or "box" (one arena, every world its own seed: one shared model, so that 16,384 worlds
    fit a laptop's memory). Each measurement runs ``steps`` control steps after one untimed run of the same worlds
    (kernels compiled, CUDA graphs captured). A row's ``host_us`` and ``physics_us`` are microseconds per world and
    control step: the host's part (``sense_us``: sensor model and noise, ``controllers_us``, ``record_us``) and the
    physics'. The sensor noise is drawn :data:`~neurowalk.body.noise.BLOCK` control steps ahead, so a run shorter
    than a block pays a whole block's draw: ``noise_draw_us`` is a world-step's share of the draws in a run of whole
    blocks, and ``host_us`` and ``sense_us`` count it so (``host_us_this_run``: as this short run paid it).
    """
    from neurowalk.sim.batch import MujocoBatchWorlds

    device = resolve_device(device) if engine == "warp" else "cpu"
    opts = ARENA_OPTS if arena == "random" else {}
    rows = []
    for n in worlds:
        kind = "warp" if engine == "warp" else DEFAULT_ENGINE  # the config's engine; mujoco.batch runs CPU configs
        cfgs = [EpisodeConfig(arena=arena, arena_opts=opts, steps=steps, seed=s, engine=kind) for s in range(n)]
        t0 = time.perf_counter()
        runs = WarpWorlds(cfgs, device=device) if engine == "warp" else MujocoBatchWorlds(cfgs, nthread=threads)
        build = time.perf_counter() - t0
        runs.run()  # untimed: compile, capture
        runs.timing = dict.fromkeys(runs.timing, 0.0)
        runs.noise.draw_s, runs.noise.blocks = 0.0, 0
        _, wall = _timed(runs.run)
        per = {k: 1e6 * v / (n * steps) for k, v in runs.timing.items()}
        # the noise is drawn BLOCK steps ahead: a run of whole blocks pays a block's draw once per BLOCK steps
        draw_us = 1e6 * runs.noise.draw_s / (n * BLOCK * max(runs.noise.blocks, 1))
        drawn_here_us = 1e6 * runs.noise.draw_s / (n * steps)
        rows.append(
            {
                "worlds": n,
                "control_steps": steps,
                "wall_s": wall,
                "build_s": build,
                "control_steps_per_s": n * steps / wall,
                "physics_steps_per_s": n * steps * runs.n_substeps / wall,
                "physics_share": runs.timing["physics"] / max(runs.timing["physics"] + runs.timing["control"], 1e-12),
                "host_us": per["control"] - drawn_here_us + draw_us,
                "physics_us": per["physics"],
                "sense_us": per["sense"] - drawn_here_us + draw_us,
                "noise_draw_us": draw_us,
                **{f"{k}_us": per[k] for k in ("controllers", "record")},
                "host_us_this_run": per["control"],
            }
        )
        if progress:
            r = rows[-1]
            print(
                f"{engine} {device}: {n} worlds, {r['control_steps_per_s']:.0f} control steps/s, host "
                f"{r['host_us']:.2f} us and physics {r['physics_us']:.2f} us per world-step",
                flush=True,
            )
    name = device_name(device) if engine == "warp" else f"cpu ({platform.processor() or platform.machine()})"
    return {"engine": engine, "device": device, "device_name": name, "threads": threads, "rows": rows}


def warp_rates(
    worlds: tuple[int, ...] = (1, 64, 1024, 4096), steps: int = 5, device: str | None = None, progress: bool = True
) -> dict[str, Any]:
    """The closed loop on MuJoCo Warp (:func:`lockstep_rates`, random arenas) for each number of worlds."""
    return lockstep_rates(worlds, steps, engine="warp", device=device, progress=progress)


def run_bench(
    *,
    quick: bool = False,
    workers: int | None = None,
    progress: bool = True,
    engine: str = DEFAULT_ENGINE,
    device: str | None = None,
    worlds: tuple[int, ...] = (1, 64, 1024, 4096),
) -> dict[str, Any]:
    """All figures; ``quick`` shortens every measurement (for tests). ``engine`` 'warp': MuJoCo Warp's rates for
    each of ``worlds`` on ``device`` beside the CPU loop and batch (no surrogate figures then)."""

    cores = os.cpu_count() or 1
    workers = workers or min(cores, 8)
    steps, seeds = (200, 1) if quick else (2000, 3)
    phys = physics_rates(steps, seeds)
    loop = closed_loop_ratio(300 if quick else 3000, 1 if quick else 5)
    settings = physics_settings(300 if quick else 3000, 1 if quick else 5)
    batch, ratio = _batch(quick, workers)
    out: dict[str, Any] = {
        "machine": {
            "cores": cores,
            "platform": platform.platform(),
            "python": platform.python_version(),
            "mujoco": mujoco.__version__,
            "neurowalk": neurowalk.__version__,
        },
        "physics": phys,
        "closed_loop_vs_bare": loop,
        "physics_settings": settings,
        "batch_physics": {
            **batch,
            "speedup_vs_single_loop": {k: v.get("speedup") for k, v in batch.items()},
            f"nthread_{workers}_over_1": ratio,
            "aim": f"close to the number of cores ({cores})",
        },
        "quick": quick,
    }
    if ENGINES[engine].devices:  # an engine on a device (MuJoCo Warp): its rates by number of worlds
        w = warp_rates(worlds, 2 if quick else 5, device, progress)
        best = max(r["control_steps_per_s"] for r in w["rows"])
        cpu = phys["control_steps_per_s"]
        w["vs_cpu_loop"] = {
            "best_control_steps_per_s": best,
            "cpu_loop_control_steps_per_s": cpu,
            "ratio": best / cpu,
            "aim_on_a_gpu": 100,
        }
        out["warp"] = w
        return out
    sur = surrogate_rates(2000 if quick else 20000, 2 if quick else 10, workers)
    out["surrogate"] = sur
    out["surrogate_end_to_end"] = surrogate_end_to_end(2000 if quick else 20000, 2 if quick else 40)
    out["surrogate_pool"] = surrogate_pool(2000 if quick else 20000, 4 if quick else 100, workers, 1 if quick else 3)
    cpu = phys["control_steps_per_s"]
    out["surrogate_vs_physics"] = {
        "one_process": sur["env_steps_per_s_one_process"] / cpu,
        "pool": sur["env_steps_per_s_pool"] / cpu,
        "aim": 1000,
    }
    out["busy_core"] = busy_parallel(quick, workers)
    if not quick:
        for key, environments in (("table2_surrogate", 50), ("table2_surrogate_1000", 1000)):
            out[key] = {**table2_time(workers, environments), "aim_s": 60}
    return out
