"""The pictures of runs: what their titles say."""

import pytest

from neurowalk.plotting import plot_run, run_title
from neurowalk.sim.episode import EpisodeConfig, run_episode


@pytest.mark.parametrize("body", ["surrogate", "surrogate-wheeled"])
def test_the_run_picture_names_the_body(body):
    ep = run_episode(EpisodeConfig(arena="box", body=body, steps=20))
    fig = plot_run(ep.trajectory, ep.arena, ep.summary)
    assert fig.axes[0].get_title() == f"box, {body}, plastic, 20 steps, seed 0"


def test_the_title_names_a_users_robot_by_its_file_and_the_fixed_steering():
    summary = {"arena": "open", "body": "mjcf:/home/me/robots/crab.xml", "controller": "fixed", "steer": [-1, 1],
               "steps": 5, "seed": 3}  # fmt: skip
    assert run_title(summary) == "open, mjcf:crab.xml, fixed (-1, 1), 5 steps, seed 3"
