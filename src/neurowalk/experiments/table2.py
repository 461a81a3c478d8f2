"""Table 2: success and failure counts in random environments, per network (see :mod:`.random_envs`)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from neurowalk.experiments import Result, register
from neurowalk.experiments.random_envs import BOXES, NETWORKS, QUICK_STEPS, RULE, STEPS, environments, spec, wilson

if TYPE_CHECKING:
    from matplotlib.figure import Figure


@register("table2", "random environments: success and failure counts per network (paper Table 2)")
def run(*, quick: bool = False, seed: int = 0, seeds: int | None = None, body: str = "surrogate",
        out: Path | None = None, workers: int = 2, climbing: bool = False) -> Result:  # fmt: skip
    """``seeds`` environments (default 50; 10 with ``quick``) x 3 networks, through a resumable store in ``out``.

    ``climbing``: leg reflexes and backbone control on (physics body only).
    """
    from neurowalk.experiments.climbing import run_store
    from neurowalk.runners.specs import spec_key

    n = seeds if seeds is not None else (10 if quick else 50)
    if n < 1:
        raise ValueError(f"seeds (environments) must be >= 1, got {n}")
    if climbing and body != "amosii":
        raise ValueError(f"climbing needs body 'amosii' (the surrogate has no legs), got body {body!r}")
    steps = QUICK_STEPS if quick else STEPS
    envs = environments(n, seed)
    specs = [spec(e, c, steps, body, climbing) for e in envs for c in NETWORKS]
    folder = Path(out) if out is not None else Path("out/table2")
    folder.mkdir(parents=True, exist_ok=True)
    results, report = run_store(specs, folder, workers)
    rows, counts = [], {}
    for e in envs:
        row = {**e}
        for c in NETWORKS:
            r = results[spec_key(spec(e, c, steps, body, climbing))]
            row[c] = {"success": not r["trapped"], "ever_trapped": r["ever_trapped"], "coverage": r["coverage"],
                      "path_length_m": r["path_length_m"]}  # fmt: skip
        rows.append(row)
    for c in NETWORKS:
        ok = sum(r[c]["success"] for r in rows)
        lo, hi = wilson(ok, n)
        cov = float(np.median([r[c]["coverage"] for r in rows]))
        counts[c] = {"environments": n, "success": ok, "failure": n - ok, "success_rate": ok / n,
                     "success_rate_95ci": [lo, hi], "median_coverage": cov,
                     "ever_held_up_300s": sum(r[c]["ever_trapped"] for r in rows)}  # fmt: skip
    summary = {"body": body, "climbing": climbing, "steps": steps, "seed": seed, "boxes": list(BOXES), "rule": RULE,
               "interval": "Wilson score interval, 95%", "counts": counts, "environments": rows,
               "paper": {"environments": 50, "success": 49, "failure": 1},
               "store": str(folder / "results.sqlite"), "sweep": report.counts()}  # fmt: skip
    return Result("table2", summary)


def plot(res: Result) -> Figure:
    """Success counts per network with 95% intervals, and the failures by number of boxes."""
    from neurowalk.plotting import pyplot

    plt = pyplot()
    s = res.summary
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    names = list(s["counts"])
    rate = [s["counts"][c]["success_rate"] for c in names]
    ci = np.array([s["counts"][c]["success_rate_95ci"] for c in names])
    ax[0].bar(names, rate, color=["C0", "C1", "C2"][: len(names)], alpha=0.7)
    err = np.maximum(0.0, [np.array(rate) - ci[:, 0], ci[:, 1] - np.array(rate)])
    ax[0].errorbar(names, rate, yerr=err, fmt="none", c="k")
    for i, c in enumerate(names):
        k = s["counts"][c]
        ax[0].text(i, 0.03, f"{k['success']}/{k['environments']}", ha="center", fontsize=10)
    ax[0].set_ylim(0, 1.05)
    ax[0].set_ylabel("success rate (95% interval)")
    on = " with climbing modules" if s.get("climbing") else ""
    ax[0].set_title(f"Table 2 on {s['body']}{on}: {s['counts'][names[0]]['environments']} random environments, "
                    f"{s['steps']} steps (paper: plastic 49/50)", fontsize=9)  # fmt: skip
    boxes = np.arange(s["boxes"][0], s["boxes"][1] + 1)
    for i, c in enumerate(names):
        fails = [sum(1 for r in s["environments"] if r["n_boxes"] == b and not r[c]["success"]) for b in boxes]
        ax[1].plot(boxes, fails, "o-", c=f"C{i}", label=c)
    ax[1].set_xlabel("boxes in the environment")
    ax[1].set_ylabel("failures")
    ax[1].legend(fontsize=8)
    ax[1].set_title("failures by clutter", fontsize=9)
    fig.text(0.01, 0.01, s["rule"], fontsize=7)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    return fig
