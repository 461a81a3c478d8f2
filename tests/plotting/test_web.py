"""The web replay's server side (viser, the `web` extra): the slider poses the scene and moves each trace's marker,
a port in use is refused before anything starts, and the export is one HTML file holding the recording."""

from __future__ import annotations

import base64
import re
import socket
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("viser", reason="the web viewer needs the `web` extra (viser)")

from neurowalk.plotting.replay import load_replay
from neurowalk.plotting.web import (
    PortError,
    ReplayPage,
    check_port,
    export_html,
    free_port,
    ray_colours,
    y_ticks,
)


@pytest.fixture(scope="module")
def run_dir(run_folder) -> Path:
    return run_folder("--arena", "narrow-passage", "--steps", "300")


def test_rays_are_green_far_and_red_near():
    far, near, mid = ray_colours(np.array([-1.0, 1.0, 0.0]))
    assert far[1] > far[0] and near[0] > near[1]
    assert np.all(ray_colours(np.array([-5.0, 5.0])) == ray_colours(np.array([-1.0, 1.0])))  # clipped
    assert np.all(np.minimum(far, near) <= mid) and np.all(mid <= np.maximum(far, near))


def test_a_port_in_use_is_refused():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen()
        with pytest.raises(PortError, match=rf"127\.0\.0\.1:{s.getsockname()[1]}"):
            check_port("127.0.0.1", s.getsockname()[1])
    check_port("127.0.0.1", free_port())  # a free one passes


def test_the_slider_poses_the_scene_and_moves_the_markers(run_dir: Path):
    replay = load_replay(run_dir)
    page = ReplayPage(replay, port=free_port())
    try:
        for step in (0, 150, 299):
            page.go(step)
            assert int(page.slider.value) == step
            f = replay.frame_of_step(step)
            for k, handle in enumerate(page.scene.parts):
                assert np.allclose(handle.position, replay.pos[f, k])
            assert f"step {step} of 300" in page.clock.content
            for title, plot, _values in page.plots:
                marker = np.asarray(plot.data[-1])
                lo, hi = page._y[title]
                shown = (marker >= lo) & (marker <= hi)
                assert shown.sum() == 1, title  # one point on the panel: the moment shown
                assert plot.data[0][np.argmax(shown)] == pytest.approx(replay.t[step], abs=1.0)
                assert plot.axes[1]["splits"] == y_ticks(lo, hi), title  # the y axis's ticks: the panel's range
        page.go(10_000)  # past the end: the last step
        assert int(page.slider.value) == 299
    finally:
        page.close()


@pytest.mark.parametrize("lo, hi", [(-1.06, 1.06), (-2.4, 1.7), (-5.3, 2.2), (-0.001, 0.001), (0.2, 0.9)])
def test_a_trace_panel_has_three_to_five_round_ticks_inside_its_range(lo: float, hi: float):
    """uPlot alone gives a short panel one tick (a weights panel read "0", as if it were the axis's label)."""
    ticks = y_ticks(lo, hi)
    assert 3 <= len(ticks) <= 5 and all(lo <= t <= hi for t in ticks) and ticks == sorted(ticks)
    steps = np.diff(ticks)
    assert np.allclose(steps, steps[0])  # evenly spaced round values


def test_the_export_is_one_html_file(run_dir: Path, tmp_path: Path):
    path = tmp_path / "replay.html"
    size = export_html(load_replay(run_dir), path)
    text = path.read_text(encoding="utf-8")
    assert size == path.stat().st_size and text.lstrip().lower().startswith("<!doctype html")
    assert list(tmp_path.iterdir()) == [path]  # nothing else written (no half-written file left)
    assert not re.search(r"""(?:src|href)=["']https?://""", text)  # nothing loaded from elsewhere: it plays offline
    panel = re.search(r'<figure id="neurowalk-traces".*?src="data:image/png;base64,([^"]+)"', text)
    assert panel is not None  # the run's traces beside the replay, as the served page has them
    png = base64.b64decode(panel.group(1))
    assert png.startswith(b"\x89PNG") and len(png) > 10_000
