"""Fig. 6: the plastic network in sixteen random environments (the first 16 of Table 2), each marked by its outcome.

As the paper's figure: red, failed (stuck at the end, Table 2's not-stuck rule); green, a success that faced a
confined space; blue, a success that faced a trap; by the rule of
:mod:`neurowalk.experiments.suites.confinement` (the arena's boxes and the trunk's path; its numbers are in the
json and on the picture). A success that faced neither is left unframed. Each environment also gets its coverage
and Table 2's coverage rule.
"""

from __future__ import annotations

import textwrap
from collections import Counter
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from neurowalk.experiments import Result
from neurowalk.experiments.stores import run_store, store_folder
from neurowalk.experiments.suites import confinement
from neurowalk.experiments.suites.random_envs import (
    COVERAGE_CELL_M,
    DURATION_S,
    QUICK_DURATION_S,
    RULE,
    SIZE,
    STUCK_S,
    arena_of,
    check_rate,
    coverage_rule,
    coverage_threshold,
    environments,
    spec,
    steps_at,
)
from neurowalk.plotting import draw_arena, pyplot
from neurowalk.runners.specs import normalize, result_of, spec_key, to_config
from neurowalk.sim.episode import RunInterruptedError, run_episode

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: Frame colour of each class (the paper's red, green and blue squares; a plain success unframed).
COLOURS = {"failed": "red", "passed a confined space": "green", "escaped a trap": "blue", "plain success": None}


def pose_stride(control_hz: float) -> int:
    """Control steps between the kept poses: one a second of simulated time (10 at 10 Hz)."""
    return max(1, round(control_hz))


def path_of(spec_: dict[str, Any]) -> dict[str, Any]:
    """The stored result of one run: its summary and its pose every second of simulated time (a list)."""
    try:
        ep = run_episode(to_config(normalize(spec_)))
    except RunInterruptedError:
        raise KeyboardInterrupt from None  # a half run is not a result
    stride = pose_stride(float(spec_.get("control_hz", 10.0)))
    return {"summary": result_of(ep), "pose": ep.trajectory.pose[::stride].tolist()}


def specs(
    *,
    quick: bool = False,
    seed: int = 0,
    body: str = "surrogate",
    size: float = SIZE,
    variant: str = "paper",
    params: dict[str, float] | None = None,
    control_hz: float = 10.0,
) -> list[dict[str, Any]]:
    """The sixteen run specs (ValueError where ``body`` cannot run at ``control_hz``: a surrogate runs at 10 Hz)."""
    check_rate(body, control_hz)
    steps = steps_at(QUICK_DURATION_S if quick else DURATION_S, control_hz)
    envs = environments(16, seed)
    return [
        spec(e, "plastic", steps, body, variant=variant, size=size, params=params, control_hz=control_hz) for e in envs
    ]


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
    control_hz: float = 10.0,
) -> Result:
    """The plastic network (``variant``) in the first 16 environments of Table 2 (same seeds), whole paths.

    ``out``: the folder of the resumable result store (``results.sqlite``): a rerun goes on from the runs it holds.
    ``control_hz``: the control rate (a physics body; the surrogate runs at its 10 Hz only); every run lasts the
    same simulated time (2000 s, quick 500 s) whatever the rate.
    """
    run_specs = specs(
        quick=quick, seed=seed, body=body, size=size, variant=variant, params=params, control_hz=control_hz
    )
    envs = environments(16, seed)
    duration = QUICK_DURATION_S if quick else DURATION_S
    threshold = coverage_threshold(duration)
    stride = pose_stride(control_hz)
    with store_folder(out) as folder:
        stored, _ = run_store(run_specs, folder, workers, fn=path_of)
    if any("pose" not in r for r in stored.values()):
        raise RuntimeError(
            f"{folder / 'results.sqlite'} holds other runs than fig6's (another figure's or sweep's "
            "store); use a fresh output folder"
        )
    runs = [{**stored[spec_key(s)], "pose": np.asarray(stored[spec_key(s)]["pose"], dtype=float)} for s in run_specs]
    arrays = {f"env{i}/pose": r["pose"] for i, r in enumerate(runs)}
    end_rows = round(STUCK_S * control_hz / stride)  # the kept poses of the last 300 s
    rows = []
    for e, s, r in zip(envs, run_specs, runs, strict=True):
        success = not r["summary"]["trapped"]
        faced = confinement.classify(arena_of(s), r["pose"], success, end_rows=end_rows)
        rows.append(
            {
                **e,
                "success": success,
                "outcome": faced.pop("class"),
                "coverage": r["summary"]["coverage"],
                "success_coverage": r["summary"]["coverage"] >= threshold,
                "final_pose": r["summary"]["final_pose"],
                **faced,
            }
        )
    classes = Counter(r["outcome"] for r in rows)
    summary = {
        "body": body,
        "steps": run_specs[0]["steps"],
        "control_hz": control_hz,
        "duration_s": duration,
        "seed": seed,
        "rule": RULE,
        "coverage_rule": coverage_rule(duration),
        "coverage_threshold": threshold,
        "coverage_cell_m": COVERAGE_CELL_M,
        "class_rule": confinement.CLASS_RULE,
        "class_numbers": dict(confinement.RULE_NUMBERS),
        "classes": {c: classes.get(c, 0) for c in confinement.CLASSES},
        "environments": rows,
        "variant": variant,
        "params": params,
        "box_size_m": size,
        "success": sum(r["success"] for r in rows),
        "success_coverage": sum(r["success_coverage"] for r in rows),
        "pose_stride": stride,
        "pose_stride_s": stride / control_hz,
    }
    return Result("fig6", summary, arrays)


def plot(res: Result) -> Figure:
    """4 x 4 panels: arena, path, start (red) and end (green) dots; framed by outcome: failed red, a confined space
    passed green, a trap escaped blue (the point it left marked by a ring of that colour)."""
    plt = pyplot()
    s = res.summary
    fig, axes = plt.subplots(4, 4, figsize=(12, 12.8))
    for i, (ax, env) in enumerate(zip(axes.flat, s["environments"], strict=False)):
        arena = arena_of(spec(env, "plastic", 1, "surrogate", size=s.get("box_size_m", SIZE)))
        pose = res.arrays[f"env{i}/pose"]
        draw_arena(ax, arena, pose, margin=0.2)
        cls = env.get("outcome", "plain success" if env["success"] else "failed")
        cov = f", coverage {env['coverage']:.1%}" if env.get("coverage") is not None else ""
        ax.set_title(f"{env['n_boxes']} boxes, seed {env['seed']}{cov}\n{cls}", fontsize=8)
        ax.tick_params(labelsize=6)
        ax.set(xlabel="", ylabel="")
        for key, colour in (("left_trap", "blue"), ("left_confined", "green")):
            if env.get(key) is not None:
                ax.plot(*env[key], "o", mfc="none", mec=colour, mew=2, ms=12, zorder=6)
        colour = COLOURS.get(cls)
        if colour is not None:
            for side in ax.spines.values():
                side.set_edgecolor(colour)
                side.set_linewidth(3)
    counts = s.get("classes", {})
    hz = s.get("control_hz", 10.0)
    fig.suptitle(
        f"Fig. 6: plastic network ({s.get('variant', 'paper')}) in 16 random environments ({s['body']}, "
        f"{s['steps']} steps at {hz:g} Hz): {s['success']}/16 not stuck at the end"
        + (f", {s['success_coverage']}/16 by coverage" if "success_coverage" in s else "")
        + "\nframes: red failed"
        + (
            f" ({counts.get('failed', 0)}), green confined space passed ({counts.get('passed a confined space', 0)}),"
            f" blue trap escaped ({counts.get('escaped a trap', 0)}), none: plain success "
            f"({counts.get('plain success', 0)})"
            if counts
            else ""
        ),
        fontsize=10,
    )
    notes = [s["rule"]]
    if "coverage_rule" in s:
        notes.append(s["coverage_rule"])
    if "class_rule" in s:
        notes.append("classes: " + s["class_rule"])
    fig.text(0.01, 0.005, "\n".join(_wrap(n, 190) for n in notes), fontsize=6.5, va="bottom")
    fig.tight_layout(rect=(0, 0.075, 1, 1))
    return fig


def _wrap(text: str, width: int) -> str:
    """``text`` broken into lines of at most about ``width`` characters, at spaces."""
    return "\n".join(textwrap.wrap(text, width))
