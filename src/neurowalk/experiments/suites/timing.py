"""Simulated time of the figures' runs, and the comparison with the real robot's clock.

A figure that sets its runs' length in seconds turns it into control steps at the run's control rate
(:func:`steps_for`), so that a run covers the same simulated time at 10 Hz (the authors' simulator, the default) as
at 27 Hz (the real AMOSII's controller, paper §2.2). The networks keep their step semantics (the CPG period is a
number of control steps), so at 27 Hz the robot walks and learns 2.7 times as fast in seconds.

The paper's real-robot experiments (Fig. 8-10) give the times of key events as the time stamps of their photos,
taken with the controller at :data:`REAL_ROBOT_HZ`; :func:`real_robot_entry` puts the intervals between two of them
(:func:`interval_s`: from an event the robot meets in the arena, not from the start, which depends on where an
invented arena puts it) beside the same intervals in simulation.
"""

from __future__ import annotations

from typing import Any

import numpy as np

SIM_HZ = 10.0  # the authors' simulator's control rate, the default of every run
REAL_ROBOT_HZ = 27.0  # the real AMOSII's control rate (paper §2.2), the clock of the paper's photo times


def steps_for(seconds: float, control_hz: float) -> int:
    """Control steps of a run of ``seconds`` s of simulated time at ``control_hz`` Hz: ``round(seconds * control_hz)``
    (at least 1)."""
    return max(1, round(seconds * control_hz))


def quick_seconds(seconds: float, max_steps: int, control_hz: float) -> float:
    """Length (s) of a ``quick`` run: ``seconds``, or ``max_steps / control_hz`` where that is shorter.

    ``max_steps`` caps a quick run's control steps, and so its cost, at a high control rate.
    """
    return min(float(seconds), max_steps / control_hz)


def quick_note(seconds: float, quick_s: float, control_hz: float) -> str | None:
    """The line a summary gives when a ``quick`` run was shortened for a high control rate (None when it was not)."""
    if quick_s >= seconds:
        return None
    return (
        f"quick runs last {quick_s:g} s here instead of {seconds:g} s: at {control_hz:g} Hz a quick run keeps at "
        f"most the control steps of the {SIM_HZ:g} Hz quick run (the robot walks as far in them)"
    )


def interval_s(start_s: float | None, end_s: float | None) -> float | None:
    """The time (s) from one event to a later one of the same run; None where either did not happen."""
    return None if start_s is None or end_s is None else float(end_s) - float(start_s)


def time_stats(times: list[float | None]) -> dict[str, Any]:
    """Times (s) of one event over runs (None: it did not happen in that run): median and range of those it did.

    Returns ``runs`` (how many), ``happened`` (in how many), ``median_s``, ``min_s``, ``max_s`` (None where it never
    happened) and ``times_s`` (each run's, in run order).
    """
    done = [float(t) for t in times if t is not None]
    return {
        "runs": len(times),
        "happened": len(done),
        "median_s": float(np.median(done)) if done else None,
        "min_s": min(done) if done else None,
        "max_s": max(done) if done else None,
        "times_s": [None if t is None else float(t) for t in times],
    }


def real_robot_entry(
    events: dict[str, tuple[float, str, list[float | None]]], control_hz: float, run_s: float, runs: str
) -> dict[str, Any]:
    """The ``real_robot`` entry of a real-robot figure's summary: the paper's times beside the simulated ones.

    Args:
        events: event name -> (the paper's time in s, the paper's words for it with its time stamp, the simulated
            times in s of each run, None where the event did not happen within the run).
        control_hz: the simulated runs' control rate (Hz).
        run_s: the simulated runs' length (s).
        runs: which runs the simulated times come from, in words.
    """
    fair = control_hz == REAL_ROBOT_HZ
    if fair:
        note = (
            f"the paper's times and the simulated ones are on the same {REAL_ROBOT_HZ:g} Hz controller clock; they "
            "still differ by the body (model vs the real AMOSII), the arena's build and the sensors"
        )
    else:
        note = (
            f"not the fair comparison: the paper's times were taken on the real robot, whose controller ran at "
            f"{REAL_ROBOT_HZ:g} Hz, and these runs' controller ran at {control_hz:g} Hz; the networks count time "
            f"in control steps (the CPG period, the weights' growth and decay), so here the robot walks and learns "
            f"{REAL_ROBOT_HZ / control_hz:.2f} times as slowly in seconds. Run with --control-hz {REAL_ROBOT_HZ:g} "
            "for the comparison on the robot's clock"
        )
    return {
        "paper_control_hz": REAL_ROBOT_HZ,
        "control_hz": float(control_hz),
        "same_clock": fair,
        "run_s": float(run_s),
        "runs": runs,
        "events": {
            name: {"paper_s": float(paper_s), "paper": words, "sim": time_stats(times)}
            for name, (paper_s, words, times) in events.items()
        },
        "note": note,
    }
