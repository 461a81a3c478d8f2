"""What a run gives, typed: :class:`RunSummary`, read by attribute, from a run's ``summary.json`` dict and back.

The files on disk keep their format (a JSON object, ``sim/summarize.py``); :meth:`RunSummary.from_dict` reads it,
today's and older ones (a key added later is None where an older run lacks it), and keeps any key it does not know
in :attr:`RunSummary.others`, so that :meth:`RunSummary.to_dict` gives the dict back.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from neurowalk.sim.config_values import FrozenDict, freeze


@dataclass(frozen=True, kw_only=True)
class RunSummary:
    """One run's outcome (units in the names: m, s, deg; steps are control steps).

    Attributes:
        arena: the arena's name.
        controller: the network (plastic, static, braitenberg) or ``fixed``.
        body: the robot.
        steps: control steps run.
        seed: the run's seed.
        control_hz: control rate, Hz.
        noise: strength of the sensor noise, in [0, 1].
        variant: the network's variant (``paper``, ``original``, ``tuned``).
        gait: the CPG's gait.
        arena_opts: the arena's options, all filled in.
        body_opts: the body's options as given.
        body_settings: every option of the body with the value the run used: given, or its default (None: an older
            run).
        physics: the physics as it ran (``body.registry.physics_settings``: the step after fitting to the control
            rate, its substeps, integrator, solver, cone, Jacobian, iterations, tolerance); None: a planar body.
        params: SensoryParams fields set over the variant, or None.
        steer: (O1, O2) of a ``fixed`` controller, or None.
        start_weights: the plastic network's start weights {b0, q0}, or None.
        reflexes: local leg control was on.
        backbone: backbone joint control was on.
        final_z_m: trunk height after the last step, m (None: a planar body).
        max_z_m: the trunk's highest, m (None: a planar body).
        exit_step: the control step the trunk reached the exit region (None: never).
        escaped: it reached the arena's exit region (None: the arena has none).
        trapped: the trunk stayed within a disc of radius 0.5 m over the last 300 s.
        ever_trapped: it did so over some 300 s of the run.
        ever_held_up_1000s: it did so over some 1000 s (None: an older run).
        end_turn_share: share of the last 300 s spent turning on the spot (mixed signs of O1, O2), in [0, 1].
        end_blind_share: share of the last 300 s with both sensors seeing nothing, in [0, 1].
        coverage: share of the arena's free 0.25 m cells the trunk visited, in [0, 1] (None: an unbounded arena).
        path_length_m: length of the trunk's path, m.
        forward_displacement_m: displacement along the start heading, m.
        net_displacement_m: straight-line distance from the start, m.
        heading_change_deg: net change of heading, deg (positive: left).
        min_up_z: lowest z of the trunk's up vector (below 0: it turned over).
        direction_switches: sign changes of the steering.
        turn_episodes: avoidance turns.
        max_turn_deg: the largest avoidance turn, deg.
        wedged_periods: periods held within a small region (``metrics.wedged_periods``).
        longest_wedged_s: the longest of them, s.
        wedged_causes: their count per cause ("body contact", "both rays blind", "other").
        wedged: the periods: start, end (steps), duration_s, centre, extent_m, fractions, cause,
            heading_range_deg, held (runs of held steps: [start, end]) and held_s.
        held_periods: runs of held steps (in the disc with the heading within 30 degrees; None: an older run).
        longest_held_s: the longest of them, s (None: an older run).
        turning_periods: wedged periods with no held step: slow turns in place (None: an older run).
        final_pose: (x m, y m, yaw rad) after the last step.
        final_weights: b (2,), q (2,) and c of the plastic network at the end (None: a fixed controller).
        simulation_warnings: MuJoCo's warnings by kind (count).
        wall_time_s: the run's wall time, s (not kept in a result store).
        real_time_factor: simulated over wall time (not kept in a result store).
        neurowalk_version: the version that ran it.
        code: the fingerprint of the code that computed it (:func:`neurowalk.fingerprint.code`; None: an older run).
        others: keys this class does not name (e.g. an engine's ``device``), kept as they came.
    """

    arena: str
    controller: str
    body: str
    steps: int
    seed: int
    control_hz: float = 10.0
    noise: float = 0.02
    variant: str = "paper"
    gait: str = "wave"
    arena_opts: Mapping[str, Any] = field(default_factory=FrozenDict)
    body_opts: Mapping[str, Any] = field(default_factory=FrozenDict)
    body_settings: Mapping[str, Any] | None = None
    physics: Mapping[str, Any] | None = None
    params: Mapping[str, Any] | None = None
    steer: tuple[float, ...] | None = None
    start_weights: Mapping[str, float] | None = None
    reflexes: bool = False
    backbone: bool = False
    final_z_m: float | None = None
    max_z_m: float | None = None
    exit_step: int | None = None
    escaped: bool | None = None
    trapped: bool = False
    ever_trapped: bool = False
    ever_held_up_1000s: bool | None = None
    end_turn_share: float | None = None
    end_blind_share: float | None = None
    coverage: float | None = None
    path_length_m: float = 0.0
    forward_displacement_m: float = 0.0
    net_displacement_m: float | None = None
    heading_change_deg: float = 0.0
    min_up_z: float | None = None
    direction_switches: int = 0
    turn_episodes: int = 0
    max_turn_deg: float = 0.0
    wedged_periods: int = 0
    longest_wedged_s: float = 0.0
    wedged_causes: Mapping[str, int] = field(default_factory=FrozenDict)
    wedged: tuple[Mapping[str, Any], ...] = ()
    held_periods: int | None = None
    longest_held_s: float | None = None
    turning_periods: int | None = None
    final_pose: tuple[float, ...] = ()
    final_weights: Mapping[str, Any] | None = None
    simulation_warnings: Mapping[str, int] = field(default_factory=FrozenDict)
    wall_time_s: float | None = None
    real_time_factor: float | None = None
    neurowalk_version: str | None = None
    code: str | None = None
    others: Mapping[str, Any] = field(default_factory=FrozenDict)

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> RunSummary:
        """The summary of a run's dict (``summary.json``, a store's result); ValueError naming a missing key."""
        names = {f.name for f in dataclasses.fields(cls)} - {"others"}
        missing = [n for n in ("arena", "controller", "body", "steps", "seed") if n not in d]
        if missing:
            raise ValueError(f"not a run's summary: no {', '.join(missing)}")
        known = {k: freeze(v) for k, v in d.items() if k in names}
        return cls(**known, others=FrozenDict({k: freeze(v) for k, v in d.items() if k not in names}))

    def to_dict(self) -> dict[str, Any]:
        """The dict it was read from (JSON-able; the keys an older run lacked are None or their defaults)."""
        d = {f.name: _thaw(getattr(self, f.name)) for f in dataclasses.fields(self) if f.name != "others"}
        return {**d, **_thaw(self.others)}

    @property
    def exit_s(self) -> float | None:
        """Seconds to leave the trap (None: never)."""
        return None if self.exit_step is None else self.exit_step / self.control_hz


def _thaw(v: Any) -> Any:
    """``v`` with its frozen mappings as dicts and its tuples as lists (JSON's shapes)."""
    if isinstance(v, Mapping):
        return {k: _thaw(x) for k, x in v.items()}
    if isinstance(v, tuple | list):
        return [_thaw(x) for x in v]
    return v
