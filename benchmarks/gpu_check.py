"""The GPU engine checked in one command: what docs/gpu.md states, measured on the machine at hand.

Sections, each written to ``--out`` (JSON) as soon as it is done; one that fails records its error and the next
one runs; one that the time budget (``--budget-s``) leaves no room for is recorded as skipped:

* ``env``: versions, the device, the CPU cores;
* ``cpu_loop``: the CPU loop on this machine (one process, :func:`neurowalk.experiments.bench.physics_rates`);
* ``worlds``: the closed loop on MuJoCo Warp by number of worlds (random arenas, plastic network): control steps/s,
  the physics' share of the wall time, host and physics microseconds per world-step
  (:func:`neurowalk.experiments.bench.lockstep_rates`);
* ``determinism``: with MuJoCo Warp's deterministic execution on and off, the largest difference in a world's qpos
  between a rerun, the world beside one other and beside many, and the world run alone; the cost of the option
  (wall time of the same run, on against off);
* ``table2``: the runs of ``neurowalk figure table2 --quick --body amosii --engine warp --seeds N`` (N random
  environments x 3 networks, all worlds of one call) against CPU MuJoCo on all cores for the first environments:
  runs/s each, and how many of the shared runs have the same outcome (Table 2's two rules);
* ``tests``: the Warp tests (``pytest -m warp``) on the device (``NEUROWALK_TEST_DEVICE``).

``--tiny`` shrinks every section to a smoke run (a few worlds and control steps), for CI on Warp's CPU device.

Run: ``python benchmarks/gpu_check.py --device cuda --out gpu.json`` (under 6 minutes on an H100/H200);
``python benchmarks/gpu_check.py --device cpu --tiny --out x.json`` (CI). Exit status 1 where a section failed.
"""

from __future__ import annotations

import argparse
import os
import platform
import subprocess
import sys
import time
import traceback
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from neurowalk.fileio import write_json

ROOT = Path(__file__).resolve().parents[1]
FULL = {"worlds": (1, 64, 1024, 4096, 16384), "steps": 20, "cpu_steps": 2000, "det_steps": 25, "beside": 64,
        "cost_worlds": 1024, "table2_envs": 1000, "cpu_envs": 16, "tests": ""}  # fmt: skip
TINY = {"worlds": (1, 4), "steps": 2, "cpu_steps": 20, "det_steps": 3, "beside": 3, "cost_worlds": 4,
        "table2_envs": 2, "cpu_envs": 2, "table2_steps": 3, "tests": "independent_and_runs_repeat"}  # fmt: skip


class Check:
    """The sections' results, written to ``out`` after each; ``budget_s``: no section starts after it."""

    def __init__(self, out: Path, budget_s: float) -> None:
        self.out, self.budget_s, self.t0 = out, budget_s, time.perf_counter()
        self.result: dict[str, Any] = {"seconds": {}}
        self.failed = False

    def left(self) -> float:
        """Seconds of the budget left."""
        return self.budget_s - (time.perf_counter() - self.t0)

    def section(self, name: str, fn: Callable[[], Any], needs_s: float = 0.0) -> None:
        """Run one section and write the file (its error recorded where it raises; skipped where the budget has
        less than ``needs_s`` left)."""
        t = time.perf_counter()
        print(f"== {name} ({t - self.t0:.0f} s in)", flush=True)
        if self.left() < needs_s:
            self.result[name] = {"skipped": f"{self.left():.0f} s of the budget left, {needs_s:.0f} s needed"}
        else:
            try:
                self.result[name] = fn()
            except Exception as e:  # a failed section is recorded, the next one runs
                self.result[name] = {"error": repr(e)[:500], "traceback": traceback.format_exc()[-3000:]}
                self.failed = True
                print(self.result[name]["traceback"], flush=True)
        self.result["seconds"][name] = round(time.perf_counter() - t, 2)
        self.result["total_s"] = round(time.perf_counter() - self.t0, 1)
        write_json(self.out, self.result)


def env(device: str) -> dict[str, Any]:
    """Versions, the Warp device and the machine."""
    import mujoco
    import mujoco_warp
    import numba
    import warp as wp

    from neurowalk.sim.warp_engine import device_name

    out = {
        "python": platform.python_version(),
        "warp": wp.config.version,
        "mujoco": mujoco.__version__,
        "mujoco_warp": getattr(mujoco_warp, "__version__", "?"),
        "numba": numba.__version__,
        "numpy": np.__version__,
        "device": device,
        "device_name": device_name(device),
        "cuda_devices": wp.get_cuda_device_count(),
        "cpu_cores": os.cpu_count(),
    }
    if device == "cuda":
        smi = ["nvidia-smi", "--query-gpu=name,memory.total,driver_version", "--format=csv,noheader"]
        out["nvidia_smi"] = subprocess.run(smi, capture_output=True, text=True, timeout=30).stdout.strip()
    return out


def determinism(device: str, steps: int, beside: int, cost_worlds: int) -> dict[str, Any]:
    """Largest |qpos| difference of world 0 (a random arena) against its run alone: rerun, beside 1 other world,
    beside ``beside`` others; with the deterministic option on and off; and the option's cost in wall time."""
    from neurowalk.experiments.bench import ARENA_OPTS
    from neurowalk.sim.episode import EpisodeConfig
    from neurowalk.sim.warp_engine import WarpWorlds

    cfgs = [EpisodeConfig(arena="random", arena_opts=ARENA_OPTS, steps=steps, seed=s, engine="warp") for s in
            range(beside + 1)]  # fmt: skip

    def qpos(worlds: list[EpisodeConfig], deterministic: bool) -> np.ndarray:
        return WarpWorlds(worlds, device=device, deterministic=deterministic).run()[0].trajectory.qpos

    out: dict[str, Any] = {"control_steps": steps, "beside": beside}
    for det in (True, False):
        alone = qpos(cfgs[:1], det)
        diff = {
            "rerun": qpos(cfgs[:1], det),
            "beside_1": qpos(cfgs[:2], det),
            f"beside_{beside}": qpos(cfgs, det),
        }
        out["on" if det else "off"] = {k: float(np.abs(v - alone).max()) for k, v in diff.items()}
    many = [replace(c, seed=s) for s, c in enumerate(cfgs[:1] * cost_worlds)]
    walls = {}
    for det in (True, False):
        w = WarpWorlds(many, device=device, deterministic=det)
        w.run()  # untimed: compile, capture
        t = time.perf_counter()
        w.run()
        walls["on" if det else "off"] = time.perf_counter() - t
    out["cost"] = {"worlds": cost_worlds, "wall_s": walls, "on_over_off": walls["on"] / walls["off"]}
    return out


def table2(device: str, envs: int, cpu_envs: int, steps: int | None) -> dict[str, Any]:
    """Table 2's quick physics runs on Warp (all ``envs`` environments in one call) and, for the first ``cpu_envs``,
    on CPU MuJoCo on every core: runs/s, and the share of those runs whose outcomes agree (``steps``: shorter runs,
    for a smoke run)."""
    from neurowalk.experiments import FIGURES, Settings
    from neurowalk.experiments.study import planned
    from neurowalk.experiments.study_runs import run_all
    from neurowalk.experiments.suites.random_envs import QUICK_DURATION_S, coverage_threshold, outcome
    from neurowalk.sim.engine_interface import EngineOptions

    def configs(engine: str, n: int) -> list[Any]:
        s = Settings(quick=True, body="amosii", engine=engine, seeds=n, device=device if engine == "warp" else None)
        runs = [p.config for p in planned(FIGURES["table2"], s)]
        return [cfg.replace(steps=steps) for cfg in runs] if steps else runs

    out: dict[str, Any] = {}
    results = {}
    for engine, n, workers in (("warp", envs, 1), ("mujoco", cpu_envs, os.cpu_count() or 2)):
        cfgs = configs(engine, n)
        t = time.perf_counter()
        got = run_all(cfgs, workers=workers, progress=False, options=EngineOptions(device=device))
        results[engine] = [r.summary.to_dict() for r in got]
        wall = time.perf_counter() - t
        out[engine] = {"environments": n, "runs": len(cfgs), "wall_s": wall, "runs_per_s": len(cfgs) / wall}
    threshold = coverage_threshold(QUICK_DURATION_S)
    shared = len(results["mujoco"])
    keys = ("success", "success_coverage")
    same = sum(
        all(outcome(a, threshold)[k] == outcome(b, threshold)[k] for k in keys)
        for a, b in zip(results["warp"][:shared], results["mujoco"], strict=True)
    )
    out["agreement"] = {"runs": shared, "same_outcome": same}
    out["warp_over_cpu_runs_per_s"] = out["warp"]["runs_per_s"] / out["mujoco"]["runs_per_s"]
    return out


def tests(device: str, select: str) -> dict[str, Any]:
    """The Warp tests on ``device`` (``-k select`` where given); their exit status and last line."""
    cmd = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-m", "warp",
           "tests/sim/test_warp_engine.py", "tests/sim/test_engines.py"]  # fmt: skip
    if select:
        cmd += ["-k", select]
    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, env={**os.environ,
                          "NEUROWALK_TEST_DEVICE": device})  # fmt: skip
    lines = (done.stdout + done.stderr).strip().splitlines()
    if done.returncode != 0:
        raise RuntimeError(f"the Warp tests failed on {device}: {lines[-1] if lines else done.returncode}")
    return {"exit_status": done.returncode, "last_line": lines[-1] if lines else ""}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--device", choices=("cuda", "cpu"), default="cuda")
    ap.add_argument("--out", type=Path, required=True, metavar="FILE.json")
    ap.add_argument("--tiny", action="store_true", help="a smoke run of every section (CI, Warp's CPU device)")
    ap.add_argument("--budget-s", type=float, default=330.0, help="no section starts after this many seconds")
    args = ap.parse_args()
    p = TINY if args.tiny else FULL
    from neurowalk.experiments.bench import lockstep_rates, physics_rates

    check = Check(args.out, args.budget_s)
    check.result.update(device=args.device, tiny=args.tiny)
    check.section("env", lambda: env(args.device))
    check.section("cpu_loop", lambda: physics_rates(p["cpu_steps"], 2))
    check.section("worlds", lambda: lockstep_rates(p["worlds"], p["steps"], engine="warp", device=args.device))
    check.section("determinism", lambda: determinism(args.device, p["det_steps"], p["beside"], p["cost_worlds"]))
    check.section(
        "table2", lambda: table2(args.device, p["table2_envs"], p["cpu_envs"], p.get("table2_steps")), needs_s=30
    )
    check.section("tests", lambda: tests(args.device, p["tests"]), needs_s=20)
    print(f"wrote {args.out} in {check.result['total_s']} s", flush=True)
    return 1 if check.failed else 0


if __name__ == "__main__":
    sys.exit(main())
