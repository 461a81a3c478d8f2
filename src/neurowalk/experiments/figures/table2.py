"""Table 2: success and failure counts in random environments, per network (see
:mod:`neurowalk.experiments.suites.random_envs`).

Rows: the plastic network as the paper's Eq. 1-6 read (``plastic-paper``) and as the authors' code runs it
(``plastic-original``), beside the static and Braitenberg networks (``plastic-tuned`` too where the tuned
variant is shipped, ``plastic-params`` for a ``--params`` file). Each row: successes, environments, rate
and Wilson 95% interval; the paper's 49/50 with its own interval; each failure's class.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from tqdm import tqdm

from neurowalk.body.registry import bodies_where, body_info
from neurowalk.experiments import Result
from neurowalk.experiments.stores import run_store
from neurowalk.experiments.suites.random_envs import (
    BOXES,
    FAILURE_RULE,
    QUICK_STEPS,
    ROWS,
    RULE,
    SIZE,
    STEPS,
    environments,
    failure_class,
    spec,
    wilson,
)
from neurowalk.neural.variants import variant_names
from neurowalk.plotting import pyplot
from neurowalk.runners.local import run_unordered
from neurowalk.runners.specs import run_spec, spec_key
from neurowalk.sim.config import DEFAULT_ENGINE, engine_refusal
from neurowalk.sim.engine import EngineOptions

if TYPE_CHECKING:
    from matplotlib.figure import Figure

PAPER = {"environments": 50, "success": 49, "failure": 1}
CLASSES = ("latched spin", "wedged", "other")


def rows(variant: str | None = None, params: dict[str, float] | None = None) -> dict[str, dict[str, Any]]:
    """Table rows: name -> {"controller", "variant", "params"}; extra rows for a named variant or a params file."""
    out = {name: {"controller": c, "variant": v, "params": None} for name, (c, v) in ROWS.items()}
    if "tuned" in variant_names():
        out["plastic-tuned"] = {"controller": "plastic", "variant": "tuned", "params": None}
    if params:
        out["plastic-params"] = {"controller": "plastic", "variant": variant or "original", "params": params}
    elif variant is not None and f"plastic-{variant}" not in out:
        raise ValueError(f"unknown variant {variant!r}; expected one of {', '.join(variant_names())}")
    return out


def run(
    *,
    quick: bool = False,
    seed: int = 0,
    seeds: int | None = None,
    body: str = "surrogate",
    out: Path | None = None,
    workers: int = 2,
    climbing: bool = False,
    size: float = SIZE,
    variant: str | None = None,
    params: dict[str, float] | None = None,
    engine: str = DEFAULT_ENGINE,
    device: str | None = None,
) -> Result:
    """``seeds`` environments (default 50; 10 with ``quick``) x the rows, through a resumable store in ``out``.

    ``size``: box side (m; the authors' 1 m by default). ``climbing``: leg reflexes and backbone control on
    (physics body only). ``variant``/``params``: an extra plastic row (``--params FILE``). A physics body with a
    calibrated surrogate (AMOSII: ``surrogate``, wheeled: ``surrogate-wheeled``) runs it beside, environment for
    environment (``surrogate_agreement``). ``engine``: ``warp`` runs the AMOSII physics rows on MuJoCo Warp, every
    environment a world of one model (``--engine warp``; a GPU makes 1000 environments in physics practical), on
    ``device``.
    """
    n = seeds if seeds is not None else (10 if quick else 50)
    if n < 1:
        raise ValueError(f"seeds (environments) must be >= 1, got {n}")
    info = body_info(body)
    if engine not in info.engines:
        raise ValueError(engine_refusal(engine, body, climbing))
    if climbing and not info.climbs:
        climbers = ", ".join(repr(b) for b in bodies_where(lambda b: b.climbs))
        raise ValueError(f"climbing needs body {climbers} (the surrogate has no legs), got body {body!r}")
    steps = QUICK_STEPS if quick else STEPS
    table = rows(variant, params)
    envs = environments(n, seed)

    def spec_of(e: dict[str, Any], r: dict[str, Any], b: str) -> dict[str, Any]:
        s = spec(
            e, r["controller"], steps, b, climbing and b == body, variant=r["variant"], size=size, params=r["params"]
        )
        return {**s, "engine": engine} if b == body else s  # the physics rows on the engine; a surrogate: its loop

    surrogate = body_info(body).surrogate  # its own surrogate beside a physics body (amosii, wheeled)
    bodies = [body] if surrogate is None else [body, surrogate]
    specs = [spec_of(e, r, b) for b in bodies for e in envs for r in table.values()]
    folder = Path(out) if out is not None else Path("out/table2")
    folder.mkdir(parents=True, exist_ok=True)
    results, report = run_store(specs, folder, workers, options=EngineOptions(device=device))
    keys = [spec_key(s) for s in specs]  # in the order of specs: body, environment, row
    _reclassify(results, specs, keys, workers)
    by_body = {b: keys[i * len(envs) * len(table) : (i + 1) * len(envs) * len(table)] for i, b in enumerate(bodies)}

    def outcomes(b: str) -> list[dict[str, Any]]:
        """Per environment, each row's outcome on body ``b``."""
        k = iter(by_body[b])
        return [{name: _outcome(results[next(k)]) for name in table} for _ in envs]

    env_rows = [{**e, **o} for e, o in zip(envs, outcomes(body), strict=True)]
    counts = {name: {**r, **_count(env_rows, name)} for name, r in table.items()}
    agreement = None
    if surrogate is not None:
        sur = outcomes(surrogate)
        agreement = {name: _agreement(env_rows, sur, name) for name in table}
    paper = {
        **PAPER,
        "success_rate": PAPER["success"] / PAPER["environments"],
        "success_rate_95ci": list(wilson(PAPER["success"], PAPER["environments"])),
    }
    summary = {
        "body": body,
        "engine": engine,
        "climbing": climbing,
        "steps": steps,
        "seed": seed,
        "boxes": list(BOXES),
        "box_size_m": size,
        "rule": RULE,
        "failure_rule": FAILURE_RULE,
        "interval": "Wilson score interval, 95%",
        "counts": counts,
        "environments": env_rows,
        "paper": paper,
        "store": str(folder / "results.sqlite"),
        "sweep": report.counts(),
        "surrogate": surrogate,
        "surrogate_agreement": agreement,
    }
    return Result("table2", summary)


def _reclassify(
    results: dict[str, dict[str, Any]], specs: list[dict[str, Any]], keys: list[str], workers: int = 2
) -> None:
    """Rerun (deterministic, on ``workers`` processes) the failed runs whose stored summary predates the class keys.

    Stores written before the failure classes existed lack ``wedged_periods`` and a blind share by
    :data:`~neurowalk.metrics.BLIND_M`; the rerun gives the same run, bit for bit, with them.
    """
    stale = [(s, k) for s, k in zip(specs, keys, strict=True) if _predates_classes(results[k])]
    old, old_keys = [s for s, _ in stale], [k for _, k in stale]
    with tqdm(total=len(old), unit="run", desc="reclassify", disable=not old, mininterval=0.5) as bar:
        for done in run_unordered(run_spec, old, workers=workers):
            if done.error is not None:
                raise done.error
            results[old_keys[done.index]] = done.value
            bar.update(1)


def _predates_classes(res: dict[str, Any]) -> bool:
    """A failed run stored before the failure classes existed (no ``wedged_periods``)."""
    return bool(res["trapped"]) and "wedged_periods" not in res


def _outcome(res: dict[str, Any]) -> dict[str, Any]:
    """One run's Table 2 outcome from its summary."""
    return {
        "success": not res["trapped"],
        "failure_class": failure_class(res),
        "ever_held_up_300s": res["ever_trapped"],
        "ever_held_up_1000s": res["ever_held_up_1000s"],
        "coverage": res["coverage"],
        "path_length_m": res["path_length_m"],
        "end_turn_share": res["end_turn_share"],
        "end_blind_share": res["end_blind_share"],
    }


def _agreement(physics: list[dict[str, Any]], surrogate: list[dict[str, Any]], name: str) -> dict[str, Any]:
    """Environment by environment: does the surrogate give row ``name`` the physics outcome?"""
    pairs = [(x["seed"], x[name]["success"], s[name]["success"]) for x, s in zip(physics, surrogate, strict=True)]
    return {
        "environments": len(pairs),
        "same_outcome": sum(p == s for _, p, s in pairs),
        "surrogate_success": sum(s for _, _, s in pairs),
        "differ": [{"seed": seed, "physics": p, "surrogate": s} for seed, p, s in pairs if p != s],
    }


def _count(env_rows: list[dict[str, Any]], name: str) -> dict[str, Any]:
    """Counts of one row over the environments: successes, rate, Wilson interval, failure classes."""
    n = len(env_rows)
    ok = sum(x[name]["success"] for x in env_rows)
    return {
        "environments": n,
        "success": ok,
        "failure": n - ok,
        "success_rate": ok / n,
        "success_rate_95ci": list(wilson(ok, n)),
        "failure_classes": {c: sum(x[name]["failure_class"] == c for x in env_rows) for c in CLASSES},
        "median_coverage": float(np.median([x[name]["coverage"] for x in env_rows])),
        "ever_held_up_300s": sum(x[name]["ever_held_up_300s"] for x in env_rows),
        "ever_held_up_1000s": sum(x[name]["ever_held_up_1000s"] for x in env_rows),
    }


def plot(res: Result) -> Figure:
    """Success rates with 95% intervals beside the paper's; failures by clutter and by class."""
    plt = pyplot()
    s = res.summary
    fig, ax = plt.subplots(1, 3, figsize=(16, 4.8), gridspec_kw={"width_ratios": [1.4, 1, 1]})
    names = list(s["counts"])
    rate = np.array([s["counts"][c]["success_rate"] for c in names])
    ci = np.array([s["counts"][c]["success_rate_95ci"] for c in names])
    x = np.arange(len(names))
    ax[0].bar(x, rate, color=[f"C{i}" for i in range(len(names))], alpha=0.7)
    ax[0].errorbar(x, rate, yerr=np.maximum(0.0, [rate - ci[:, 0], ci[:, 1] - rate]), fmt="none", c="k", capsize=4)
    paper = s.get("paper", PAPER)
    if "success_rate_95ci" in paper:
        lo, hi = paper["success_rate_95ci"]
        ax[0].axhspan(lo, hi, color="0.85", zorder=0, label=f"paper 49/50, 95% interval {lo:.1%}-{hi:.1%}")
        ax[0].axhline(paper["success_rate"], c="0.5", lw=1, zorder=0)
        ax[0].legend(fontsize=8, loc="upper right")
    for i, c in enumerate(names):
        k = s["counts"][c]
        ax[0].text(i, 0.03, f"{k['success']}/{k['environments']}\n{k['success_rate']:.1%}", ha="center", fontsize=9)
    agree = s.get("surrogate_agreement") or {}
    who = s.get("surrogate") or "surrogate"
    labels = [
        f"{c}\n{who} agrees {agree[c]['same_outcome']}/{agree[c]['environments']}" if c in agree else c for c in names
    ]
    ax[0].set_xticks(x, labels, fontsize=7 if agree else 8)
    ax[0].set_ylim(0, 1.05)
    ax[0].set_ylabel("success rate (Wilson 95% interval)")
    on = " with climbing modules" if s.get("climbing") else ""
    size = s.get("box_size_m", 0.6)
    ax[0].set_title(
        f"Table 2 on {s['body']}{on}: {s['counts'][names[0]]['environments']} random environments, "
        f"{size:g} m boxes, {s['steps']} steps",
        fontsize=9,
    )
    boxes = np.arange(s["boxes"][0], s["boxes"][1] + 1)
    for i, c in enumerate(names):
        fails = [sum(1 for r in s["environments"] if r["n_boxes"] == b and not r[c]["success"]) for b in boxes]
        ax[1].plot(boxes, fails, "o-", c=f"C{i}", label=c, ms=3)
    ax[1].set_xlabel("boxes in the environment")
    ax[1].set_ylabel("failures")
    ax[1].legend(fontsize=8)
    ax[1].set_title("failures by clutter", fontsize=9)
    bottom = np.zeros(len(names))
    for j, cls in enumerate(CLASSES):
        v = np.array([s["counts"][c].get("failure_classes", {}).get(cls, 0) for c in names])
        ax[2].bar(x, v, bottom=bottom, color=["C3", "C1", "0.6"][j], label=cls)
        bottom += v
    ax[2].set_xticks(x, names, fontsize=8)
    ax[2].set_ylabel("failures")
    ax[2].legend(fontsize=8)
    ax[2].set_title("failures by class", fontsize=9)
    fig.text(0.01, 0.01, s["rule"] + "\n" + s.get("failure_rule", ""), fontsize=7)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    return fig
