"""Where a control step of the closed loop goes: a per-stage timer and cProfile, side by side with bare ``mj_step``.

The loop is the one of ``neurowalk.sim.episode`` (AMOSII, ``box`` arena, plastic network), written out here so that
each stage can be timed on its own: physics (``body.advance``: 20 ``mj_step``), sensors (``body.observe`` less its
noise), noise (the coloured sensor noise), controller (``act``: sensory and locomotion networks), apply (joint targets
into ``ctrl``) and recording (the trajectory rows). Bare ``mj_step`` replays the same joint targets on the same model
(the baseline of ``neurowalk bench``). Then cProfile of ``run_episode`` on the same config lists the functions that
take the most time of their own.

Run: ``python benchmarks/bench_profile.py [--steps 3000] [--out out/bench]``; writes ``profile.json``.
"""

from __future__ import annotations

import argparse
import cProfile
import json
import pstats
import time
from pathlib import Path

import numpy as np

from neurowalk.experiments.bench import _bare
from neurowalk.sim.episode import EpisodeConfig, build, run_episode, seeds
from neurowalk.sim.trajectory import Trajectory


def stages(cfg: EpisodeConfig) -> tuple[dict[str, float], np.ndarray]:
    """Seconds per stage over the run, and the joint targets (steps, 19) for the bare baseline."""
    _, body, ctrl = build(cfg)
    body_rng, ctrl_rng, _ = seeds(cfg)
    body.reset(body_rng)
    ctrl.reset(ctrl_rng)
    noise = body._noise
    step_noise, spent = noise.step, {"noise": 0.0}

    def timed_noise() -> np.ndarray:
        t = time.perf_counter()
        out = step_noise()
        spent["noise"] += time.perf_counter() - t
        return out

    noise.step = timed_noise  # type: ignore[method-assign]
    buf = Trajectory.empty(cfg.steps, body.model.nq)
    t = {"physics": 0.0, "sensors and noise": 0.0, "controller": 0.0, "apply": 0.0, "recording": 0.0}
    clock = time.perf_counter
    for k in range(cfg.steps):
        t0 = clock()
        obs = body.observe()
        t1 = clock()
        targets = ctrl.act(obs)
        t2 = clock()
        body.apply(targets)
        t3 = clock()
        body.advance()
        t4 = clock()
        buf.inputs[k], buf.outputs[k], buf.b[k], buf.q[k] = ctrl.inputs, ctrl.steering, ctrl.b, ctrl.q
        buf.targets[k], buf.us_distance[k], buf.foot_contact[k] = targets, obs.us_distance, obs.foot_contact
        buf.qpos[k], buf.t[k] = body.data.qpos, body.data.time
        t5 = clock()
        t["sensors and noise"] += t1 - t0
        t["controller"] += t2 - t1
        t["apply"] += t3 - t2
        t["physics"] += t4 - t3
        t["recording"] += t5 - t4
    t["sensors"] = t.pop("sensors and noise") - spent["noise"]
    t["noise"] = spent["noise"]
    return t, buf.targets


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--steps", type=int, default=3000)
    ap.add_argument("--out", type=Path, default=Path("out/bench"))
    args = ap.parse_args()
    cfg = EpisodeConfig(arena="box", controller="plastic", steps=args.steps, seed=0)
    run_episode(EpisodeConfig(arena="box", steps=5))  # warm the compiled kernels
    t, targets = stages(cfg)
    bare = _bare(cfg, targets)
    loop = sum(t.values())
    per_step = {k: v / args.steps * 1e6 for k, v in t.items()}
    prof = cProfile.Profile()
    prof.enable()
    run_episode(cfg)
    prof.disable()
    st = pstats.Stats(prof)
    rows = sorted(st.stats.items(), key=lambda kv: kv[1][2], reverse=True)[:12]  # type: ignore[attr-defined]
    top = [{"function": f"{Path(f).name}:{line}({name})", "calls": cc, "own_s": tt, "cumulative_s": ct}
           for (f, line, name), (cc, _, tt, ct, _) in rows]  # fmt: skip
    report = {"steps": args.steps, "us_per_control_step": per_step,
              "share": {k: v / loop for k, v in t.items()}, "loop_wall_s": loop, "bare_mj_step_wall_s": bare,
              "ratio_loop_over_bare": loop / bare, "cprofile_top_own_time": top}  # fmt: skip
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "profile.json").write_text(json.dumps(report, indent=2) + "\n")
    for k, v in sorted(per_step.items(), key=lambda kv: -kv[1]):
        print(f"{k:10s} {v:8.1f} us/step  {v / (loop / args.steps * 1e6):6.1%}")
    print(f"bare mj_step {bare / args.steps * 1e6:8.1f} us/step; loop / bare {loop / bare:.3f} (timers included)")
    for r in top[:8]:
        print(f"  {r['own_s']:7.3f} s own  {r['function']}")


if __name__ == "__main__":
    main()
