"""The long runs of Fig. 3 and Fig. 5 in the original arenas, and what the paper's "time steps" are.

* Long runs in ``cluttered`` and ``difficult``, streamed (:class:`LongRunKeeper`): every :data:`LONG_STRIDE`-th
  row of the path, inputs, outputs and weights (and the last row), the coverage over time (:class:`FirstVisits`),
  trapping, and the periods the robot stayed wedged (:func:`neurowalk.metrics.wedged_periods`: its trunk centre
  within 0.3 m for more than 100 s), with their causes; the json's tables of them (:func:`coverage_table`,
  :func:`wedged_counts`).
* The reading of the paper's time steps (below), in numbers for the figures' json (:func:`time_step_reading`).

What the paper's "time steps" are
---------------------------------
The paper counts every run in "time steps": the dead ends 5000 (Fig. 3A-E, 5A-E), the long run of Fig. 3F/G
70,000 + 330,000 (the green dot of 3G at 70,000), and that of Fig. 5F/G 1,000,000. The authors' simulation
(LPZRobots, original_code_facts.md §1, S4) steps ODE every 0.01 s and calls the controller every
``controlinterval = 10`` physics steps: 100 physics steps and 10 control steps a second. The reading here:

* **Dead ends: control steps.** 5000 control steps are 500 s. As 5000 physics steps they would be 50 s, about
  0.6 m of the wave gait (the authors' own regression run walks 0.95 m in 100 s, §8), too short for Fig. 5B's
  "few turns to and fro" before the escape. The authors' logs of these runs (the network's ``outTezinhib.txt``,
  plotted over "timesteps" by ``hysteresis_plot_t_w.py``, and LPZRobots' track file, written by
  ``Agent::step``) have one row per control step.
* **Long runs: physics steps** (the simulator's step count, as in the group's regression test, which runs
  "10000 physics steps (100 s)", §8): :data:`PHYSICS_PER_CONTROL` = 10 of them make one control step. Fig. 5's
  1,000,000 are 100,000 control steps (10,000 s), Fig. 3's 70,000 + 330,000 are 7,000 + 33,000 control steps
  (4,000 s). Three things point this way. (1) The authors' weight-plotting script draws the weights over "timesteps"
  0 to 99,000 of the network's log, one row per control step: about the 100,000 control steps of a
  1,000,000-physics-step run, not 1,000,000 of them.
  (2) The walked path: at about 1.3 cm/s (this model's wave gait in the difficult arena) 100,000 control steps
  are about 125 m, enough to "explore the whole environment" of 9 x 9 m and still a readable line; 1,000,000
  control steps (28 h simulated) would be some 1,250 m, a solid blot, and Fig. 3F's "initial 70,000" red line
  (9 m here, against 90 m) would not stand apart from the gray. (3) The dead ends cannot be physics steps
  (above), so the paper's one word covers two counts either way: the logs' rows for the short runs drawn
  step by step, the simulator's count for the long ones.

The reading is a judgement: the paper never says which step it counts. The long runs keep their control steps
at any ``control_hz`` (as the dead ends do: the networks' learning and forgetting are per step); seconds are
steps / ``control_hz``. ``time_step_reading`` in the figures' json says all this in numbers.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable
from typing import Any

import numpy as np

from neurowalk import metrics
from neurowalk.arenas import ArenaSpec, make_arena
from neurowalk.experiments.study_runs import Term
from neurowalk.sim.episode import Episode, EpisodeConfig, Streaming
from neurowalk.sim.trajectory import Trajectory

PHYSICS_PER_CONTROL = 10  # the authors' physics steps per control step (controlinterval 10, 0.01 s ODE steps)
QUICK_LONG_STEPS = 10_000  # control steps of a long run with --quick (1,000 s at 10 Hz)
LONG_STRIDE = 10  # a long run keeps every LONG_STRIDE-th row (1 s at 10 Hz) and its last one
LONG_CHUNK = 10_000  # rows a streamed long run holds at a time
WEDGED_LONG_S = 300.0  # wedged periods longer than this are counted apart ("over 300 s")
TRACES = ("pose", "inputs", "outputs", "b", "q")  # the traces a figure keeps of a run (dead end or long run)
LONG_TRACES = ("step", *TRACES, "coverage")  # a long run's arrays: rows at the steps `step`


def control_steps_of(paper_time_steps: int) -> int:
    """Control steps of a long run of the paper's ``paper_time_steps`` (physics steps; see the module's text)."""
    return paper_time_steps // PHYSICS_PER_CONTROL


def time_step_reading(
    paper: dict[str, int], long_steps: int, control_hz: float, *, paper_trap_steps: int, trap_steps: int
) -> dict[str, Any]:
    """The reading of the paper's "time steps" in numbers, for a figure's json.

    ``paper``: the figure's long-run counts as the paper gives them ({what: time steps}). ``paper_trap_steps``,
    ``trap_steps``: the dead ends' time steps in the paper and the control steps they are read as.
    """
    return {
        "dead_ends": f"the paper's {paper_trap_steps} time steps are control steps: {trap_steps} control "
        f"steps, {trap_steps / control_hz:g} s at {control_hz:g} Hz",
        "long_runs": "the paper's long-run time steps are physics steps of the authors' simulator (0.01 s, "
        f"{PHYSICS_PER_CONTROL} to a control step at 10 Hz): control steps = time steps / {PHYSICS_PER_CONTROL}",
        "paper_time_steps": paper,
        "control_steps": {k: control_steps_of(v) for k, v in paper.items()},
        "physics_per_control_step": PHYSICS_PER_CONTROL,
        "at_other_rates": "every run keeps its control steps (the networks' step semantics); seconds = steps / "
        "control_hz",
        "this_run_long_steps": long_steps,
        "this_run_long_s": long_steps / control_hz,
        "argument": "neurowalk.experiments.suites.long_runs (module text)",
    }


class FirstVisits:
    """The first control step at which the trunk centre entered each free cell of an arena (coverage over time).

    The cells and the rule are :func:`neurowalk.metrics.coverage`'s (0.25 m cells of the free area): the curve's
    value at the last step is the run's ``coverage``. Feed rows in step order with :meth:`add`.
    """

    def __init__(self, arena: ArenaSpec, cell: float = 0.25) -> None:
        self.x0, _, self.y0, _ = arena.bounds if arena.bounds is not None else (0.0, 0.0, 0.0, 0.0)
        self.cell = cell
        free = arena.free_cells(cell) if arena.bounds is not None else np.zeros((0, 2))
        self.n_free = len(free)
        keys = np.floor((free - [self.x0, self.y0]) / cell).astype(np.int64)
        self.k0 = keys.min(axis=0) if len(keys) else np.zeros(2, dtype=np.int64)
        self.shape = (keys.max(axis=0) - self.k0 + 1) if len(keys) else np.zeros(2, dtype=np.int64)
        self.flat_free = (keys[:, 0] - self.k0[0]) * self.shape[1] + (keys[:, 1] - self.k0[1])
        self.first = np.full(int(np.prod(self.shape)), np.iinfo(np.int64).max, dtype=np.int64)

    def add(self, pose: np.ndarray, start: int) -> None:
        """Take the rows of steps ``start, start + 1, ...`` (``pose`` (n, >= 2), m)."""
        if self.n_free == 0 or len(pose) == 0:
            return
        with np.errstate(invalid="ignore"):
            fx = np.floor((np.asarray(pose[:, 0], dtype=np.float64) - self.x0) / self.cell) - self.k0[0]
            fy = np.floor((np.asarray(pose[:, 1], dtype=np.float64) - self.y0) / self.cell) - self.k0[1]
        ok = (fx >= 0) & (fx < self.shape[0]) & (fy >= 0) & (fy < self.shape[1])  # NaN: False
        rows = np.flatnonzero(ok)
        if len(rows) == 0:
            return
        flat = fx[rows].astype(np.int64) * self.shape[1] + fy[rows].astype(np.int64)
        cells, at = np.unique(flat, return_index=True)  # each cell's first row in these rows
        self.first[cells] = np.minimum(self.first[cells], start + rows[at])

    def curve(self, steps: np.ndarray) -> np.ndarray:
        """Coverage (share of the free cells visited) after each of ``steps`` (NaN: the arena has no free cells)."""
        steps = np.asarray(steps)
        if self.n_free == 0:
            return np.full(len(steps), np.nan)
        visits = np.sort(self.first[self.flat_free])
        return np.searchsorted(visits, steps, side="right") / self.n_free


def saturating_fit(t: np.ndarray, coverage: np.ndarray) -> dict[str, float]:
    """Least-squares fit of ``coverage = c_max (1 - exp(-t / tau))`` to a coverage curve (``t`` (n,) s, ``coverage``
    (n,) shares): ``c_max`` (the share it levels off at), ``tau_s`` (s; searched on a log grid from 10 s to 100 times
    the curve's span, ``c_max`` solved exactly at each) and ``rms`` (the residual's root mean square). A curve still
    rising straight at its end gives a ``tau_s`` beyond its span and a ``c_max`` beyond its last value."""
    t, c = np.asarray(t, dtype=float), np.asarray(coverage, dtype=float)
    span = max(float(t[-1]), 10.0)
    best = (np.inf, 0.0, 0.0)
    for tau in np.geomspace(10.0, 100.0 * span, 400):
        g = 1.0 - np.exp(-t / tau)
        c_max = float(g @ c / (g @ g)) if g @ g > 0 else 0.0
        err = float(np.sqrt(np.mean((c - c_max * g) ** 2)))
        if err < best[0]:
            best = (err, c_max, float(tau))
    return {"c_max": best[1], "tau_s": best[2], "rms": best[0]}


def sample_steps(steps: int, stride: int) -> np.ndarray:
    """The steps a long run keeps: 0, stride, 2·stride, ... and the last (steps - 1)."""
    at = np.arange(0, steps, stride)
    return at if at[-1] == steps - 1 else np.append(at, steps - 1)


class LongRunKeeper:
    """The sink of a streamed long run (:class:`~neurowalk.sim.engine_interface.Streaming`): what a figure keeps of it.

    Keeps every ``stride``-th row (and the last) of the path, inputs, outputs and weights, the first visit of every
    free cell (:class:`FirstVisits`), and the positions (qpos) of every step, from which the summary replays the
    obstacle contacts of its wedged periods (:meth:`qpos_rows`; the cause of each). Memory: 8·nq bytes a step
    (about 21 MB for 100,000 steps of AMOSII, nq = 26) plus one chunk of the run.
    """

    def __init__(self, cfg: EpisodeConfig, stride: int = LONG_STRIDE) -> None:
        self.steps, self.stride = cfg.steps, stride
        self.at = sample_steps(cfg.steps, stride)
        self.kept = {k: np.full((len(self.at), 3 if k == "pose" else 2), np.nan) for k in TRACES}
        self.visits = FirstVisits(make_arena(cfg.arena, **cfg.arena_opts))
        self.qpos: np.ndarray | None = None

    def __call__(self, rows: Trajectory, start: int) -> None:
        """Take the rows of steps ``start, start + 1, ...`` (valid during the call only: copied)."""
        n = len(rows)
        if self.qpos is None:
            self.qpos = np.full((self.steps, rows.qpos.shape[1]), np.nan)
        self.qpos[start : start + n] = rows.qpos
        lo, hi = np.searchsorted(self.at, [start, start + n])
        for k in TRACES:
            self.kept[k][lo:hi] = getattr(rows, k)[self.at[lo:hi] - start]
        self.visits.add(rows.pose, start)

    def qpos_rows(self, rows: np.ndarray) -> np.ndarray:
        """The positions of steps ``rows`` (the summary's replay of wedged periods)."""
        assert self.qpos is not None
        return self.qpos[rows]

    def traces(self, done: int) -> dict[str, np.ndarray]:
        """The kept rows of the first ``done`` steps: ``step`` (the rows' steps), the traces, ``coverage``."""
        n = int(np.searchsorted(self.at, done))
        at = self.at[:n]
        return {"step": at, **{k: v[:n] for k, v in self.kept.items()}, "coverage": self.visits.curve(at)}


def keep_long_traces(ep: Episode) -> dict[str, Any]:
    """:class:`LongRunKeeper`'s traces of a run held in memory (the many-worlds engines' path)."""
    keeper = LongRunKeeper(ep.config)
    keeper(ep.trajectory, 0)
    return keeper.traces(len(ep.trajectory))


def stream_long_traces(cfg: EpisodeConfig) -> tuple[Streaming, Callable[[Episode], dict[str, Any]]]:
    """The run of ``cfg`` streamed to a :class:`LongRunKeeper` (its rows not held in memory), and what is kept."""
    keeper = LongRunKeeper(cfg)
    stream = Streaming(sink=keeper, chunk=min(LONG_CHUNK, cfg.steps), keep_rows=False, picture_rows=1)
    return stream, lambda ep: keeper.traces(cfg.steps)


#: The term of a long run: every :data:`LONG_STRIDE`-th row (and the last) of :data:`LONG_TRACES`, streamed.
LONG = Term(
    "long",
    keep_long_traces,
    arrays={k: "int64" if k == "step" else "float64" for k in LONG_TRACES},
    stream=stream_long_traces,
)


def coverage_table(step: np.ndarray, coverage: np.ndarray, points: int = 10) -> dict[str, list]:
    """Coverage at ``points`` evenly spaced kept steps (the last included), for the json (the npz holds all)."""
    idx = np.unique(np.round(np.linspace(0, len(step) - 1, points + 1)).astype(int))
    return {"step": [int(s) for s in step[idx]], "coverage": [float(c) for c in coverage[idx]]}


def wedged_counts(summaries: dict[str, dict[str, Any]], control_hz: float = 10.0) -> dict[str, dict[str, Any]]:
    """Per long run: number of wedged periods, the longest (s), counts by cause, time wedged in all (s), those over
    :data:`WEDGED_LONG_S` (count and causes), and the list of periods (start step and s, duration, cause); then the
    held periods (:func:`neurowalk.metrics.held_periods`: in the disc with the heading within the band), the
    longest, those over :data:`WEDGED_LONG_S` (count and the causes of their wedged periods) and the number of
    turning periods (wedged with no held step).
    """
    out = {}
    for k, s in summaries.items():
        long = [p for p in s["wedged"] if p["duration_s"] > WEDGED_LONG_S]
        held = metrics.held_periods(s["wedged"], control_hz)
        held_rule = (
            f"wedged, and the heading's range (max minus min of the unwrapped yaw) within "
            f"{metrics.HELD_HEADING_DEG:g} degrees over each stretch of more than {metrics.WEDGE_MIN_S:g} s"
        )
        held_long = [h for h in held if h["duration_s"] > WEDGED_LONG_S]
        out[k] = {
            "periods": s["wedged_periods"],
            "longest_s": s["longest_wedged_s"],
            "causes": s["wedged_causes"],
            "total_s": float(sum(p["duration_s"] for p in s["wedged"])),
            f"over_{WEDGED_LONG_S:g}s": {"periods": len(long), "causes": dict(Counter(p["cause"] for p in long))},
            "list": [
                {
                    "start_step": int(p["start"]),
                    "start_s": float(p["start"]) / control_hz,
                    "duration_s": float(p["duration_s"]),
                    "cause": p["cause"],
                    "heading_range_deg": p["heading_range_deg"],
                    "held_s": p["held_s"],
                }
                for p in s["wedged"]
            ],
            "rule": f"trunk centre within {metrics.WEDGE_RADIUS} m of its mean for more than {metrics.WEDGE_MIN_S:g} s",
            "held": {
                "periods": len(held),
                "longest_s": max((h["duration_s"] for h in held), default=0.0),
                f"over_{WEDGED_LONG_S:g}s": {
                    "periods": len(held_long),
                    "causes": dict(Counter(h["cause"] for h in held_long)),
                },
                "turning_periods": sum(1 for p in s["wedged"] if not p["held"]),
                "rule": held_rule,
            },
        }
    return out
