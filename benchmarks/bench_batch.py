"""Physics batch (``mujoco.batch``, 1 and 2 threads) against the single loop on the same runs, side by side.

Runs ``--copies`` configs of the ``random`` arena (plastic controller, seeds 0, 1, ...) for ``--steps`` control
steps five ways, interleaved, ``--repeats`` times:

* ``single``: ``run_episode`` for each config, one after another (the closed loop as it is);
* ``single_bare``: the same runs' recorded joint targets replayed open-loop through ``AmosII.apply/advance``
  (physics of the single loop, nothing else);
* ``batch_1`` / ``batch_2``: the closed loop of all copies in one :class:`~neurowalk.sim.batch.MujocoBatchWorlds`
  on 1 / 2 threads;
* ``batch_bare_1`` / ``batch_bare_2``: the recorded targets replayed through the batch's ``step`` alone.

Wall times exclude building (compilation of models and arenas). Reported: median wall time of each, aggregate
physics steps per second, and ratios against ``single`` measured in the same run (no timed asserts: the
numbers depend on the machine and on what else runs on it).

Run: ``python benchmarks/bench_batch.py [--copies 8] [--steps 300] [--repeats 3] [--out out/bench]``; writes
``batch.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numpy as np

from neurowalk.sim.batch import MujocoBatchWorlds
from neurowalk.sim.episode import EpisodeConfig, build, run_episode, seeds


def single(configs: list[EpisodeConfig]) -> tuple[float, list[np.ndarray]]:
    """Wall time (s) of run_episode over the configs, and each run's targets (steps, 19)."""
    eps = [run_episode(cfg) for cfg in configs]
    return sum(ep.summary["wall_time_s"] for ep in eps), [ep.trajectory.targets for ep in eps]


def single_bare(configs: list[EpisodeConfig], targets: list[np.ndarray]) -> float:
    """Wall time (s) of replaying each run's targets through AmosII.apply/advance."""
    total = 0.0
    for cfg, tg in zip(configs, targets, strict=True):
        _, body, _ = build(cfg)
        body.reset(seeds(cfg)[0])
        t0 = time.perf_counter()
        for k in range(tg.shape[0]):
            body.apply(tg[k])
            body.advance()
        total += time.perf_counter() - t0
    return total


def batch(configs: list[EpisodeConfig], nthread: int) -> tuple[float, dict[str, float]]:
    """Wall time (s) of the batch's closed loop, and its split into physics and control."""
    be = MujocoBatchWorlds(configs, nthread=nthread)
    t0 = time.perf_counter()
    be.run()
    return time.perf_counter() - t0, dict(be.timing)


def batch_bare(configs: list[EpisodeConfig], targets: list[np.ndarray], nthread: int) -> float:
    """Wall time (s) of replaying the targets through the batch's step alone."""
    be = MujocoBatchWorlds(configs, nthread=nthread)
    be.reset()
    ctrl = be.batch.bind("ctrl")
    tg = np.stack(targets, axis=1)  # (steps, n, 19)
    t0 = time.perf_counter()
    for k in range(tg.shape[0]):
        ctrl[:] = tg[k]
        be.batch.step(nstep=be.n_substeps)
    return time.perf_counter() - t0


def _median_split(splits: list[dict[str, float]]) -> dict[str, float]:
    return {p: float(np.median([s[p] for s in splits])) for p in ("physics", "control")}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--copies", type=int, default=8)
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", type=Path, default=Path("out/bench"))
    args = ap.parse_args()
    run = {"arena": "random", "controller": "plastic", "steps": args.steps}
    configs = [EpisodeConfig(**run, seed=s) for s in range(args.copies)]
    MujocoBatchWorlds(configs[:1], nthread=1).run()  # warm-up: compiles the controller kernels if not cached
    times: dict[str, list[float]] = {k: [] for k in ("single", "single_bare", "batch_1", "batch_2", "batch_bare_1",
                                                     "batch_bare_2")}  # fmt: skip
    splits: dict[str, list[dict[str, float]]] = {"batch_1": [], "batch_2": []}
    for _ in range(args.repeats):
        wall, targets = single(configs)
        times["single"].append(wall)
        times["single_bare"].append(single_bare(configs, targets))
        for nthread in (1, 2):
            wall, split = batch(configs, nthread)
            times[f"batch_{nthread}"].append(wall)
            splits[f"batch_{nthread}"].append(split)
            times[f"batch_bare_{nthread}"].append(batch_bare(configs, targets, nthread))
    n_sub = MujocoBatchWorlds(configs[:1]).n_substeps
    physics_steps = args.copies * args.steps * n_sub
    med = {k: float(np.median(v)) for k, v in times.items()}
    report = {
        "copies": args.copies,
        "control_steps": args.steps,
        "physics_steps_per_control_step": n_sub,
        "physics_steps": physics_steps,
        "repeats": args.repeats,
        "cpus": os.cpu_count(),
        "load_average": os.getloadavg(),
        "wall_s": med,
        "physics_steps_per_s": {k: physics_steps / v for k, v in med.items()},
        "ratio_to_single": {k: med["single"] / v for k, v in med.items()},
        "batch_split_s": {k: _median_split(v) for k, v in splits.items()},
    }
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "batch.json").write_text(json.dumps(report, indent=2) + "\n")
    print(f"{args.copies} copies x {args.steps} control steps x {n_sub} physics steps, median of {args.repeats}")
    for k, v in med.items():
        print(f"{k:13s} {v:7.3f} s  {physics_steps / v:9.0f} physics steps/s  {med['single'] / v:5.2f}x single")
    for k, s in report["batch_split_s"].items():
        print(f"{k}: physics {s['physics']:.3f} s, control {s['control']:.3f} s")


if __name__ == "__main__":
    main()
