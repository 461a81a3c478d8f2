"""The paper's result in physics, on a smaller count than `neurowalk figure fig5 --seeds 10`."""

import pytest

from neurowalk.experiments.deadlock import VARIANTS, outcome_table


@pytest.mark.slow
def test_plastic_escapes_the_narrow_passage_static_does_not_both_escape_simple_deadlock():
    variants = {k: VARIANTS[k] for k in ("simple-deadlock", "narrow-passage")}
    counts = outcome_table(4, variants=variants, progress=False)["counts"]
    narrow, simple = counts["narrow-passage"], counts["simple-deadlock"]
    assert narrow["plastic"]["escaped"] >= 3
    assert narrow["static"]["escaped"] <= 1
    assert narrow["static"]["trapped"] >= 3
    assert simple["plastic"]["escaped"] >= 3 and simple["static"]["escaped"] >= 3
    # The trapped static robot oscillates: it reverses its turn far more often than the plastic one.
    assert narrow["static"]["median_direction_switches"] > narrow["plastic"]["median_direction_switches"]
    assert set(narrow) == {"plastic", "plastic, start b=2.4 q=3.5", "static", "braitenberg"}


@pytest.mark.slow
@pytest.mark.parametrize("climbing", [False, True], ids=["modules off", "reflexes and backbone on"])
def test_long_runs_static_explores_cluttered_trapped_in_difficult_plastic_explores_difficult(climbing):
    from neurowalk.arenas.spec import WALL_HEIGHT
    from neurowalk.runners.local import run_many
    from neurowalk.sim.episode import EpisodeConfig

    # With climbing on, the original 0.10 m boxes would be steps: they are raised to wall height.
    on = {"reflexes": True, "backbone": True, "arena_opts": {"height": WALL_HEIGHT}} if climbing else {}
    cfgs = [EpisodeConfig(arena="cluttered", controller="static", steps=30000, **on),
            EpisodeConfig(arena="difficult", controller="static", steps=30000, **on),
            EpisodeConfig(arena="difficult", controller="plastic", steps=30000, **on)]  # fmt: skip
    clut_static, diff_static, diff_plastic = run_many(cfgs, progress=False)
    assert not clut_static["trapped"]
    assert diff_static["trapped"] and not diff_plastic["trapped"]
    assert diff_plastic["coverage"] > diff_static["coverage"]
