"""The reproduction's plan: the paper's results, then every registered study that judges its own (Study.claims)."""

from __future__ import annotations

import importlib.util
from types import ModuleType

from neurowalk.experiments import FIGURES, Study
from neurowalk.experiments.reproduce import plan
from neurowalk.experiments.reproduce.claims import holds
from neurowalk.experiments.reproduce.plan import PAPER, PLAN, judged_studies


def test_a_study_with_claims_joins_the_plan_with_its_claims_as_its_judge():
    def claims(summary: dict, quick: bool) -> list:
        rate = summary["rate"]
        return [holds("the plastic network escapes", "escapes", rate > 0.5, rate, f"escape rate {rate} > 0.5")]

    mine = Study("mine", "escape rate of my study", plot=print, runs=print, measure=print, claims=claims)
    (item,) = judged_studies({**FIGURES, "mine": mine}, {i.figure for i in PAPER})
    assert (item.name, item.figure, item.paper) == ("mine", "mine", "escape rate of my study")
    assert [c.verdict for c in item.judge({"rate": 0.9}, False) + item.judge({"rate": 0.1}, True)] == [
        "reproduced",
        "not",
    ]
    assert item.given(quick=True) == {"quick": True} and item.given(quick=False) == {}


def _plan_module() -> ModuleType:
    """The plan module as importing it now makes it (a fresh copy; the imported one is left as it is)."""
    spec = importlib.util.find_spec(plan.__name__)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_plan_is_the_papers_results_then_the_judged_studies(monkeypatch):
    assert {n for n, s in FIGURES.items() if s.claims is not None} <= {i.figure for i in PLAN}
    assert {i.figure for i in PLAN} <= set(FIGURES)
    mine = Study("mine", "my study", plot=print, runs=print, measure=print, claims=lambda summary, quick: [])
    monkeypatch.setitem(FIGURES, "mine", mine)  # registered before the plan is made
    fresh = _plan_module()
    assert [i.name for i in fresh.PLAN] == [*(i.name for i in PAPER), "mine"]
    assert fresh.ITEMS["mine"].paper == "my study"
