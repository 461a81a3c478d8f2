"""The networks on other robots: the dead-end suite and Table 2 on AMOSII and on a wheeled robot at two sizes.

The paper closes: "the network can be applied to other mobile robot systems for generating adaptive obstacle
avoidance". This figure tests it. The same sensory networks (plastic, static, Braitenberg; variant ``paper``) drive

- ``amosii``: the hexapod in MuJoCo, through the locomotion network (the paper's robot);
- ``wheeled``: a differential-drive robot with AMOSII's footprint, speed and rangefinders, the steering pair on its
  wheels (no locomotion network);
- ``wheeled x0.5``: the same robot at half the size and speed (distances read in its own units, so its sensors
  reach 0.2 m), in the same arenas: a small robot in a world made for a larger one.

Each body runs the dead ends of Fig. 3/5 (simple deadlock, narrow passage, corner; ``seeds`` seeds each,
:data:`~neurowalk.experiments.suites.deadends.TRAP_STEPS` steps, twice as many for the half-size robot, which is half as
fast: escaped or not) and Table 2 (the first ``environments``
random environments of table seed ``seed``, 20,000 steps, Table 2's rule, Wilson 95% intervals). All runs go
through a resumable result store in the output folder (the dead ends with their sampled paths).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from neurowalk.arenas import make_arena
from neurowalk.experiments import Result
from neurowalk.experiments.stores import run_store
from neurowalk.experiments.suites.deadends import TRAP_STEPS
from neurowalk.experiments.suites.random_envs import STEPS, environments, spec, wilson
from neurowalk.experiments.suites.real_robot import run_store_paths
from neurowalk.plotting import draw_arena, pyplot
from neurowalk.runners.specs import spec_key

if TYPE_CHECKING:
    from matplotlib.figure import Figure

BODIES: dict[str, tuple[str, dict[str, float]]] = {
    "amosii": ("amosii", {}),
    "wheeled": ("wheeled", {}),
    "wheeled x0.5": ("wheeled", {"scale": 0.5}),
}
NETWORKS = ("plastic", "static", "braitenberg")
DEAD_ENDS = ("simple-deadlock", "narrow-passage", "corner")


def _dead_end(arena: str, net: str, body: str, opts: dict[str, float], steps: int, seed: int) -> dict[str, Any]:
    out: dict[str, Any] = {"arena": arena, "controller": net, "body": body, "steps": steps, "seed": seed}
    return {**out, "body_opts": opts} if opts else out


def _slower(steps: int, opts: dict[str, float]) -> int:
    """Dead-end steps for a body at ``scale`` < 1: as many more as it is slower, so it can cover the same distance."""
    return round(steps / min(1.0, opts.get("scale", 1.0)))


def run(
    *, quick: bool = False, seed: int = 0, seeds: int | None = None, out: Path | None = None, workers: int = 2
) -> Result:
    """``seeds`` (default 10; 2 with ``quick``) runs per dead end and 5x as many Table 2 environments (default 50;
    quick: 3 environments of 1000 steps, dead ends of 600: a smoke test), per body and network, through the store in
    ``out``."""
    n = seeds if seeds is not None else (2 if quick else 10)
    if n < 1:
        raise ValueError(f"seeds must be >= 1, got {n}")
    n_env = 3 if quick and seeds is None else 5 * n
    dead_steps, t2_steps = (600, 1000) if quick else (TRAP_STEPS, STEPS)
    envs = environments(n_env, seed)
    dead = {
        (b, net, a, s): _dead_end(a, net, body, opts, _slower(dead_steps, opts), seed + s)
        for b, (body, opts) in BODIES.items()
        for net in NETWORKS
        for a in DEAD_ENDS
        for s in range(n)
    }
    table = {
        (b, net, e["seed"]): {**spec(e, net, t2_steps, body), **({"body_opts": opts} if opts else {})}
        for b, (body, opts) in BODIES.items()
        for net in NETWORKS
        for e in envs
    }
    folder = Path(out) if out is not None else Path("out/bodies")
    res = run_store_paths(list(dead.values()), folder, workers)  # the dead ends with their paths (drawn)
    res.update(run_store(list(table.values()), folder, workers)[0])  # Table 2: outcomes only
    rows, paths = [], {}
    for b in BODIES:
        for net in NETWORKS:
            escapes = {a: sum(res[spec_key(dead[(b, net, a, s)])]["escaped"] for s in range(n)) for a in DEAD_ENDS}
            t2 = [res[spec_key(table[(b, net, e["seed"])])] for e in envs]
            ok = sum(not r["trapped"] for r in t2)
            rows.append(
                {
                    "body": b,
                    "network": net,
                    "dead_ends": escapes,
                    "dead_end_runs": n,
                    "table2_success": ok,
                    "table2_environments": len(t2),
                    "table2_rate": ok / len(t2),
                    "table2_ci95": list(wilson(ok, len(t2))),
                    "table2_median_coverage": float(np.median([r["coverage"] for r in t2])),
                }
            )
            for a in DEAD_ENDS:
                paths[f"{b}|{net}|{a}"] = np.array(res[spec_key(dead[(b, net, a, 0)])]["path"])
    summary = {
        "bodies": {b: {"body": body, "body_opts": opts} for b, (body, opts) in BODIES.items()},
        "networks": list(NETWORKS),
        "variant": "paper",
        "dead_end_steps": dead_steps,
        "dead_end_steps_by_body": {b: _slower(dead_steps, opts) for b, (_, opts) in BODIES.items()},
        "table2_steps": t2_steps,
        "table2_seed": seed,
        "interval": "Wilson score interval, 95%",
        "rows": rows,
        "rule": "dead ends: escaped = left the trap's exit region; Table 2: success = not stuck over the "
        "last 300 s (3000 steps within a 0.5 m disc)",
        "store": str(folder / "results.sqlite"),
    }
    return Result("bodies", summary, arrays=paths)


def plot(res: Result) -> Figure:
    """Paths in the narrow passage per body (plastic vs static); dead-end escapes; Table 2 success with intervals."""
    plt = pyplot()
    s = res.summary
    bodies = list(s["bodies"])
    fig = plt.figure(figsize=(15, 9), layout="constrained")
    grid = fig.add_gridspec(2, len(bodies))
    for j, b in enumerate(bodies):
        ax = fig.add_subplot(grid[0, j])
        draw_arena(ax, make_arena("narrow-passage"))
        for net, color in zip(s["networks"], ("C0", "C7", "C3"), strict=True):
            p = res.arrays.get(f"{b}|{net}|narrow-passage")
            if p is not None and len(p):
                ax.plot(p[:, 0], p[:, 1], c=color, lw=1.5, label=net)
        ax.set_title(f"{b}: narrow passage, seed {s['table2_seed']}", fontsize=10)
        ax.legend(fontsize=8, loc="lower left")
    rows = s["rows"]
    labels = [f"{r['body']}\n{r['network']}" for r in rows]
    x = np.arange(len(rows))
    ax = fig.add_subplot(grid[1, 0])
    width = 0.8 / len(DEAD_ENDS)
    for k, a in enumerate(DEAD_ENDS):
        v = [r["dead_ends"][a] / r["dead_end_runs"] for r in rows]
        ax.bar(x + (k - 1) * width, v, width, label=a)
    ax.set_xticks(x, labels, fontsize=7, rotation=60)
    ax.set_ylim(0, 1.05)
    ax.set_ylabel(f"escaped (of {rows[0]['dead_end_runs']} seeds)")
    ax.legend(fontsize=8)
    ax.set_title(f"dead ends, {s['dead_end_steps']} steps (half-size robot: twice as many)", fontsize=10)
    ax = fig.add_subplot(grid[1, 1:])
    rate = np.array([r["table2_rate"] for r in rows])
    ci = np.array([r["table2_ci95"] for r in rows])
    ax.bar(x, rate, color=[f"C{bodies.index(r['body'])}" for r in rows], alpha=0.7)
    ax.errorbar(x, rate, yerr=np.maximum(0.0, [rate - ci[:, 0], ci[:, 1] - rate]), fmt="none", c="k", capsize=3)
    for i, r in enumerate(rows):
        ax.text(i, 0.02, f"{r['table2_success']}/{r['table2_environments']}", ha="center", fontsize=7)
    ax.set_xticks(x, labels, fontsize=8)
    ax.set_ylim(0, 1.05)
    ax.set_ylabel("Table 2 success (Wilson 95% interval)")
    ax.set_title(f"Table 2, {rows[0]['table2_environments']} environments, {s['table2_steps']} steps", fontsize=10)
    fig.suptitle("The same networks on other robots (paper variant)")
    return fig
