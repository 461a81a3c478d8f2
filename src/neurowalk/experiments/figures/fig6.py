"""Fig. 6: the plastic network in sixteen random environments (the first 16 of Table 2)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from neurowalk.arenas import make_arena
from neurowalk.experiments import Result
from neurowalk.experiments.stores import run_store, store_folder
from neurowalk.experiments.suites.random_envs import QUICK_STEPS, RULE, SIZE, STEPS, environments, spec
from neurowalk.plotting import draw_arena, pyplot
from neurowalk.runners.specs import normalize, result_of, spec_key, to_config
from neurowalk.sim.episode import EpisodeConfig, RunInterruptedError, run_episode, seeds

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def path_of(spec_: dict[str, Any]) -> dict[str, Any]:
    """The stored result of one run: its summary and its pose every 10th control step (a list)."""
    try:
        ep = run_episode(to_config(normalize(spec_)))
    except RunInterruptedError:
        raise KeyboardInterrupt from None  # a half run is not a result
    return {"summary": result_of(ep), "pose": ep.trajectory.pose[::10].tolist()}


def run(
    *,
    quick: bool = False,
    seed: int = 0,
    body: str = "surrogate",
    workers: int = 2,
    size: float = SIZE,
    variant: str = "paper",
    params: dict[str, float] | None = None,
    out: Path | None = None,
) -> Result:
    """The plastic network (``variant``) in the first 16 environments of Table 2 (same seeds), whole paths.

    ``out``: the folder of the resumable result store (``results.sqlite``): a rerun goes on from the runs it holds.
    """
    steps = QUICK_STEPS if quick else STEPS
    envs = environments(16, seed)
    specs = [spec(e, "plastic", steps, body, variant=variant, size=size, params=params) for e in envs]
    with store_folder(out) as folder:
        stored, _ = run_store(specs, folder, workers, fn=path_of)
    if any("pose" not in r for r in stored.values()):
        raise RuntimeError(
            f"{folder / 'results.sqlite'} holds other runs than fig6's (another figure's or sweep's "
            "store); use a fresh output folder"
        )
    runs = [{**stored[spec_key(s)], "pose": np.asarray(stored[spec_key(s)]["pose"], dtype=float)} for s in specs]
    arrays = {f"env{i}/pose": r["pose"] for i, r in enumerate(runs)}
    rows = [
        {
            **e,
            "success": not r["summary"]["trapped"],
            "coverage": r["summary"]["coverage"],
            "final_pose": r["summary"]["final_pose"],
        }
        for e, r in zip(envs, runs, strict=True)
    ]
    summary = {
        "body": body,
        "steps": steps,
        "seed": seed,
        "rule": RULE,
        "environments": rows,
        "variant": variant,
        "params": params,
        "box_size_m": size,
        "success": sum(r["success"] for r in rows),
        "pose_stride": 10,
    }
    return Result("fig6", summary, arrays)


def plot(res: Result) -> Figure:
    """4 x 4 panels: arena, path, start (red) and end (green) dots; a failure framed in red."""
    plt = pyplot()
    s = res.summary
    fig, axes = plt.subplots(4, 4, figsize=(12, 12))
    for i, (ax, env) in enumerate(zip(axes.flat, s["environments"], strict=False)):
        opts = spec(env, "plastic", 1, "surrogate", size=s.get("box_size_m", 0.6))["arena_opts"]
        arena = make_arena("random", rng=seeds(EpisodeConfig(seed=env["seed"]))[2], **opts)
        pose = res.arrays[f"env{i}/pose"]
        draw_arena(ax, arena, pose, margin=0.2)
        ax.set_title(f"{env['n_boxes']} boxes, seed {env['seed']}", fontsize=8)
        ax.tick_params(labelsize=6)
        ax.set(xlabel="", ylabel="")
        if not env["success"]:
            for side in ax.spines.values():
                side.set_edgecolor("red")
                side.set_linewidth(3)
    fig.suptitle(
        f"Fig. 6: plastic network ({s.get('variant', 'paper')}) in 16 random environments ({s['body']}, "
        f"{s['steps']} steps): "
        f"{s['success']}/16 explored; failures framed red",
        fontsize=11,
    )
    fig.tight_layout()
    return fig
