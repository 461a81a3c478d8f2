"""``neurowalk baseline``: learned policies against the two neurons on held-out Table 2 environments.

.. code-block:: text

    train (each resumable, in DIR/training/METHOD/):
        neuroevo   a 4-unit recurrent network evolved by CMA-ES           (baselines/evolved_rnn.py)
        ppo        PPO, 64-64 MLP                (stable-baselines3)      (baselines/ppo.py)
        rppo       recurrent PPO, 32-unit LSTM   (sb3-contrib)
        all on neurowalk/Explore-v0 (the surrogate), episodes of 10,000 control steps, reward = area newly covered
    score (a job each, kept in the result store DIR/results.sqlite), the learned policies and the plastic (variants
    paper and original), static and Braitenberg networks alike:
        evaluate_batch on the held-out environments (reset seeds 10^9 + i), 20,000 control steps each,
        Table 2's rule (not stuck over the last 300 s), coverage, collisions
    DIR/baselines.json (everything, incl. training curves), baselines.md (the table), baselines.png (the plot)

The learned policies see exactly what the networks see (the two noisy ultrasonic distances) and act through the
same steering pair. Training budgets (env steps, wall time) are recorded with the results.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from neurowalk.envs.policy import NetworkPolicy, evaluate_batch
from neurowalk.experiments.baselines import evolved_rnn, ppo
from neurowalk.experiments.baselines.evolved_rnn import RecurrentPolicy
from neurowalk.experiments.baselines.ppo import MODEL, Sb3Policy, import_rl
from neurowalk.experiments.cma_record import import_cma
from neurowalk.experiments.study_runs import run_jobs
from neurowalk.experiments.suites.random_envs import wilson
from neurowalk.fileio import atomic_write, write_json
from neurowalk.plotting import pyplot, styled
from neurowalk.runners.stopping import deferred
from neurowalk.runners.sweep import job_kind

METHODS: tuple[str, ...] = ("neuroevo", "ppo", "rppo")
NETWORKS: tuple[str, ...] = ("plastic", "plastic-original", "static", "braitenberg")  # NAME[-VARIANT]
HELDOUT_BASE = 10**9  # reset seeds of the held-out environments: HELDOUT_BASE + i
#: Every size: (full run, ``quick`` run, largest accepted).
SIZES: dict[str, tuple[int, int, int]] = {
    "generations": (150, 3, 100_000),
    "population": (16, 6, 10_000),
    "envs": (8, 4, 100_000),
    "ppo_steps": (5_000_000, 4096, 10**10),
    "rppo_steps": (2_000_000, 2048, 10**10),
    "eval_envs": (200, 20, 100_000),
    "eval_steps": (20_000, 3000, 10**7),
    "episode_steps": (10_000, 200, 10**7),
}
FULL, QUICK, LIMITS = ({k: v[i] for k, v in SIZES.items()} for i in range(3))
#: The runner's kind of a policy's scoring: {"policy": NAME, "environments": n, "steps": T, "first_seed": s,
#: "trained": its training's env steps (None: a network), and a neuroevo's "theta", "hidden"}.
SCORE = job_kind("baseline-score")
LABELS = {
    "plastic": "plastic (2 neurons)",
    "plastic-original": "plastic, authors' code",
    "static": "static (2 neurons)",
    "braitenberg": "Braitenberg",
    "neuroevo": "evolved RNN (CMA-ES)",
    "ppo": "PPO (MLP)",
    "rppo": "recurrent PPO (LSTM)",
}


def sizes_of(quick: bool, overrides: dict[str, int]) -> dict[str, int]:
    """The run's sizes: FULL (or QUICK) with ``overrides``; ValueError names a size out of its range."""
    sizes = {**(QUICK if quick else FULL), **overrides}
    for key, value in sizes.items():
        low = 2 if key == "population" else 1
        if not low <= value <= LIMITS[key]:
            raise ValueError(f"--{key.replace('_', '-')} must be in [{low}, {LIMITS[key]:,}], got {value}")
    if sizes["generations"] * sizes["envs"] > 1_000_000:
        raise ValueError(
            f"--generations x --envs must be <= 1,000,000 (the training seeds' range), got "
            f"{sizes['generations']} x {sizes['envs']}"
        )
    return sizes


def train_method(
    method: str, folder: Path, sizes: dict[str, int], seed: int, progress: bool, log: Callable[[str], None]
) -> dict[str, Any]:
    """Train (or resume) one learned method; its record (budget, curve, weights or model path)."""
    common: dict[str, Any] = {"steps": sizes["episode_steps"], "seed": seed, "progress": progress, "log": log}
    if method == "neuroevo":
        sized = {k: sizes[k] for k in ("generations", "population", "envs")}
        return evolved_rnn.train(folder, **sized, **common)
    return ppo.train(method, folder, total_steps=sizes[f"{method}_steps"], **common)


def score(folder: str, progress: bool, spec: dict[str, Any]) -> dict[str, Any]:
    """A policy scored on the held-out environments (the runner's job, :data:`SCORE`; ``folder``: the baseline's
    DIR, whose training/NAME holds a trained model): :func:`~neurowalk.envs.policy.evaluate_batch`'s dict."""
    name = spec["policy"]
    policy = policy_of(name, spec, Path(folder) / "training" / name)
    seeds = [spec["first_seed"] + i for i in range(spec["environments"])]
    return evaluate_batch(policy, seeds, steps=spec["steps"], progress=progress)


def policy_of(name: str, record: dict[str, Any] | None, folder: Path) -> Any:
    """The batched policy of a network or a trained method."""
    if name in NETWORKS:
        network, _, variant = name.partition("-")
        return NetworkPolicy(network, variant=variant or "paper")
    assert record is not None
    if name == "neuroevo":
        return RecurrentPolicy(np.array(record["theta"]), record["hidden"])
    return Sb3Policy(name, folder / MODEL)


def check_methods(methods: Sequence[str], *, available: bool = True) -> None:
    """ValueError for an unknown method; with ``available``, the missing package's error (cma for neuroevo, the rl
    extra for ppo/rppo), before any work."""
    for m in methods:
        if m not in METHODS:
            raise ValueError(f"unknown method {m!r}; expected some of {', '.join(METHODS)}")
    if not available:
        return
    if "neuroevo" in methods:
        import_cma(evolved_rnn.CMA_MISSING)
    for m in methods:
        if m != "neuroevo":
            import_rl(m)


def run(
    out: Path,
    *,
    methods: Sequence[str] = METHODS,
    quick: bool = False,
    sizes: dict[str, int] | None = None,
    seed: int = 0,
    progress: bool = True,
    log: Callable[[str], None] = print,
) -> dict[str, Any]:
    """Train the methods, score them and the networks, write DIR/baselines.{json,md,png}; the result."""
    check_methods(methods)
    sz = sizes_of(quick, sizes or {})
    out = Path(out)
    records: dict[str, Any] = {}
    for m in methods:
        log(f"training {m}")
        records[m] = train_method(m, out / "training" / m, sz, seed, progress, log)
    seeds = [HELDOUT_BASE + i for i in range(sz["eval_envs"])]
    names = (*NETWORKS, *methods)
    specs = []
    for name in names:
        spec = {"policy": name, "environments": sz["eval_envs"], "steps": sz["eval_steps"], "first_seed": HELDOUT_BASE}
        spec["trained"] = records[name]["env_steps"] if name in records else None
        if name == "neuroevo":  # its weights name it
            spec.update(theta=list(map(float, records[name]["theta"])), hidden=records[name]["hidden"])
        specs.append(spec)
    log(f"scoring {', '.join(names)} on {len(seeds)} held-out environments, {sz['eval_steps']} steps each")
    scores = run_jobs(functools.partial(score, str(out), progress), specs, SCORE, folder=out, workers=1,
                      progress=progress, desc="scoring")  # fmt: skip
    rows = [row(name, done, records.get(name)) for name, done in zip(names, scores, strict=True)]
    result = {
        "sizes": sz,
        "seed": seed,
        "heldout_seeds": [seeds[0], seeds[-1]],
        "rows": rows,
        "training": {m: {k: v for k, v in r.items() if k != "theta"} for m, r in records.items()},
        "body": "surrogate",
        "variant": "paper, but plastic-original: original",
    }
    with deferred():  # the table and its numbers agree
        write_json(out / "baselines.json", result)
        atomic_write(out / "baselines.md", lambda tmp: Path(tmp).write_text(markdown(result)))
    plot(result, out / "baselines.png")
    return result


def row(name: str, ev: dict[str, Any], record: dict[str, Any] | None) -> dict[str, Any]:
    """One line of the table: success with its Wilson 95% interval, coverage and collisions (mean, 95% CI)."""
    n, ok = ev["environments"], ev["success"]
    cov = np.array([r["coverage"] for r in ev["runs"]])
    hits = np.array([r["contacts"] for r in ev["runs"]], dtype=float)
    half = 1.959964 / math.sqrt(n)
    lo, hi = wilson(ok, n)
    return {
        "name": name,
        "label": LABELS[name],
        "kind": "learned" if record else "network",
        "success": ok,
        "n": n,
        "rate": ok / n,
        "ci95": [lo, hi],
        "coverage_mean": float(cov.mean()),
        "coverage_ci95_half": float(half * cov.std(ddof=1)) if n > 1 else math.nan,
        "contacts_mean": float(hits.mean()),
        "contacts_ci95_half": float(half * hits.std(ddof=1)) if n > 1 else math.nan,
        "train_env_steps": record["env_steps"] if record else None,
        "train_wall_s": record["wall_s"] if record else None,
        "coverage": cov.tolist(),
    }


def markdown(result: dict[str, Any]) -> str:
    """The table of :func:`run`'s result as Markdown."""
    sz = result["sizes"]
    lines = [
        f"Held-out environments: {sz['eval_envs']} (reset seeds {result['heldout_seeds'][0]} to "
        f"{result['heldout_seeds'][1]}), {sz['eval_steps']:,} control steps each, surrogate body.",
        "",
        "| policy | success | rate (95% CI) | coverage (mean ± 95% CI) | collision overlaps per run | training |",
        "|---|---|---|---|---|---|",
    ]
    for r in result["rows"]:
        train = (
            "none (fixed rule)"
            if r["kind"] == "network"
            else (f"{r['train_env_steps']:,} env steps, {r['train_wall_s'] / 60:.1f} min")
        )
        lines.append(
            f"| {r['label']} | {r['success']}/{r['n']} | {r['rate']:.1%} ({r['ci95'][0]:.1%}-"
            f"{r['ci95'][1]:.1%}) | {r['coverage_mean']:.1%} ± {r['coverage_ci95_half']:.1%} | "
            f"{r['contacts_mean']:.0f} ± {r['contacts_ci95_half']:.0f} | {train} |"
        )
    return "\n".join(lines) + "\n"


@styled
def plot(result: dict[str, Any], path: Path) -> None:
    """Success rates with their intervals, coverage per environment, and the training curves; to ``path``."""
    plt = pyplot()
    rows = result["rows"]
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2), layout="constrained")
    ax = axes[0]
    y = np.arange(len(rows))[::-1]
    colors = ["tab:blue" if r["kind"] == "network" else "tab:orange" for r in rows]
    rates = np.array([r["rate"] for r in rows])
    err = np.array([[r["rate"] - r["ci95"][0], r["ci95"][1] - r["rate"]] for r in rows]).T
    ax.barh(y, rates, xerr=err, color=colors, capsize=3)
    ax.set_yticks(y, [r["label"] for r in rows])
    ax.set_xlim(0, 1)
    ax.set_xlabel("success (not stuck at the end), Wilson 95% CI")
    ax = axes[1]
    ax.boxplot([r["coverage"] for r in rows], positions=y, orientation="horizontal", widths=0.6)
    ax.set_yticks(y, [r["name"] for r in rows])
    ax.set_xlabel(f"coverage of free area after {result['sizes']['eval_steps']:,} steps")
    ax = axes[2]
    for m, rec in result["training"].items():
        curve = rec["curve"]
        vals = np.array([c["mean"] if isinstance(c, dict) else c for c in curve], dtype=float)
        if not len(vals):
            continue
        steps = np.linspace(rec["env_steps"] / len(vals), rec["env_steps"], len(vals))
        ax.plot(steps, vals, label=LABELS[m] + (" (population mean)" if m == "neuroevo" else ""))
    ax.set_xscale("log")
    ax.set_xlabel("training env steps")
    ax.set_ylabel(f"episode return (m² covered in {result['sizes']['episode_steps']} steps)")
    ax.legend(fontsize=8)
    fig.suptitle(f"Learned policies vs the two neurons: {rows[0]['n']} held-out Table 2 environments (surrogate)")
    atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    plt.close(fig)
