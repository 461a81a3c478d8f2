"""The dead ends of Fig. 3 (static network) and Fig. 5 (plastic network), and the build both figures share.

* Outcome table: every network (plastic from zero and from the paper's Fig. 4 start, static,
  Braitenberg) in the simple deadlock and in the narrow passage (default geometry, and gap and
  funnel angle changed by ±20%), ``seeds`` seeds each, 5000 control steps.
* Example runs (seed 0): the figure's network in both dead ends, with neural traces (the term :data:`TRACED`).
* :func:`runs` and :func:`measure`: what Fig. 3 and Fig. 5 run and measure: the outcome table, the example runs
  and the long runs in the original arenas (how those are run and kept, and what the paper's "time steps" are:
  :mod:`.long_runs`).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import Any

import numpy as np

from neurowalk.arenas import arena_options
from neurowalk.arenas.spec import WALL_HEIGHT
from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.reproduce.claims import Claim, outcome
from neurowalk.experiments.study_runs import Kept, Term
from neurowalk.experiments.suites.long_runs import (
    LONG,
    LONG_STRIDE,
    LONG_TRACES,
    QUICK_LONG_STEPS,
    TRACES,
    coverage_table,
    time_step_reading,
    wedged_counts,
)
from neurowalk.experiments.suites.real_robot import PATH
from neurowalk.sim.config import UNTIL
from neurowalk.sim.episode import Episode, EpisodeConfig

NETWORKS: dict[str, dict[str, Any]] = {
    "plastic": {"controller": "plastic"},
    "plastic, start b=2.4 q=3.5": {"controller": "plastic", "b0": 2.4, "q0": 3.5},
    "static": {"controller": "static"},
    "braitenberg": {"controller": "braitenberg"},
}
_NP = arena_options("narrow-passage")
VARIANTS: dict[str, tuple[str, dict[str, float]]] = {
    "simple-deadlock": ("simple-deadlock", {}),
    "narrow-passage": ("narrow-passage", {}),
    **{
        f"narrow-passage {k} {sign}20%": ("narrow-passage", {k: round(_NP[k] * f, 6)})
        for k in ("gap", "funnel")
        for sign, f in (("-", 0.8), ("+", 1.2))
    },
}
QUICK_VARIANTS = ("simple-deadlock", "narrow-passage")  # --quick: the default geometries only
QUICK_SEEDS = 1  # --quick: seeds per cell of the outcome table (unless --seeds is given)
PAPER_TRAP_TIME_STEPS = 5000  # the paper's dead-end runs (Fig. 3, 5: "5000 time steps")
TRAP_STEPS = PAPER_TRAP_TIME_STEPS  # control steps in a dead end (the paper's time steps read as control steps)


def keep_traces(ep: Episode) -> dict[str, Any]:
    """The traces a figure draws of a dead-end run (pose, inputs, outputs, b, q), every row."""
    tr = ep.trajectory
    return {"pose": tr.pose, "inputs": tr.inputs, "outputs": tr.outputs, "b": tr.b, "q": tr.q}


TRACED = Term("traces", keep_traces, arrays=dict.fromkeys(TRACES, "float64"))


def table_runs(s: Settings, variants: Mapping[str, tuple[str, dict]] | None = None, body: str | None = None
               ) -> Iterator[Plan]:  # fmt: skip
    """The outcome table's runs, labelled ``("table", variant, network)``: every network in every dead end
    ``variants`` (default :data:`VARIANTS`), ``s.seeds`` seeds from ``s.seed`` (default 10; 1 with ``quick``),
    :data:`TRAP_STEPS` control steps each, stopped once escaped (``body``: where the settings name none); each kept
    with its path (the figure ``bodies`` draws the same runs)."""
    for vname, (arena, opts) in (variants or VARIANTS).items():
        for nname, net in NETWORKS.items():
            for seed in range(s.seed, s.seed + s.n(full=10, quick=QUICK_SEEDS)):
                cfg = EpisodeConfig(arena=arena, arena_opts=opts, steps=TRAP_STEPS, until="escaped", seed=seed, **net)
                cfg = cfg.replace(body=body) if body else cfg
                yield Plan(("table", vname, nname), cfg, (PATH,))  # kept with its path, as bodies' runs are


def table_counts(s: Settings, runs: Mapping[Any, Sequence[Kept]], body: str = "amosii", prefix: tuple = ("table",)
                  ) -> dict[str, Any]:  # fmt: skip
    """Escape counts per dead end and network from the runs of :func:`table_runs` (labels ``prefix + (variant,
    network)``). ``runs`` in the table lists every run as [variant, network, seed, escaped, trapped]."""
    n = len(prefix)
    cells = {k[n:]: v for k, v in runs.items() if k[:n] == prefix}
    table: dict[str, dict[str, dict[str, Any]]] = {}
    every = []
    for (vname, nname), rs in cells.items():
        every += [[vname, nname, r.seed, bool(r.escaped), bool(r.trapped)] for r in rs]
        table.setdefault(vname, {})[nname] = {
            "runs": len(rs),
            "escaped": sum(bool(r.escaped) for r in rs),
            "trapped": sum(bool(r.trapped) for r in rs),
            "median_direction_switches": float(np.median([r.direction_switches for r in rs])),
        }
    variants = {v for v, _ in cells}
    control_hz = s.rate
    return {
        "seeds": s.n(full=10, quick=QUICK_SEEDS),
        "first_seed": s.seed,
        "steps": TRAP_STEPS,
        "control_hz": control_hz,
        "seconds": TRAP_STEPS / control_hz,
        "body": body,
        "climbing": s.climbing,
        "variants": {k: {"arena": a, "options": o} for k, (a, o) in VARIANTS.items() if k in variants},
        "network_variant": s.variant or "paper",
        "gait": s.gait or "wave",
        "engine": s.engine,
        "counts": table,
        "runs": every,
        "rule": "escaped: the trunk centre reached the exit region behind the trap's mouth within the steps; "
        "trapped: the last 3000 steps stayed within a disc of radius 0.5 m",
        "stop_rule": UNTIL["escaped"] + "; a run that does not escape runs all its steps",
    }


def runs(s: Settings, network: str, long_runs: dict[str, dict[str, Any]], long_steps: int) -> Iterator[Plan]:
    """Fig. 3's or Fig. 5's runs: the outcome table (:func:`table_runs`; ``quick``: the :data:`QUICK_VARIANTS`
    only), ``network``'s example runs in both dead ends (``("example", name)``, every row kept) and the long runs
    ``{name: config fields}`` (``("long", name)``, ``long_steps`` control steps, :data:`QUICK_LONG_STEPS` at most
    with ``quick``; streamed, every :data:`LONG_STRIDE`-th row kept), all with seed ``s.seed``. With ``s.climbing``
    (leg reflexes and backbone control on) the original arenas' boxes are raised to
    :data:`~neurowalk.arenas.spec.WALL_HEIGHT` (their 0.10 m boxes would be climbable steps)."""
    yield from table_runs(s, {k: v for k, v in VARIANTS.items() if k in QUICK_VARIANTS} if s.quick else VARIANTS)
    for arena in ("simple-deadlock", "narrow-passage"):
        cfg = EpisodeConfig(arena=arena, steps=TRAP_STEPS, seed=s.seed, **NETWORKS[network])  # every step drawn
        yield Plan(("example", arena), cfg, (TRACED,))
    steps = min(long_steps, QUICK_LONG_STEPS) if s.quick else long_steps
    opts = {"height": WALL_HEIGHT} if s.climbing else {}
    for name, fields in long_runs.items():
        yield Plan(("long", name), EpisodeConfig(steps=steps, arena_opts=opts, seed=s.seed, **fields), (LONG,))


def measure(
    name: str,
    network: str,
    long_runs: dict,
    s: Settings,
    runs: Mapping[Any, Sequence[Kept]],
    *,
    long_steps: int,
    paper_time_steps: dict[str, int],
    mark_step: int | None = None,
) -> Result:
    """Fig. 3's or Fig. 5's numbers from its :func:`runs`: the outcome table, the example runs' traces, the long
    runs' rows, coverage over time and wedged periods. ``long_steps``: the long runs' control steps without
    ``quick``; ``paper_time_steps``: the paper's counts behind them (for ``time_step_reading``); ``mark_step``: a
    step the figure marks on the long runs (Fig. 3: 7,000, the paper's 70,000 time steps)."""
    control_hz = s.rate
    kept = {k[1]: v[0] for k, v in runs.items() if k[0] in ("example", "long")}
    traces = {k: r.kept["traces" if k not in long_runs else "long"] for k, r in kept.items()}
    steps = kept[next(iter(long_runs))].config.steps  # the long runs' control steps, as planned
    arrays = {
        f"{k}/{field}": v[field] for k, v in traces.items() for field in (LONG_TRACES if k in long_runs else TRACES)
    }
    summaries = {k: r.summary.to_dict() for k, r in kept.items()}
    summary = {
        "network": network,
        "variant": s.variant or "paper",
        "gait": s.gait or "wave",
        "engine": s.engine,
        "seed": s.seed,
        "climbing": s.climbing,
        "quick": s.quick,
        "control_hz": control_hz,
        "time_step_reading": time_step_reading(
            paper_time_steps, steps, control_hz, paper_trap_steps=PAPER_TRAP_TIME_STEPS, trap_steps=TRAP_STEPS
        ),
        "table": table_counts(s, runs),
        **_long_steps(steps, long_steps, control_hz, {k: len(traces[k]["step"]) for k in long_runs}),
        "mark_step": mark_step if mark_step is not None and mark_step < steps else None,
        "runs": summaries,
        "coverage_over_time": {k: coverage_table(traces[k]["step"], traces[k]["coverage"]) for k in long_runs},
        "wedged": wedged_counts({k: summaries[k] for k in long_runs}, control_hz=control_hz),
    }
    return Result(name, summary, arrays)


def _long_steps(long_steps: int, full_steps: int, control_hz: float, rows: dict[str, int]) -> dict[str, Any]:
    """The long runs' length (``long_steps`` control steps, ``full_steps`` without ``quick``) and the ``rows`` their
    arrays keep (every :data:`LONG_STRIDE`-th step and the last)."""
    return {
        "long_steps": long_steps,
        "long_s": long_steps / control_hz,
        "long_steps_full": full_steps,
        "long_rows": {
            "stride": LONG_STRIDE,
            "rule": f"the long runs' arrays (name/step, /pose, /inputs, /outputs, /b, /q, /coverage) hold every "
            f"{LONG_STRIDE}th control step from step 0, and the last step",
            "rows": rows,
        },
    }


def dead_end_claim(s: dict[str, Any], arena: str, network: str, want: str, what: str) -> Claim:
    """An outcome claim of the dead-end table: ``want`` is ``escaped`` or ``trapped``."""
    cell = s["table"]["counts"][arena][network]
    return outcome(what, want, cell[want], cell["runs"])
