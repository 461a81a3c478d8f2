import os
import sys

import pytest

os.environ.setdefault("MUJOCO_GL", "egl")


@pytest.fixture(autouse=True)
def _close_figures():
    """Close the figures a test leaves open (a worker runs many tests; pyplot keeps every open figure)."""
    yield
    if "matplotlib.pyplot" in sys.modules:
        sys.modules["matplotlib.pyplot"].close("all")
