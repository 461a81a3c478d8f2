"""Sensitivity to invented geometry: the paper's outcomes in its dead ends and on its climbing track, with the one
invented dimension each hinges on scaled by 0.8, 1.0 and 1.2.

The paper gives its arenas in pictures and words, not in metres; neurowalk invented their numbers
(:mod:`neurowalk.arenas`, docs/paper-vs-code.md). Each case of :data:`CASES` names a claim's arena, the
dimension it turns on and the outcome the paper shows for each network:

* the simple dead end's depth (Fig. 3A, 5A): the static and the plastic network escape;
* the narrow passage's gap between its end obstacles, and its depth (Fig. 3B, 5B, 8): the plastic network
  escapes, the static one stays trapped;
* the climbing track's distance from the first step to the wall on its platform (Fig. 10): the plastic network
  with the climbing modules crosses the track.

The complex path of Fig. 9 has its own map of the same factors (width and obstacle spacing: fig9's ``map``).

Each cell runs ``seeds`` seeds (default 10; 2 with ``quick``) at the settings' control rate (10 Hz, the simulator's,
where those outcomes are judged): the dead ends :data:`~neurowalk.experiments.suites.deadends.TRAP_STEPS` control
steps, the track :data:`~neurowalk.experiments.suites.climbing.TRACK_STEPS`, each stopped once its outcome is
decided. A claim holds in a cell where at least two thirds of the seeds end as the paper's run did (the rule
**outcome**); its verdict says whether it holds in all three cells (reproduced: it does not hinge on the number),
at the default only (partly: it hinges on it), or not at the default (not).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.ticker import PercentFormatter

from neurowalk.arenas import arena_options
from neurowalk.arenas.climbing import FIRST_EDGE
from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.figures.escape_map import MARKERS
from neurowalk.experiments.reproduce.claims import Claim
from neurowalk.experiments.study_runs import Kept
from neurowalk.experiments.suites.climbing import TRACK_HEIGHTS, TRACK_STEPS, track_spec, track_success
from neurowalk.experiments.suites.deadends import TRAP_STEPS
from neurowalk.experiments.suites.random_envs import wilson
from neurowalk.plotting.style import legend_outside, letter_panels, network_line, pyplot, styled
from neurowalk.sim.config import EpisodeConfig

if TYPE_CHECKING:
    from matplotlib.figure import Figure

NAME = "sensitivity"
FACTORS: tuple[float, ...] = (0.8, 1.0, 1.2)
TWO_THIRDS = 2 / 3  # the rule outcome's share: a typical outcome is what two thirds of the seeds show
STEP = TRACK_HEIGHTS[0]  # m, the climbing track's step height of Fig. 10's example

#: case -> (arena, option, the figures, {network: the paper's outcome}); the outcome is "escaped", "trapped" or
#: "crossed" (the climbing track).
CASES: dict[str, tuple[str, str, str, dict[str, str]]] = {
    "simple dead end: depth": ("simple-deadlock", "depth", "Fig. 3A, 5A", {"static": "escaped", "plastic": "escaped"}),
    "narrow passage: gap": ("narrow-passage", "gap", "Fig. 3B, 5B, 8", {"plastic": "escaped", "static": "trapped"}),
    "narrow passage: depth": ("narrow-passage", "depth", "Fig. 3B, 5B, 8", {"plastic": "escaped", "static": "trapped"}),
    "climbing track: step to wall": ("climbing-track", "wall_x", "Fig. 10", {"plastic": "crossed"}),
}


def size(case: str, factor: float) -> float:
    """The option's value (m) at ``factor`` x the default; for the climbing track, the wall's distance from the first
    step's edge is scaled (the wall's x follows)."""
    arena, option, _, _ = CASES[case]
    default = float(arena_options(arena)[option])
    if option == "wall_x":
        return round(FIRST_EDGE + factor * (default - FIRST_EDGE), 6)
    return round(factor * default, 6)


def runs(s: Settings) -> Iterator[Plan]:
    """Every case x factor x network x seed (``s.seeds`` seeds from ``s.seed``; default 10, 2 with ``quick``),
    labelled ``(case, factor, network)``; each stopped once its outcome is decided."""
    for case, (arena, option, _, nets) in CASES.items():
        for f in FACTORS:
            for net in nets:
                for seed in s.seed_range(10, 2):
                    if arena == "climbing-track":
                        cfg = EpisodeConfig.from_spec(
                            {**track_spec(STEP, seed, TRACK_STEPS), "arena_opts": {"step": STEP, option: size(case, f)}}
                        )
                    else:
                        opts = {option: size(case, f)}
                        cfg = EpisodeConfig(
                            arena=arena, arena_opts=opts, controller=net, steps=TRAP_STEPS, until="escaped", seed=seed
                        )
                    yield Plan((case, f, net), cfg)


def ended_as_paper(kept: Kept, outcome: str) -> bool:
    """Whether a run ended as the paper's: ``escaped`` (in the exit region), ``trapped`` (never there) or
    ``crossed`` (the climbing track's success rule)."""
    summary = kept.summary.to_dict()
    if outcome == "crossed":
        return track_success(summary, STEP)
    return bool(summary["escaped"]) == (outcome == "escaped")


def measure(s: Settings, runs: Mapping[tuple, Sequence[Kept]]) -> Result:
    """Each case's cells: the option's value and, per network, the runs that ended as the paper's."""
    cases: dict[str, Any] = {}
    for case, (arena, option, figures, nets) in CASES.items():
        cells = []
        for f in FACTORS:
            cell: dict[str, Any] = {"factor": f, "value_m": size(case, f)}
            for net, paper in nets.items():
                rs = runs[case, f, net]
                cell[net] = {"runs": len(rs), "as_paper": sum(ended_as_paper(r, paper) for r in rs)}
            cells.append(cell)
        cases[case] = {"arena": arena, "option": option, "figures": figures, "paper": nets, "cells": cells}
    summary = {
        "seeds": s.n(10, 2),
        "first_seed": s.seed,
        "control_hz": s.rate,
        "quick": s.quick,
        "factors": list(FACTORS),
        "steps": {"dead ends": TRAP_STEPS, "climbing track": TRACK_STEPS},
        "cases": cases,
        "rule": (
            "a cell holds the paper's outcome where at least two thirds of its seeds end that way (escaped: the "
            "trunk centre in the exit region behind the trap's mouth; trapped: never there; crossed: the track's "
            "success rule); each run stopped once its outcome was decided"
        ),
    }
    return Result(NAME, summary, {})


@styled
def plot(res: Result) -> Figure:
    """One panel per case: the share of seeds that ended as the paper's run against the scale factor, one line per
    network, the two-thirds line of the rule dotted."""
    plt = pyplot()
    s = res.summary
    n = len(s["cases"])
    fig, axes = plt.subplots(1, n, figsize=(4.2 * n + 1.5, 5.0), layout="constrained", sharey=True)
    axes = list(np.atleast_1d(axes))
    for ax, (case, c) in zip(axes, s["cases"].items(), strict=True):
        x = [cell["factor"] for cell in c["cells"]]
        for net, paper in c["paper"].items():
            share = [cell[net]["as_paper"] / cell[net]["runs"] for cell in c["cells"]]
            marker, ms, face = MARKERS[net]  # large hollow over small filled: equal shares stay visible
            ax.plot(x, share, marker=marker, ms=ms, mfc=face, mew=1.5, label=f"{net}: {paper}", **network_line(net))
        ax.axhline(TWO_THIRDS, color="0.5", ls=":", lw=1)
        wall = c["option"] == "wall_x"  # the climbing track: the wall's distance from the first step's edge
        values = ", ".join(f"{cell['value_m'] - FIRST_EDGE if wall else cell['value_m']:.3g}" for cell in c["cells"])
        what = "step to wall" if wall else c["option"]
        ax.set(xticks=x, xlabel=f"{what} x default: {values} m", ylim=(-0.04, 1.04), title=case)
        ax.yaxis.set_major_formatter(PercentFormatter(1.0))
        legend_outside(ax, side="below")
    axes[0].set_ylabel(f"ended as the paper's run ({s['seeds']} seeds)")
    letter_panels(axes)
    fig.suptitle(
        f"Sensitivity to invented geometry: each dimension at 0.8, 1.0, 1.2 x its default, {s['seeds']} seeds a cell "
        f"at {s['control_hz']:g} Hz (dotted: two thirds, the outcome rule)"
    )
    return fig


def claims(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Beyond the paper: each case's outcome for each network holds across the scaled range (reproduced), at the
    default only (partly: it hinges on the number), or not at the default (not)."""
    out = []
    for case, c in s["cases"].items():
        for net, paper in c["paper"].items():
            held = [cell[net]["as_paper"] >= TWO_THIRDS * cell[net]["runs"] for cell in c["cells"]]
            default = held[FACTORS.index(1.0)]
            verdict = "reproduced" if all(held) else "partly" if default else "not"
            counts = ", ".join(
                f"x{cell['factor']:g} ({cell['value_m']:g} m) {cell[net]['as_paper']}/{cell[net]['runs']}"
                for cell in c["cells"]
            )
            k = sum(cell[net]["as_paper"] for cell in c["cells"])
            m = sum(cell[net]["runs"] for cell in c["cells"])
            rule = (
                f"{net} {paper} ({c['figures']}) with the {c['option']} at {counts}: reproduced where at least two "
                "thirds of the seeds end so in every cell (the outcome does not hinge on the invented number), partly "
                "where at the default only, not where not at the default"
            )
            out.append(
                Claim(
                    f"{case}: {net} {paper}",
                    f"{paper} ({c['figures']})",
                    f"{k}/{m}",
                    verdict,
                    rule,
                    wilson(k, m),
                    unit="runs",
                )
            )
    return out
