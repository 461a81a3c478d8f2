"""What ``neurowalk reproduce`` runs: every result of the paper as an :class:`Item` (:data:`PAPER`), and every
registered study that judges its own results (``Study.claims``), in :data:`PLAN`.

An item names the figure that measures it and that figure's settings (typed: :class:`~neurowalk.experiments.Settings`
fields, ``quick`` and the quick ones in a quick reproduction, the full ones otherwise), what the paper shows, and the
judge that reads the figure's saved numbers and gives the paper's results as claims with verdicts (:mod:`.claims`).
Items of the same figure and settings share one run.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from neurowalk.experiments import FIGURES, Study
from neurowalk.experiments.reproduce.claims import Claim

#: The real AMOSII's control rate (paper §2.2: "updated with a frequency of approximately 27 Hz").
REAL_ROBOT_HZ = 27.0


@dataclass(frozen=True)
class Item:
    """One result of the paper and how it is measured and judged.

    Attributes:
        name: the item's name (``DIR/NAME.json``; ``--only NAME``).
        figure: the figure that measures it (``neurowalk figure FIG``).
        paper: what the paper shows, in a line, with where.
        settings: the figure's settings in both modes (:class:`~neurowalk.experiments.Settings` fields).
        full: settings of the full reproduction only.
        quick: settings of the quick one only (with ``quick``).
        claims: its judge where it is not that of the registered figure (a study of a table of one's own).
    """

    name: str
    figure: str
    paper: str
    settings: Mapping[str, Any] = field(default_factory=dict)
    full: Mapping[str, Any] = field(default_factory=dict)
    quick: Mapping[str, Any] = field(default_factory=dict)
    claims: Callable[[dict[str, Any], bool], list[Claim]] | None = None

    def judge(self, summary: dict[str, Any], quick: bool) -> list[Claim]:
        """The paper's results the figure's saved numbers ``summary`` show, judged: its study's ``claims``."""
        return (self.claims or FIGURES[self.figure].claims)(summary, quick)  # type: ignore[misc]

    def given(self, quick: bool) -> dict[str, Any]:
        """The figure's settings in a quick (``quick`` set) or a full reproduction: Settings fields by name."""
        return {**self.settings, **({"quick": True, **self.quick} if quick else self.full)}


PAPER: tuple[Item, ...] = (
    Item("table1", "table1", "Table 1: walking direction for each sign of the outputs O1, O2"),
    Item("fig2", "fig2", "Fig. 2: linear, hysteresis and two-state dynamics of the recurrent neurons"),
    Item(
        "fig3",
        "fig3",
        "Fig. 3: the static network escapes a simple dead end, is trapped in a narrow passage and in "
        "the difficult arena, explores the cluttered one",
    ),
    Item(
        "fig4",
        "fig4",
        "Fig. 4: weights converge for constant inputs, rise and decay for changing ones",
    ),
    Item(
        "fig5",
        "fig5",
        "Fig. 5: the plastic network escapes both dead ends and explores the difficult arena with "
        "weights adapting stably over 1,000,000 time steps",
    ),
    Item(
        "fig6",
        "fig6",
        "Fig. 6: sixteen random environments: one failure, successes facing a confined space and a trap",
    ),
    Item(
        "fig7",
        "fig7",
        "Fig. 7: joint angles of the wave gait, legs swinging one by one from hind to front",
    ),
    Item("table2", "table2", "Table 2: 49 of 50 random environments explored (planar surrogate)"),
    Item(
        "table2-1000",
        "table2",
        "Table 2 on 1000 random environments (planar surrogate; 100 with --quick)",
        full={"seeds": 1000},
        quick={"seeds": 100},
    ),
    Item(
        "table2-physics",
        "table2",
        "Table 2: 49 of 50 random environments explored (physics AMOSII)",
        settings={"body": "amosii"},
    ),
    Item(
        "fig8",
        "fig8",
        "Fig. 8: narrow passage: the plastic network escapes, the static one stays trapped (simulator rate, 10 Hz)",
    ),
    Item(
        "fig8-27hz",
        "fig8",
        "Fig. 8: the real robot (27 Hz) saw the obstacle at 0:10 and escaped the narrow passage at 0:50",
        settings={"control_hz": REAL_ROBOT_HZ},
    ),
    Item(
        "fig9",
        "fig9",
        "Fig. 9: complex path: the plastic network goes out of the path, the static one is stuck "
        "(simulator rate, 10 Hz)",
    ),
    Item(
        "fig9-27hz",
        "fig9",
        "Fig. 9: the real robot (27 Hz) saw an obstacle at 0:20, approached the end at 1:08, went out at 3:20",
        settings={"control_hz": REAL_ROBOT_HZ},
    ),
    Item(
        "fig10",
        "fig10",
        "Fig. 10: climbs a step, avoids a wall, climbs a second step (simulator rate, 10 Hz)",
    ),
    Item(
        "fig10-27hz",
        "fig10",
        "Fig. 10: the real robot (27 Hz) climbed onto the first platform at 0:17-0:23, the second at 1:14",
        settings={"control_hz": REAL_ROBOT_HZ},
    ),
    Item(
        "escape-map",
        "escape-map",
        "Beyond the paper: escape rate against trap size, three networks",
    ),
    Item(
        "sensitivity",
        "sensitivity",
        "Beyond the paper: the outcomes with each invented arena dimension at 0.8-1.2 x",
    ),
    Item(
        "latched-spin",
        "latched-spin",
        "Beyond the paper: the plastic network's failure case of Table 2",
    ),
    Item(
        "ablation",
        "ablation",
        "Beyond the paper: the authors' code's options one at a time in Table 2",
    ),
    Item(
        "steps",
        "steps",
        "Beyond the paper: the highest step climbed with and without backbone control",
    ),
    Item("bodies", "bodies", "Beyond the paper: the networks on a wheeled robot at two sizes"),
    Item(
        "surrogate",
        "surrogate",
        "Beyond the paper: the planar surrogate against the physics robot",
    ),
)


def settings_words(given: dict[str, Any] | tuple[tuple[str, Any], ...]) -> str:
    """A figure's settings in words: ``quick, control_hz 27`` (``default settings`` where none is given)."""
    words = [k if v is True else f"{k} {v:g}" if isinstance(v, float) else f"{k} {v}" for k, v in dict(given).items()]
    return ", ".join(words) or "default settings"


def judged_studies(figures: Mapping[str, Study], named: Iterable[str]) -> tuple[Item, ...]:
    """An item for each study of ``figures`` that judges its own results (``Study.claims``) and that ``named`` (the
    figures of :data:`PAPER`) leaves out: its claims are its judge, its title what it shows."""
    skip = set(named)
    return tuple(
        Item(n, n, s.title, claims=s.claims) for n, s in figures.items() if s.claims is not None and n not in skip
    )


#: Every result ``neurowalk reproduce`` runs and judges: the paper's, then every registered study with claims.
PLAN: tuple[Item, ...] = (*PAPER, *judged_studies(FIGURES, {i.figure for i in PAPER}))
ITEMS: dict[str, Item] = {item.name: item for item in PLAN}
