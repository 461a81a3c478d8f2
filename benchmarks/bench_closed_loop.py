"""Closed loop vs bare ``mj_step`` on the same model for the same simulated time, side by side.

The baseline replays the closed loop's own recorded joint targets open-loop (so the robot makes
the same motions and contacts) with nothing but ``data.ctrl[:] = ...; mj_step(nstep)`` per
control step. The closed loop adds sensors, noise, the neural controller and recording.

Run: ``python benchmarks/bench_closed_loop.py [--steps 3000] [--out out/bench]``; writes
``closed_loop.json``. Reported: median wall time of each over repeats (interleaved), their ratio
(the budget is 1.15), and real-time factors.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import mujoco
import numpy as np

from neurowalk.sim.episode import EpisodeConfig, build, run_episode


def bare(cfg: EpisodeConfig, targets: np.ndarray) -> float:
    """Wall time (s) of bare mj_step replaying ``targets`` (steps, 19)."""
    _, body, _ = build(cfg)
    body.reset(np.random.default_rng(0))
    m, d, n = body.model, body.data, body.n_substeps
    t0 = time.perf_counter()
    for k in range(targets.shape[0]):
        d.ctrl[:] = targets[k]
        mujoco.mj_step(m, d, nstep=n)
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--steps", type=int, default=3000)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--out", type=Path, default=Path("out/bench"))
    args = ap.parse_args()
    cfg = EpisodeConfig(arena="box", controller="plastic", steps=args.steps, seed=0)
    loop_times, bare_times = [], []
    for _ in range(args.repeats):
        ep = run_episode(cfg)
        loop_times.append(ep.summary["wall_time_s"])
        bare_times.append(bare(cfg, ep.trajectory.targets))
    sim_time = args.steps / cfg.control_hz
    loop, base = float(np.median(loop_times)), float(np.median(bare_times))
    report = {
        "steps": args.steps,
        "simulated_time_s": sim_time,
        "physics_steps_per_control_step": build(cfg)[1].n_substeps,
        "closed_loop_wall_s": loop,
        "bare_mj_step_wall_s": base,
        "ratio_closed_loop_over_bare": loop / base,
        "ratio_budget": 1.15,
        "real_time_factor_closed_loop": sim_time / loop,
        "real_time_factor_bare": sim_time / base,
        "control_steps_per_s_closed_loop": args.steps / loop,
        "repeats": args.repeats,
    }
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "closed_loop.json").write_text(json.dumps(report, indent=2) + "\n")
    print(f"bare mj_step   {base:7.3f} s  ({report['real_time_factor_bare']:.0f}x real time)")
    print(f"closed loop    {loop:7.3f} s  ({report['real_time_factor_closed_loop']:.0f}x real time, "
          f"{report['control_steps_per_s_closed_loop']:.0f} control steps/s)")  # fmt: skip
    print(f"ratio          {report['ratio_closed_loop_over_bare']:.3f} (budget 1.15)")


if __name__ == "__main__":
    main()
