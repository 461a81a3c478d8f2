"""Local leg control: a forward model per leg, the searching reflex and the elevation reflex.

After reference/original_code_facts.md §6 (Manoonpong et al. 2013), written for this package's
pre-motor signals (the TC, CTr and FTi pre-signals of :func:`neurowalk.neural.motor.presignal_step`,
before the motor map; a CTr pre-signal of -1 is the stance command):

* **Forward model** (one recurrent neuron per leg): the expected foot contact follows the leg's own
  stance command with the servo's lag, ``m(t) = w·m(t-1) + (1 - w)·[CTr(t) <= -0.99]``.
* **Error**: ``e = m - c`` with c the foot contact (binarised at ``contact_threshold``): positive
  when the foot should be down and is not (a hole or a step down), negative when it touches while
  it should swing (it hit an edge).
* **Searching reflex**: during stance, a missing contact accumulates into an offset ``E`` that
  lowers the CTr pre-signal (depresses the leg, the foot reaches further down) until the foot
  touches; it is held while the foot stands and decays during swing.
* **Elevation reflex**: a contact during swing where the forward model expects none (``m`` below
  ``elevation_expected``: the foot hit the face of a step, not just left the ground late) lifts the leg for
  ``elevation_steps``: TC pulled back by 0.8, CTr to its top (1.0), FTi to 0.7, the original's
  numbers in pre-signal units, so that the next swing clears the edge.

* **Terrain gain**: the reflexes work at full gain only on uneven terrain (the obstacle-height
  sensor sees a step ahead, or the ground under the front tip or trunk centre is higher than the
  lowest sole, by more than ``terrain_min``; remembered for ``terrain_hold`` steps). On flat ground
  the searching depression is released at lift-off and a swing contact lifts a leg only once its
  CTr command is up (above ``flat_elevation_lift``): otherwise a foot that leaves the ground late
  would trip the elevation reflex at every step, slow the gait and jolt the body (measured: 57
  elevations in 150 s of flat walking, a static robot in the cluttered arena trapped by the jolts).

The original switches these reflexes off for obstacle avoidance; here they are an option of the
controller (``--reflexes``), used for climbing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

STANCE_LEVEL = -0.99  # CTr pre-signal at or below which a leg is commanded to stand


@dataclass(frozen=True, kw_only=True)
class LegControlParams:
    """Parameters of the local leg control (pre-signal units are dimensionless, about [-1, 1])."""

    contact_threshold: float = 0.1  # foot contact signal (0..1) above which the foot counts as down (1 N)
    model_weight: float = 0.6  # forward model's recurrent weight (lag of the expected contact)
    search_expected: float = 0.9  # a missing contact counts only where the forward model is this sure
    search_gain: float = 0.15  # CTr depression added per stance step of missing contact
    search_max: float = 3.0  # largest CTr depression (3 ≈ 45° lower)
    search_decay: float = 0.9  # per swing step
    elevation_expected: float = 0.15  # a contact triggers the elevation reflex only where m is below this
    elevation_steps: int = 5  # control steps an elevation reflex lasts
    elevation_tc: float = -0.8  # TC pre-signal change while elevating (back)
    elevation_ctr: float = 1.0  # CTr pre-signal while elevating (top)
    elevation_fti: float = 0.7  # FTi pre-signal while elevating
    terrain_min: float = 0.02  # m: terrain ahead or under the body higher than this makes the reflexes climb
    terrain_hold: int = 50  # control steps the terrain stays "uneven" after the last reading above terrain_min
    flat_search_decay: float = 0.0  # per swing step on flat ground (the depression is released at lift-off)
    flat_elevation_lift: float = -0.5  # on flat ground the elevation reflex needs the CTr pre-signal above this
    searching: bool = True  # switch the searching reflex
    elevation: bool = True  # switch the elevation reflex

    def __post_init__(self) -> None:
        if not 0.0 < self.contact_threshold < 1.0:
            raise ValueError(f"LegControlParams.contact_threshold must be in (0, 1), got {self.contact_threshold!r}")
        for name in ("model_weight", "search_decay", "flat_search_decay"):
            if not 0.0 <= getattr(self, name) < 1.0:
                raise ValueError(f"LegControlParams.{name} must be in [0, 1), got {getattr(self, name)!r}")
        if self.search_gain < 0 or self.search_max < 0:
            raise ValueError("LegControlParams.search_gain and search_max must be >= 0")
        if self.elevation_steps < 0:
            raise ValueError(f"LegControlParams.elevation_steps must be >= 0, got {self.elevation_steps!r}")


class LegControl:
    """Forward models and reflexes of the six legs (``anatomy.LEGS`` order).

    Attributes (each (6,), after the last :meth:`step`):
        expected: forward-model output, expected contact in [0, 1].
        error: expected minus sensed contact.
        search: CTr depression of the searching reflex (pre-signal units, >= 0).
        elevating: remaining steps of each leg's elevation reflex.
    """

    def __init__(self, params: LegControlParams | None = None) -> None:
        self.params = params or LegControlParams()
        self.reset()

    def reset(self) -> None:
        """Forget all reflex state."""
        self.expected = np.zeros(6)
        self.error = np.zeros(6)
        self.search = np.zeros(6)
        self.elevating = np.zeros(6, dtype=int)
        self.terrain_left = 0

    def step(self, pre: np.ndarray, contact: np.ndarray, uneven: bool = True) -> np.ndarray:
        """Shape the (3, 6) TC/CTr/FTi pre-signals in place from the (6,) foot contacts; returns ``pre``.

        ``uneven``: the terrain sensor sees a step ahead of or under the body (see :meth:`uneven`). On flat
        ground the searching depression is released at lift-off and a swing contact lifts the leg only
        once it is commanded up, so that a foot still leaving the ground does not trip the reflex.
        """
        p = self.params
        stance = pre[1] <= STANCE_LEVEL
        down = np.asarray(contact) > p.contact_threshold
        self.expected = p.model_weight * self.expected + (1.0 - p.model_weight) * stance
        self.error = self.expected - down
        if p.searching:
            missing = np.maximum(self.error, 0.0) * ~down * (self.expected > p.search_expected)
            grown = np.minimum(self.search + p.search_gain * missing, p.search_max)
            self.search = np.where(stance, grown, self.search * (p.search_decay if uneven else p.flat_search_decay))
            pre[1] -= self.search
        if p.elevation:
            hit = ~stance & down & (self.expected < p.elevation_expected)
            if not uneven:
                hit &= pre[1] > p.flat_elevation_lift
            self.elevating = np.where(hit, p.elevation_steps, np.maximum(self.elevating - 1, 0))
            on = self.elevating > 0
            pre[0] = np.where(on, pre[0] + p.elevation_tc, pre[0])
            pre[1] = np.where(on, p.elevation_ctr, pre[1])
            pre[2] = np.where(on, p.elevation_fti, pre[2])
        return pre

    def uneven(self, obstacle_height: float, ground_height: np.ndarray) -> bool:
        """Whether the terrain (m: height ahead, (2,) heights under front tip and centre) is a step to climb.

        Call once per control step: true on a reading above ``terrain_min`` and the ``terrain_hold - 1`` steps after.
        """
        p = self.params
        if obstacle_height > p.terrain_min or bool(np.any(ground_height > p.terrain_min)):
            self.terrain_left = max(p.terrain_hold, 1)
        else:
            self.terrain_left = max(self.terrain_left - 1, 0)
        return self.terrain_left > 0
