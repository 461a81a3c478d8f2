"""Climbing outcomes shared by ``fig10`` and ``steps``: run specs and success rules.

* On ``climbing-track`` (plastic network, reflexes and backbone control on) a run succeeds when the
  trunk centre reaches the second platform (0.3 m beyond its edge) within :data:`TRACK_STEPS` control steps
  and the trunk never rose to the top of a wall on the way (``max_z`` below the wall tops, 2 x step +
  0.20 m); the run stops there. The term :data:`FIRST_PLATFORM` also keeps when the trunk centre first got 0.3 m
  onto the first platform.
* On ``steps`` (steering fixed straight ahead, so only the climbing modules decide) a run climbs when
  the trunk centre gets 0.3 m onto the platform within :data:`STEP_S` s (the run stops there). The highest step
  climbed reliably is the highest height at which at least :data:`RELIABLE` of the seeds climbed, all
  lower heights included.

Every variant steps the same physics (AMOSII's defaults), the climbing modules on or off.

A track run lasts :data:`TRACK_STEPS` control steps at every control rate (the networks count time in steps: an
arm at 27 Hz, the real robot's, gives them as many updates as one at 10 Hz); a single-step run lasts :data:`STEP_S`
s of simulated time, turned into control steps at its rate (:func:`~neurowalk.experiments.suites.timing.steps_for`;
3000 steps at 10 Hz, the default). :func:`climb_step` is when a run's backbone first leaned up (a climbable step
detected) or down (the front over it, climbing).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from neurowalk.arenas.climbing import track_regions
from neurowalk.arenas.spec import WALL_HEIGHT
from neurowalk.experiments.study_runs import Term
from neurowalk.experiments.suites.timing import SIM_HZ, steps_for
from neurowalk.sim.episode import Episode

TRACK_STEPS = 12_000  # control steps per climbing-track run at every rate (1,200 s at 10 Hz)
LEAN = 0.26  # rad: a climb starts when the backbone command leans down below -LEAN (front legs on the step)
TRACK_HEIGHTS = (0.06, 0.08, 0.10)  # m
STEP_S = 300.0  # s per single-step run (3000 control steps at 10 Hz)
ONTO = 0.3  # m: "on a platform" = the trunk centre this far past its edge
SWEEP_HEIGHTS = (0.02, 0.04, 0.06, 0.08, 0.10, 0.12, 0.14)  # m
QUICK_SWEEP_HEIGHTS = (0.04, 0.08, 0.12)  # m
RELIABLE = 0.8  # share of seeds
VARIANTS: dict[str, dict[str, bool]] = {
    "reflexes + backbone": {"reflexes": True, "backbone": True},
    "backbone only": {"reflexes": False, "backbone": True},
    "reflexes only": {"reflexes": True, "backbone": False},
    "neither": {"reflexes": False, "backbone": False},
}
TRACK_RULE = (
    f"success: the trunk centre reaches the second platform ({ONTO} m past its edge) within {TRACK_STEPS:,} "
    f"control steps (1,200 s at 10 Hz), and never rises to a wall's top (max trunk z < 2 x step + {WALL_HEIGHT} m)"
)
STEP_RULE = (
    f"climbed: the trunk centre gets {ONTO} m onto the platform within {STEP_S:g} s of simulated time (steering "
    f"fixed straight ahead); reliable: at least {RELIABLE:.0%} of the seeds at that height and every lower "
    "one"
)


def track_spec(
    step: float, seed: int, steps: int | None = None, variant: str = "paper", control_hz: float = SIM_HZ
) -> dict[str, Any]:
    """Run spec of one climbing-track run (plastic network ``variant``, reflexes and backbone control) at
    ``control_hz`` Hz, ``steps`` control steps long (default :data:`TRACK_STEPS`)."""
    out = {
        "arena": "climbing-track",
        "arena_opts": {"step": step},
        "controller": "plastic",
        "steps": steps if steps is not None else TRACK_STEPS,
        "seed": seed,
        "control_hz": float(control_hz),
        "reflexes": True,
        "backbone": True,
        "until": "escaped",  # on the second platform the track is crossed: later steps cannot change that
    }
    return {**out, "variant": variant} if variant != "paper" else out


def step_spec(
    height: float, variant: str, seed: int, steps: int | None = None, control_hz: float = SIM_HZ
) -> dict[str, Any]:
    """Run spec of one single-step run of an ablation ``variant`` (a key of :data:`VARIANTS`) at ``control_hz``
    Hz, ``steps`` control steps long (default :data:`STEP_S` s at that rate)."""
    return {
        "arena": "steps",
        "arena_opts": {"height": height},
        "controller": "fixed",
        "steer": [-1.0, -1.0],
        "steps": steps if steps is not None else steps_for(STEP_S, control_hz),
        "seed": seed,
        "control_hz": float(control_hz),
        "until": "escaped",  # a run that got onto the platform has climbed: later steps cannot change that
        **{k: v for k, v in VARIANTS[variant].items() if v},
    }


def first_platform_step(pose: np.ndarray, step: float) -> int | None:
    """First row of a climbing-track run's ``pose`` (T, 3) with the trunk centre :data:`ONTO` m onto the first
    platform (x at least that far past its edge, within the first corridor); None if never."""
    x0, x1, y0, y1, _ = track_regions(step)["first platform"]
    x, y = pose[:, 0], pose[:, 1]
    idx = np.flatnonzero((x >= x0 + ONTO) & (x <= x1) & (y >= y0) & (y <= y1))
    return int(idx[0]) if len(idx) else None


def climb_step(bj_command: np.ndarray, after: int = 0, up: bool = False) -> int | None:
    """First control step at or after ``after`` at which the backbone command ``bj_command`` (T,) rad leans down
    below -:data:`LEAN` (a climb starts: the front legs on the step, the rear segment lifted), or with ``up`` leans up
    beyond +:data:`LEAN` (a climbable step detected ahead); None if never."""
    bj = np.asarray(bj_command)[after:]
    idx = np.flatnonzero(bj > LEAN if up else bj < -LEAN)
    return int(idx[0]) + after if len(idx) else None


def keep_first_platform(ep: Episode) -> dict[str, Any]:
    """``first_platform_step`` of a climbing-track run (:func:`first_platform_step`; the second platform is the
    summary's ``exit_step``) and ``detected_step``, when the backbone first leaned up for a step ahead
    (:func:`climb_step` with ``up``: the paper's "detected the platform as a climbable obstacle")."""
    tr = ep.trajectory
    return {
        "first_platform_step": first_platform_step(tr.pose, ep.config.arena_opts["step"]),
        "detected_step": climb_step(tr.targets[:, -1], up=True),
    }


FIRST_PLATFORM = Term("first_platform", keep_first_platform)


def track_success(summary: dict[str, Any], step: float) -> bool:
    """The track's success rule (see module doc) from a run's summary."""
    return summary["exit_step"] is not None and summary["max_z_m"] < 2 * step + WALL_HEIGHT


def climbed(summary: dict[str, Any]) -> bool:
    """Whether a ``steps`` run got onto the platform."""
    return summary["exit_step"] is not None


def highest_reliable(rates: dict[float, float]) -> float | None:
    """Highest height whose climb rate, and every lower height's, is at least :data:`RELIABLE`; None if none."""
    best = None
    for h in sorted(rates):
        if rates[h] + 1e-12 < RELIABLE:
            break
        best = h
    return best
