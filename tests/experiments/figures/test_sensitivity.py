"""The sensitivity study: each invented dimension at 0.8, 1.0 and 1.2 x its default, and what its verdict says."""

import pytest

from fake_runs import fake_measure, plan, summary_of
from neurowalk.arenas import arena_options, make_arena
from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.figures import sensitivity
from neurowalk.experiments.figures.sensitivity import CASES, FACTORS, claims, size


def test_each_dimension_is_scaled_from_its_default():
    assert size("narrow passage: gap", 0.8) == pytest.approx(0.8 * arena_options("narrow-passage")["gap"])
    assert size("simple dead end: depth", 1.2) == pytest.approx(1.2 * arena_options("simple-deadlock")["depth"])
    assert size("climbing track: step to wall", 1.0) == arena_options("climbing-track")["wall_x"]
    # the wall's distance from the first step's edge (0.7 m) is scaled, not its x
    assert size("climbing track: step to wall", 1.2) - 0.7 == pytest.approx(1.2 * (2.0 - 0.7))
    for case, (arena, option, _, _) in CASES.items():
        for f in FACTORS:
            assert make_arena(arena, **{option: size(case, f)}).options[option] == size(case, f)  # a valid arena


def test_every_cell_runs_each_network_of_its_claim_stopped_once_decided():
    runs = plan("sensitivity", Settings(seeds=2))
    labels = {p.label for p in runs}
    assert len(runs) == 2 * len(labels) == 2 * sum(len(nets) for *_, nets in CASES.values()) * len(FACTORS)
    for p in runs:
        case, f, net = p.label
        arena, option, _, _ = CASES[case]
        c = p.config
        assert c.arena == arena and c.arena_opts[option] == size(case, f) and c.controller == net
        assert c.until == "escaped" and c.control_hz == 10.0
        if arena == "climbing-track":
            assert c.reflexes and c.backbone and c.arena_opts["step"] == sensitivity.STEP


def _summary(held: dict[float, int], runs: int = 3) -> dict:
    cells = [{"factor": f, "value_m": f, "plastic": {"runs": runs, "as_paper": held[f]}} for f in FACTORS]
    case = {"arena": "a", "option": "gap", "figures": "Fig. 8", "paper": {"plastic": "escaped"}, "cells": cells}
    return {"cases": {"narrow passage: gap": case}}


@pytest.mark.parametrize(
    ("held", "verdict"),
    [
        ({0.8: 3, 1.0: 2, 1.2: 2}, "reproduced"),  # two thirds in every cell: it does not hinge on the number
        ({0.8: 3, 1.0: 2, 1.2: 1}, "partly"),  # at the default only: it hinges on it
        ({0.8: 3, 1.0: 1, 1.2: 3}, "not"),  # not at the default
    ],
)
def test_the_verdict_says_whether_a_claim_hinges_on_the_number(held, verdict):
    (c,) = claims(_summary(held), False)
    assert c.verdict == verdict and c.measured == f"{sum(held.values())}/9"
    assert "x0.8" in c.rule and "x1.2" in c.rule


def test_measure_counts_the_runs_that_ended_as_the_papers():
    def trapped_when_narrow(cfg):  # escapes everywhere but the narrowest gap
        narrow = cfg.arena == "narrow-passage" and cfg.arena_opts.get("gap", 1) < 0.25
        return summary_of(cfg, escaped=not narrow, max_z_m=0.1)

    _, res = fake_measure("sensitivity", Settings(seeds=1), trapped_when_narrow)
    gap = res.summary["cases"]["narrow passage: gap"]["cells"]
    assert [c["plastic"]["as_paper"] for c in gap] == [0, 1, 1]  # escaped, as the paper's
    assert [c["static"]["as_paper"] for c in gap] == [1, 0, 0]  # trapped, as the paper's
    track = res.summary["cases"]["climbing track: step to wall"]["cells"]
    assert all(c["plastic"]["as_paper"] == 1 for c in track)
    verdicts = {c.what.split(" across")[0]: c.verdict for c in FIGURES["sensitivity"].claims(res.summary, False)}
    assert verdicts["narrow passage: gap: plastic escaped"] == "partly"
    assert verdicts["narrow passage: gap: static trapped"] == "not"
