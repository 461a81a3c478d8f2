"""A study's plan of one run (:class:`Plan`): what ``Study.runs`` yields and what ``measure`` gets back with each run.

Its own small module (no heavy import): the study and the result store both use it.
"""

from __future__ import annotations

from collections.abc import Hashable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from neurowalk.sim.config import EpisodeConfig

Label = Hashable

#: The settings a run can fix itself (:attr:`Plan.fixed`): those :meth:`Settings.apply` sets on a config.
RUN_SETTINGS = ("body", "climbing", "variant", "params", "gait", "engine", "control_hz")


@dataclass(frozen=True)
class Plan:
    """One run a study asks for: what ``Study.runs`` yields, and (with the settings applied) what its ``measure``
    gets back with each run's summary (:attr:`Kept.plan <neurowalk.experiments.study_runs.Kept.plan>`).

    Attributes:
        label: its condition (a string or a tuple): the runs of one label are measured together, in order.
        config: the run.
        terms: what the runner keeps of it beside its summary (:class:`~neurowalk.experiments.study_runs.Term`).
        fixed: the run settings (:data:`RUN_SETTINGS`) it fixes itself: :meth:`Settings.apply` leaves them.
    """

    label: Label
    config: EpisodeConfig
    terms: tuple[Any, ...] = ()  # Terms (experiments.stores, which imports this module)
    fixed: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "terms", tuple(self.terms))
        object.__setattr__(self, "fixed", tuple(self.fixed))
        unknown = set(self.fixed) - set(RUN_SETTINGS)
        if unknown:
            raise ValueError(f"a plan fixes only run settings {RUN_SETTINGS}, got {sorted(unknown)}")
