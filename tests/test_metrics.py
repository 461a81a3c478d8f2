import numpy as np
import pytest

from neurowalk import metrics
from neurowalk.arenas import make_arena


def _pose(xy, yaw=None):
    xy = np.asarray(xy, dtype=float)
    return np.column_stack([xy, np.zeros(len(xy)) if yaw is None else yaw])


def test_trapped_escaped_coverage_path():
    arena = make_arena("simple-deadlock")
    still = _pose(np.full((4000, 2), 0.3))
    assert metrics.trapped(still) and not metrics.escaped(still, arena)
    out = _pose(np.column_stack([np.linspace(0, -2.0, 4000), np.zeros(4000)]))
    assert not metrics.trapped(out) and metrics.escaped(out, arena)
    assert not metrics.trapped(still[:100])  # too short to tell
    assert metrics.path_length(out) == pytest.approx(2.0)
    c1, c2 = metrics.coverage(still, arena), metrics.coverage(out, arena)
    assert 0 < c1 < c2 <= 1
    assert metrics.coverage(still, make_arena("open")) is None
    assert metrics.escaped(still, make_arena("open")) is None


def test_direction_switches_and_episodes():
    right, left, none = (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)
    outputs = np.array([none] * 5 + [right] * 10 + [none] * 3 + [right] * 4 + [left] * 6 + [none] * 5)
    assert metrics.direction_switches(outputs) == 1
    yaw = np.concatenate([np.zeros(5), -np.linspace(0, 1, 10), -np.ones(3), -1 - np.linspace(0, 0.2, 4),
                          -1.2 + np.linspace(0, 0.5, 6), np.full(5, -0.7)])  # fmt: skip
    eps = metrics.avoidance_episodes(outputs, _pose(np.zeros((len(yaw), 2)), yaw))
    assert [e["direction"] for e in eps] == [1, -1]  # the short gap is bridged
    assert eps[0]["turn_deg"] < 0 < eps[1]["turn_deg"]
