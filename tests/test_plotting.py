"""The pictures of runs: what their titles say, the colour bar of the path, the legends off the data."""

import pytest

from neurowalk.plotting import plot_run, run_title
from neurowalk.plotting.style import panel_letters
from neurowalk.sim.episode import EpisodeConfig, run_episode


@pytest.fixture(scope="module")
def surrogate_run():
    return run_episode(EpisodeConfig(arena="box", body="surrogate", steps=40))


@pytest.mark.parametrize("body", ["surrogate", "surrogate-wheeled"])
def test_the_run_picture_names_the_body_and_the_variant(body):
    ep = run_episode(EpisodeConfig(arena="box", body=body, steps=20))
    fig = plot_run(ep.trajectory, ep.arena, ep.summary)
    assert fig.get_suptitle() == f"box, {body}, plastic, variant paper, 20 steps (2 s), seed 0"


def test_the_title_names_a_users_robot_by_its_file_the_fixed_steering_and_the_variant():
    summary = {"arena": "open", "body": "mjcf:/home/me/robots/crab.xml", "controller": "fixed", "steer": [-1, 1],
               "steps": 5, "seed": 3, "variant": "original", "params": {"k": 2.0}}  # fmt: skip
    assert run_title(summary) == "open, mjcf:crab.xml, fixed (-1, 1), variant original + params, 5 steps, seed 3"


def test_the_path_has_a_time_colour_bar_in_seconds(surrogate_run):
    ep = surrogate_run
    fig = plot_run(ep.trajectory, ep.arena, ep.summary)
    bars = [ax for ax in fig.axes if ax.get_label() == "<colorbar>"]
    assert len(bars) == 1
    assert bars[0].get_ylabel() == "time (s)"
    path = fig.axes[0].collections[0]
    lo, hi = path.get_clim()
    assert lo == 0.0 and hi == pytest.approx(ep.trajectory.t[-1])


def test_every_panel_is_lettered_labelled_and_its_legend_is_off_the_data(surrogate_run):
    ep = surrogate_run
    fig = plot_run(ep.trajectory, ep.arena, ep.summary)
    fig.canvas.draw()
    plots = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
    assert panel_letters(fig) == ["A", "B", "C", "D"]
    assert all(ax.get_ylabel() for ax in plots)
    assert plots[0].get_xlabel() == "x (m)" and plots[-1].get_xlabel() == "time (s)"
    renderer = fig.canvas.get_renderer()
    for ax in plots:
        legend = ax.get_legend()
        assert legend is not None
        box, frame = legend.get_window_extent(renderer), ax.get_window_extent(renderer)
        assert not box.overlaps(frame), ax.get_ylabel()


def test_a_climb_is_in_the_summary_and_its_height_in_the_picture():
    ep = run_episode(EpisodeConfig(arena="steps", arena_opts={"height": 0.08}, reflexes=True, backbone=True,
                                   steps=1500))  # fmt: skip
    s = ep.summary
    assert s["climbed"] is True and s["climbed_at_s"] == pytest.approx(s["exit_step"] / s["control_hz"])
    fig = plot_run(ep.trajectory, ep.arena, s)
    assert panel_letters(fig) == ["A", "B", "C", "D", "E"]
    height = fig.axes[-1]
    assert height.get_ylabel() == "trunk rise (m)" and height.get_xlabel() == "time (s)"
    (rise,) = (line for line in height.get_lines() if line.get_label() == "trunk rise")
    assert max(rise.get_ydata()) > 0.08  # it got up the step
    steps = [line for line in height.get_lines() if line.get_label() == "step height"]
    assert len(steps) == 1 and steps[0].get_ydata()[0] == pytest.approx(0.08)
    assert any(line.get_label().startswith("climbed at ") for line in height.get_lines())


def test_a_run_that_does_not_climb_says_so_and_other_arenas_say_nothing_of_climbs():
    short = run_episode(EpisodeConfig(arena="steps", steps=50))
    assert short.summary["climbed"] is False and short.summary["climbed_at_s"] is None
    flat = run_episode(EpisodeConfig(arena="box", steps=20))
    assert "climbed" not in flat.summary
    assert panel_letters(plot_run(flat.trajectory, flat.arena, flat.summary)) == ["A", "B", "C", "D"]


def test_a_run_is_drawn_from_its_episode_as_from_its_parts(surrogate_run):
    ep = surrogate_run
    whole, parts = plot_run(ep), plot_run(ep.trajectory, ep.arena, ep.summary)
    assert whole.get_suptitle() == parts.get_suptitle() and len(whole.axes) == len(parts.axes)
    with pytest.raises(TypeError, match="an Episode"):
        plot_run(ep.trajectory)
