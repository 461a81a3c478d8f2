"""The web replay as a person sees it, in headless Chromium (software WebGL): the robot is drawn, moving the slider
with the keyboard moves the robot and each trace's marker, and an exported file plays with no server. Screenshots go
to $NEUROWALK_SCREENSHOTS (else pytest's temporary folder of the test) for a person to look at."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest
from cdp import CHROMIUM, Browser, changed

pytest.importorskip("viser", reason="the web viewer needs the `web` extra (viser)")
if CHROMIUM is None:
    pytest.skip("no chromium to look at the page with (Debian: apt install chromium)", allow_module_level=True)

from neurowalk.plotting.replay import load_replay
from neurowalk.plotting.web import ReplayPage, free_port

SCENE = (0.0, 0.1, 0.7, 1.0)  # the 3-D view: left of the control panel, below the notices
PANEL = (0.74, 0.2, 1.0, 1.0)  # the control panel's traces
SLIDER = "document.querySelector('[role=slider]')"


def _shots(tmp_path: Path) -> Path:
    folder = Path(os.environ.get("NEUROWALK_SCREENSHOTS") or tmp_path)
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def _run(folder: Path, *args: str) -> Path:
    cmd = [sys.executable, "-m", "neurowalk", "run", "--arena", "narrow-passage", "--out", str(folder), *args]
    subprocess.run(cmd, check=True, capture_output=True)
    return folder


@pytest.mark.parametrize("body", ["amosii", "surrogate"])
def test_the_slider_moves_the_robot_and_the_markers(body: str, tmp_path: Path):
    replay = load_replay(_run(tmp_path / body, "--body", body, "--steps", "2000"))
    page = ReplayPage(replay, port=free_port())
    try:
        with Browser() as b:
            b.open(f"http://127.0.0.1:{page.server.get_port()}/")
            b.wait_for(f"{SLIDER} !== null && document.querySelectorAll('canvas').length > 1")
            first = b.settled()
            b.evaluate(f"{SLIDER}.focus()")
            b.key("End", "End", 35)  # the slider to the run's last step, as a person would with the keyboard
            b.wait_for(f"{SLIDER}.getAttribute('aria-valuenow') === '{replay.steps - 1}'")
            deadline = time.monotonic() + 30
            while int(page.slider.value) != replay.steps - 1 and time.monotonic() < deadline:
                time.sleep(0.1)
            assert int(page.slider.value) == replay.steps - 1  # the page told the server
            last = b.settled()
            for part in page.scene.parts:
                part.visible = False
            time.sleep(1)
            empty = b.settled()
            b.save(last, _shots(tmp_path) / f"viewer-{body}.png")
    finally:
        page.close()
    assert changed(first, last, SCENE) > 1e-3  # the robot (and its path) moved
    assert changed(first, last, PANEL) > 1e-4  # the traces' markers followed
    assert changed(last, empty, SCENE) > 5e-4  # the robot is drawn: without it the scene differs


def test_an_exported_file_plays_with_no_server(tmp_path: Path):
    run = _run(tmp_path / "run", "--steps", "1000")
    html = tmp_path / "replay.html"
    subprocess.run([sys.executable, "-m", "neurowalk", "view", str(run), "--export", str(html)], check=True)
    with Browser() as b:
        b.open(html.as_uri())
        b.wait_for("document.querySelectorAll('canvas').length > 0")
        time.sleep(4)
        early = b.screenshot()
        # It plays: the robot walks on. Software WebGL on a loaded machine (the suite's other worker) draws slowly,
        # so the page gets up to 40 s to show it; a page that does not play never does.
        for _ in range(10):
            time.sleep(4)
            later = b.screenshot()
            if changed(early, later, (0.0, 0.2, 1.0, 0.9)) > 1e-3:
                break
        b.save(later, _shots(tmp_path) / "viewer-export.png")
    assert changed(early, later, (0.0, 0.2, 1.0, 0.9)) > 1e-3
