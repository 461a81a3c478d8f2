"""Climbing outcomes shared by ``fig10`` and ``steps``: run specs and success rules.

* On ``climbing-track`` (plastic network, reflexes and backbone control on) a run succeeds when the
  trunk centre reaches the second platform (0.3 m beyond its edge) within :data:`TRACK_STEPS` control
  steps and the trunk never rose to the top of a wall (``max_z`` below the wall tops, 2 x step + 0.20 m).
* On ``steps`` (steering fixed straight ahead, so only the climbing modules decide) a run climbs when
  the trunk centre gets 0.3 m onto the platform within :data:`STEP_STEPS` steps. The highest step
  climbed reliably is the highest height at which at least :data:`RELIABLE` of the seeds climbed, all
  lower heights included.
"""

from __future__ import annotations

from typing import Any

from neurowalk.arenas.spec import WALL_HEIGHT

TRACK_STEPS = 12_000  # 1200 s at 10 Hz
TRACK_HEIGHTS = (0.06, 0.08, 0.10)  # m
STEP_STEPS = 3000  # 300 s
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
    f"success: the trunk centre reaches the second platform (0.3 m past its edge) within {TRACK_STEPS} "
    f"control steps, and never rises to a wall's top (max trunk z < 2 x step + {WALL_HEIGHT} m)"
)
STEP_RULE = (
    f"climbed: the trunk centre gets 0.3 m onto the platform within {STEP_STEPS} control steps (steering "
    f"fixed straight ahead); reliable: at least {RELIABLE:.0%} of the seeds at that height and every lower "
    "one"
)


def track_spec(step: float, seed: int, steps: int = TRACK_STEPS, variant: str = "paper") -> dict[str, Any]:
    """Run spec of one climbing-track run (plastic network ``variant``, reflexes and backbone control)."""
    out = {
        "arena": "climbing-track",
        "arena_opts": {"step": step},
        "controller": "plastic",
        "steps": steps,
        "seed": seed,
        "reflexes": True,
        "backbone": True,
    }
    return {**out, "variant": variant} if variant != "paper" else out


def step_spec(height: float, variant: str, seed: int, steps: int = STEP_STEPS) -> dict[str, Any]:
    """Run spec of one single-step run of an ablation ``variant`` (a key of :data:`VARIANTS`)."""
    return {
        "arena": "steps",
        "arena_opts": {"height": height},
        "controller": "fixed",
        "steer": [-1.0, -1.0],
        "steps": steps,
        "seed": seed,
        **{k: v for k, v in VARIANTS[variant].items() if v},
    }


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
