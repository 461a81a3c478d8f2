"""Fig. 3: the static network (b = 2.4, c = -3.5) in dead ends and in the original arenas.

Panels as the paper's caption names them: A. Simple deadlock: escaped. B. Narrow passage (a gap between the end
obstacles): trapped, oscillating. C. Neural activations in the narrow passage. D-E. Input against output, coloured
by time: the hysteresis loops. F. The cluttered arena (obstacles, no sharp corners or narrow passages): explored
without getting trapped; red the first 7,000 control steps, gray the further 33,000. G. The difficult arena (sharp
corners, narrow passages): trapped; red dot the start, green dot the position after 7,000 control steps.

Run lengths: the dead ends 5000 control steps; the long runs :data:`LONG_STEPS` = 40,000 control steps (4,000 s at
10 Hz), the paper's 70,000 + 330,000 time steps read as physics steps of the authors' simulator, ten to a control
step (the reading and its argument: :mod:`neurowalk.experiments.suites.long_runs`; the json's
``time_step_reading``); :data:`MARK_STEP` = 7,000 is the paper's 70,000. ``--quick``: long runs of
:data:`~neurowalk.experiments.suites.long_runs.QUICK_LONG_STEPS`. The json holds the escape counts of all networks
(Braitenberg beside static and plastic) over ``--seeds`` seeds and ±20% geometry changes, and the wedged periods
of the long runs with their causes.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.reproduce.claims import Claim, holds
from neurowalk.experiments.study_runs import Kept
from neurowalk.experiments.suites import deadends
from neurowalk.experiments.suites.deadends import dead_end_claim
from neurowalk.experiments.suites.deadends_plot import plot as draw
from neurowalk.experiments.suites.long_runs import control_steps_of

if TYPE_CHECKING:
    from matplotlib.figure import Figure

NAME = "fig3"
NETWORK = "static"
LONG = {
    "cluttered (static)": {"arena": "cluttered", "controller": "static"},
    "difficult (static)": {"arena": "difficult", "controller": "static"},
}
PAPER_TIME_STEPS = {"initial (red line, green dot)": 70_000, "further (gray line)": 330_000}
LONG_STEPS = control_steps_of(sum(PAPER_TIME_STEPS.values()))  # 40,000 control steps
MARK_STEP = control_steps_of(PAPER_TIME_STEPS["initial (red line, green dot)"])  # 7,000 control steps
PANELS = {
    "A": "simple deadlock: escaped",
    "B": "narrow passage: trapped",
    "C": "neural activations in the narrow passage (B)",
    "D": "left input against output (hysteresis)",
    "E": "right input against output (hysteresis)",
    "F": "cluttered arena: explored (red: first 7,000 control steps, gray: the rest)",
    "G": "difficult arena: trapped (green dot: after 7,000 control steps)",
}


def runs(s: Settings) -> Iterator[Plan]:
    """The outcome table over ``s.seeds`` seeds (default 10; 1 with ``quick``), the example and the long runs
    (:func:`~neurowalk.experiments.suites.deadends.runs`)."""
    return deadends.runs(s, NETWORK, LONG, LONG_STEPS)


def measure(s: Settings, runs: Mapping[Any, Sequence[Kept]]) -> Result:
    """The outcome table, the traces, the long runs' coverage and wedged periods."""
    res = deadends.measure(NAME, NETWORK, LONG, s, runs, long_steps=LONG_STEPS, paper_time_steps=PAPER_TIME_STEPS,
                           mark_step=MARK_STEP)  # fmt: skip
    res.summary["panels"] = PANELS
    return res


def plot(res: Result) -> Figure:
    """Panels A-G; the escape counts as a table below them."""
    return draw(res, NETWORK, list(LONG))


def claims(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Static network: escapes the simple dead end, trapped in the narrow passage, explores the cluttered arena,
    trapped in the difficult one."""
    clut, diff = s["runs"]["cluttered (static)"], s["runs"]["difficult (static)"]
    return [
        dead_end_claim(
            s, "simple-deadlock", "static", "escaped", "static network escapes the simple dead end (Fig. 3A)"
        ),
        dead_end_claim(
            s, "narrow-passage", "static", "trapped", "static network is trapped in the narrow passage (Fig. 3B)"
        ),
        holds(
            "static network explores the cluttered arena without getting stuck (Fig. 3F)",
            "not stuck",
            not clut["trapped"],
            f"coverage {clut['coverage']:.1%}",
            f"one run of {clut['steps']} control steps; stuck: held in a 0.5 m disc over its last 300 s",
        ),
        holds(
            "static network is trapped in the difficult arena (Fig. 3G)",
            "trapped",
            bool(diff["trapped"]),
            f"coverage {diff['coverage']:.1%}",
            f"one run of {diff['steps']} control steps ({s['time_step_reading']['long_runs']}); longest wedged "
            f"period {diff['longest_wedged_s']:.0f} s"
            + (f", longest held {diff['longest_held_s']:.0f} s" if diff.get("longest_held_s") is not None else ""),
        ),
    ]
