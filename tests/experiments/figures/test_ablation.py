"""The ablation study of the authors' code's options (``experiments/figures/ablation.py``)."""

from __future__ import annotations

from fake_runs import fake_measure
from neurowalk.experiments import Settings
from neurowalk.experiments.figures import ablation
from neurowalk.experiments.suites.random_envs import coverage_threshold, environments, spec
from neurowalk.neural.variants import CODE_OPTIONS, get_variant
from neurowalk.sim.config import EpisodeConfig
from neurowalk.sim.episode import run_episode


def test_every_arm_differs_from_its_reading_in_one_option():
    arms = ablation.arms()
    assert len(arms) == 2 * len(ablation.SWITCHED) + 1 and "pcpg_first_partial" not in ablation.SWITCHED
    for name, (variant, params) in arms.items():
        if name == "paper + all":
            assert get_variant(variant, params).sensory == get_variant("original").sensory
            continue
        ((option, value),) = params.items()
        assert value == CODE_OPTIONS[option][1 if variant == "paper" else 0]
        assert name == f"{variant} {'+' if variant == 'paper' else '-'} {option}"


def test_a_long_runs_prefix_is_the_shorter_run():
    """The outcome kept at T s of a long run is that of a run of T s (same seed): one run gives every length."""
    env = environments(3, 0)[2]
    long = run_episode(EpisodeConfig.from_spec(spec(env, "plastic", 10_000, "surrogate")))
    short = run_episode(EpisodeConfig.from_spec(spec(env, "plastic", 5_000, "surrogate")))
    kept = ablation.keep_lengths(long)
    assert kept["lengths_s"] == [500.0, 750.0, 1000.0]
    r = short.summary
    assert kept["success"][0] is (not r["trapped"])
    assert kept["success_coverage"][0] is (r["coverage"] >= coverage_threshold(500.0))
    assert kept["success"][2] is (not long.summary["trapped"])


def test_the_physics_arms_switch_the_start_weights_alone_on_amosii():
    arms = ablation.physics_arms()
    assert set(arms) == {"paper", "original"} | {f"{v} {o}" for o in ablation.PHYSICS_OPTIONS
                                                 for v in ("paper +", "original -")}  # fmt: skip
    plans = list(ablation.runs(Settings(quick=True)))
    physics = [p for p in plans if p.label[0] == "physics"]
    assert len(physics) == len(arms) * ablation.QUICK_PHYSICS_ENVS
    assert {p.config.body for p in physics} == {"amosii"} and {p.config.steps for p in physics} == {5000}
    assert len(plans) - len(physics) == (len(ablation.arms()) + 2) * 100  # the surrogate's arms and long runs


def test_fewer_environments_than_the_physics_arms_take_run_and_count_them_all():
    """``--seeds 3``: the physics arms run the 3 environments given (5 when quick, 50 in full), and are counted so."""
    for s, n in ((Settings(quick=True, seeds=3), 3), (Settings(quick=True, seeds=8), ablation.QUICK_PHYSICS_ENVS)):
        configs, result = fake_measure("ablation", s)
        assert sum(c.body == "amosii" for c in configs) == n * len(ablation.physics_arms())
        physics = result.summary["physics"]
        assert physics["environments"] == n
        assert all(arm["environments"] == n for arm in physics["arms"].values())
        assert result.summary["environments"] == s.seeds
