"""Gaits by name (--gait): faster gaits walk faster on the physics robot; the choice is part of a run's spec."""

from __future__ import annotations

import pytest

from neurowalk.runners.specs import spec_key
from neurowalk.sim.episode import EpisodeConfig, run_episode


def _speed(gait: str) -> float:
    cfg = EpisodeConfig(arena="open", controller="fixed", steer=(-1.0, -1.0), steps=1000, gait=gait)
    return run_episode(cfg).summary["forward_displacement_m"] / 100.0  # m/s over 100 s


def test_a_higher_modulatory_input_walks_faster():
    slow, wave, tetrapod = _speed("slow-wave"), _speed("wave"), _speed("tetrapod")
    assert 0 < slow < wave < tetrapod
    assert tetrapod > 1.5 * wave


def test_gait_is_in_the_spec_only_when_not_the_default():
    assert "gait" not in EpisodeConfig.from_spec({"arena": "open"}).spec()
    assert EpisodeConfig.from_spec({"arena": "open", "gait": "tripod"}).spec()["gait"] == "tripod"
    assert spec_key({"arena": "open", "gait": "wave"}) == spec_key({"arena": "open"})


BAD = [({"gait": "trot"}, "unknown gait 'trot'"), ({"gait": "tripod", "body": "surrogate"}, "calibrated on the wave")]


@pytest.mark.parametrize("spec,word", BAD)
def test_bad_gaits_are_refused(spec, word):
    with pytest.raises(ValueError, match=word):
        EpisodeConfig.from_spec(spec).spec()
