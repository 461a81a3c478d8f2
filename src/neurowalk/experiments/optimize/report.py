"""What ``neurowalk optimize`` reports: the best candidate, the held-out table, best.json and the plots.

Files written into the output folder (all atomically):

* ``best.json``: a params file (:func:`~neurowalk.neural.variants.read_params_file` reads it):
  ``{"variant": base, "params": {field: value}, "found_by": {...}}``, ``found_by`` holding the command that
  reproduces it, the seeds, sizes, search space, fitness rule and history, and the held-out rates;
* ``heldout.json``: the best candidate, the base variant and the paper variant on the held-out environments
  (successes, rate, Wilson 95% interval, failure classes, paired counts, every environment's outcome);
* ``history.json``: every candidate of every generation (values, normalised point, fitness);
* ``convergence.png``: best and mean fitness per generation, and the parameters' trajectories.

Nothing here depends on the machine (no wall times, no paths), so the same seed gives the same files.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from neurowalk import __version__
from neurowalk.experiments.optimize.settings import Sizes
from neurowalk.experiments.optimize.space import FITNESS_RULE, Dim
from neurowalk.experiments.suites import deadends
from neurowalk.experiments.suites.random_envs import FAILURE_RULE, RULE, failure_class, wilson
from neurowalk.fileio import atomic_write, write_json
from neurowalk.plotting import look, pyplot, styled

if TYPE_CHECKING:
    from matplotlib.figure import Figure


@dataclass
class Search:
    """What a search produced: ``best`` (the best.json contents), ``heldout``, ``history`` and run counts."""

    best: dict[str, Any]
    heldout: dict[str, Any]
    history: list[dict[str, Any]]  # per generation: every candidate's values and fitness
    base_training: dict[str, Any]  # the base variant's fitness on the training set
    space: tuple[Dim, ...]
    runs_computed: int  # runs computed by this call (0 when everything was in the store)
    runs_skipped: int  # runs found in the store


def best_candidate(history: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """The candidate with the lowest CMA-ES score over all generations (the first one on a tie).

    Returns:
        {"generation", "index" (in its generation), "params", "x", "fitness" (its fitness dict)}.
    """
    best: dict[str, Any] | None = None
    for rec in history:
        for i, f in enumerate(rec["fitness"]):
            if best is None or f["score"] < best["fitness"]["score"]:
                best = {
                    "generation": rec["generation"],
                    "index": i,
                    "params": dict(rec["params"][i]),
                    "x": list(rec["x"][i]),
                    "fitness": dict(f),
                }
    if best is None:
        raise ValueError("no generation was evaluated")
    return best


def stats(rec: Mapping[str, Any]) -> dict[str, Any]:
    """A generation's best and mean fitness and its number of feasible candidates."""
    fits = [f["fitness"] for f in rec["fitness"]]
    return {"best": max(fits), "mean": float(np.mean(fits)), "feasible": sum(f["feasible"] for f in rec["fitness"])}


def generation_line(
    records: Sequence[Mapping[str, Any]], generations: int, base: Mapping[str, Any], computed: int, wall_s: float
) -> str:
    """``generation 3/16: best 0.912 mean 0.861 feasible 7/8; best so far 0.925 (base 0.850); 784 runs in 95 s``."""
    rec = records[-1]
    st = stats(rec)
    so_far = best_candidate(records)["fitness"]["fitness"]
    return (
        f"generation {rec['generation']}/{generations}: best {st['best']:.3f} mean {st['mean']:.3f} "
        f"feasible {st['feasible']}/{len(rec['fitness'])}; best so far {so_far:.3f} (base {base['fitness']:.3f}); "
        f"sigma {rec['sigma']:.3f}; {computed} runs in {wall_s:.0f} s"
    )


def heldout_rows(variant: str, params: Mapping[str, float]) -> dict[str, tuple[str, dict[str, float] | None]]:
    """The validated networks: name -> (variant, params): ``best``, ``base`` (unless it is the paper's), ``paper``."""
    rows: dict[str, tuple[str, dict[str, float] | None]] = {"best": (variant, dict(params))}
    if variant != "paper":
        rows["base"] = (variant, None)
    rows["paper"] = ("paper", None)
    return rows


def heldout_table(
    rows: Mapping[str, tuple[str, dict[str, float] | None]],
    envs: Sequence[Mapping[str, Any]],
    runs: Mapping[str, Sequence[Mapping[str, Any]]],
    table_seed: int,
    steps: int,
) -> dict[str, Any]:
    """The held-out table: per network successes, rate and Wilson 95% interval; paired counts against ``best``."""
    n = len(envs)
    ok = {name: [not r["trapped"] for r in runs[name]] for name in rows}
    table: dict[str, Any] = {}
    for name, (variant, params) in rows.items():
        classes = [failure_class(dict(r)) for r in runs[name]]
        k = int(sum(ok[name]))
        table[name] = {
            "variant": variant,
            "params": params,
            "success": k,
            "failure": n - k,
            "environments": n,
            "success_rate": k / n,
            "success_rate_95ci": list(wilson(k, n)),
            "failure_classes": {c: classes.count(c) for c in ("latched spin", "wedged", "other")},
            "median_coverage": float(np.median([r["coverage"] for r in runs[name]])),
        }
    paired = {
        name: {
            "best_only": sum(a and not b for a, b in zip(ok["best"], ok[name], strict=True)),
            f"{name}_only": sum(b and not a for a, b in zip(ok["best"], ok[name], strict=True)),
        }
        for name in rows
        if name != "best"
    }
    per_env = [{**e, **{name: ok[name][i] for name in rows}} for i, e in enumerate(envs)]
    return {
        "environments": n,
        "table_seed": table_seed,
        "run_seeds": [envs[0]["seed"], envs[-1]["seed"]],
        "steps": steps,
        "body": "surrogate",
        "box_size_m": 1.0,
        "rule": RULE,
        "failure_rule": FAILURE_RULE,
        "interval": "Wilson score interval, 95%",
        "rows": table,
        "paired": paired,
        "per_environment": per_env,
    }


def command(search: Search, sizes: Sizes, seed: int, train_seed: int, sigma0: float, variant: str) -> str:
    """The command line that reproduces the search (backend, workers and output folder do not change results)."""
    parts = ["neurowalk optimize", f"--variant {variant}", f"--fields {','.join(d.name for d in search.space)}"]
    parts += [f"--param {d.name}={d.lo:g}:{d.hi:g}" for d in search.space]
    parts += [f"--{name.replace('_', '-')} {v}" for name, v in asdict(sizes).items()]  # the Sizes in field order
    parts += [
        f"--seed {seed}",
        f"--train-seed {train_seed}",
        f"--heldout-seed {search.heldout['table_seed']}",
        f"--sigma0 {sigma0:g}",
    ]
    return " ".join(parts)


def best_json(
    search: Search,
    best: Mapping[str, Any],
    sizes: Sizes,
    *,
    seed: int,
    train_seed: int,
    sigma0: float,
    stopped: Mapping[str, Any] | None,
    variant: str,
) -> dict[str, Any]:
    """The contents of best.json: the params file of the best candidate with how it was found."""
    h = search.heldout
    hist = []
    so_far = -np.inf
    for rec in search.history:
        st = stats(rec)
        so_far = max(so_far, st["best"])
        hist.append(
            {
                "generation": rec["generation"],
                **st,
                "best_so_far": so_far,
                "sigma": rec["sigma"],
                "mean_params": rec["mean"],
            }
        )
    found_by = {
        "command": command(search, sizes, seed, train_seed, sigma0, variant),
        "method": "CMA-ES (cma package), normalised space: log scale for the rates with lo > 0, linear otherwise",
        "seed": seed,
        "generations": len(search.history),
        "population": sizes.population,
        "sigma0": sigma0,
        "stopped_early": dict(stopped) if stopped and stopped["generation"] <= len(search.history) else None,
        "space": {d.name: d.describe() for d in search.space},
        "fitness_rule": FITNESS_RULE,
        "body": "surrogate",
        "steps": sizes.steps,
        "training": {
            "environments": sizes.environments,
            "table_seed": train_seed,
            "run_seeds": [train_seed, train_seed + sizes.environments - 1],
            "box_size_m": 1.0,
        },
        "deadends": {
            "geometries": {k: {"arena": a, "options": o} for k, (a, o) in deadends.VARIANTS.items()},
            "seeds": sizes.deadend_seeds,
            "steps": deadends.TRAP_STEPS,
            "network": "plastic",
        },
        "heldout": {
            "environments": h["environments"],
            "table_seed": h["table_seed"],
            "run_seeds": h["run_seeds"],
            "rates": {
                k: {
                    "success": r["success"],
                    "success_rate": r["success_rate"],
                    "success_rate_95ci": r["success_rate_95ci"],
                    "variant": r["variant"],
                }
                for k, r in h["rows"].items()
            },
        },
        "best": {"generation": best["generation"], "index": best["index"], **best["fitness"]},
        "base_training": dict(search.base_training),
        "history": hist,
        "neurowalk_version": __version__,
    }
    return {"variant": variant, "params": dict(best["params"]), "found_by": found_by}


def write(search: Search, folder: Path) -> list[Path]:
    """Write best.json, heldout.json, history.json and convergence.png into ``folder``; return their paths."""
    paths = [folder / n for n in ("best.json", "heldout.json", "history.json", "convergence.png")]
    write_json(paths[0], search.best)
    write_json(paths[1], search.heldout)
    write_json(paths[2], {"space": {d.name: d.describe() for d in search.space}, "generations": search.history})
    fig = plot(search)
    with look():
        atomic_write(paths[3], lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    return paths


def final_line(search: Search, folder: Path) -> str:
    """``held-out (200 environments): best 0.930 [0.887, 0.958], base 0.870 [...], paper ...; wrote ...``."""
    rows = search.heldout["rows"]
    rates = ", ".join(
        f"{k} {r['success_rate']:.3f} [{r['success_rate_95ci'][0]:.3f}, {r['success_rate_95ci'][1]:.3f}]"
        for k, r in rows.items()
    )
    return (
        f"held-out ({search.heldout['environments']} environments, Wilson 95%): {rates}; "
        f"{search.runs_computed} runs computed, {search.runs_skipped} from the store; "
        f"wrote {folder / 'best.json'}, heldout.json, history.json, convergence.png"
    )


@styled
def plot(search: Search) -> Figure:
    """Left: best, mean and best-so-far fitness per generation (base on the training set dashed). Right: the
    distribution mean of every field per generation (lines) and each generation's best candidate (dots), in
    normalised coordinates (0 = lo, 1 = hi)."""
    plt = pyplot()
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    g = np.array([r["generation"] for r in search.history])
    fits = [np.array([f["fitness"] for f in r["fitness"]]) for r in search.history]
    best = np.array([f.max() for f in fits])
    ax[0].plot(g, best, "o-", label="best of generation")
    ax[0].plot(g, [f.mean() for f in fits], "s-", label="mean of generation")
    ax[0].plot(g, np.maximum.accumulate(best), "k-", lw=1, label="best so far")
    ax[0].axhline(search.base_training["fitness"], ls="--", c="0.5", label="base variant")
    ax[0].set(xlabel="generation", ylabel="fitness (training success rate; < 0: a dead end not escaped)")
    ax[0].legend(fontsize=8)
    ax[0].set_title(f"CMA-ES, {len(fits[0])} candidates per generation", fontsize=9)
    mean_x = np.array([r["mean_x"] for r in search.history])
    for j, d in enumerate(search.space):
        ax[1].plot(g, mean_x[:, j], "-", c=f"C{j}", label=f"{d.name} [{d.lo:g}, {d.hi:g}] {d.scale}")
        top = [r["x"][int(np.argmin([f["score"] for f in r["fitness"]]))][j] for r in search.history]
        ax[1].plot(g, top, "o", c=f"C{j}", ms=3)
    ax[1].set(xlabel="generation", ylabel="normalised value (0 = lo, 1 = hi)", ylim=(-0.05, 1.05))
    ax[1].legend(fontsize=7)
    ax[1].set_title("parameters: distribution mean (lines), generation's best (dots)", fontsize=9)
    for a in ax:
        a.xaxis.get_major_locator().set_params(integer=True)
    fig.tight_layout()
    return fig
