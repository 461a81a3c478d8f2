import os
import sys

import pytest

os.environ.setdefault("MUJOCO_GL", "egl")
# The commands the tests start write no compile note (a cold cache would add a line to the stderr many tests read);
# the note's own tests set it as they need.
os.environ.setdefault("NEUROWALK_COMPILE_NOTE", "0")


@pytest.fixture(autouse=True)
def _close_figures():
    """Close the figures a test leaves open (a worker runs many tests; pyplot keeps every open figure)."""
    yield
    if "matplotlib.pyplot" in sys.modules:
        sys.modules["matplotlib.pyplot"].close("all")


@pytest.fixture(scope="session")
def run_folder(tmp_path_factory):
    """``run_folder(*args)``: the folder of ``neurowalk run ARGS`` (made once per session for the same arguments),
    for the tests that read a run's files back (the replay, the viewer)."""
    import subprocess

    made = {}

    def make(*args: str):
        if args not in made:
            out = tmp_path_factory.mktemp("run")
            cmd = [sys.executable, "-m", "neurowalk", "run", *args, "--out", str(out), "--quiet"]
            subprocess.run(cmd, check=True, capture_output=True)
            made[args] = out
        return made[args]

    return make


def pytest_unconfigure(config):
    """At the end of the suite (finished or stopped by Ctrl-C), end the Ray processes its tests started and left in
    its process group (:mod:`leftovers`); an xdist worker leaves it to the controller, which ends after it."""
    if hasattr(config, "workerinput") or not sys.platform.startswith("linux"):
        return
    sys.path.insert(0, os.path.dirname(__file__))
    from leftovers import end_ray

    end_ray(os.getpgrp())
