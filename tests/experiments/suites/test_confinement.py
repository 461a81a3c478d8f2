"""Fig. 6's classes: traps and confined spaces on small arenas where the answer is known, synthetic paths."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from neurowalk.arenas.spec import ArenaSpec, Box
from neurowalk.experiments.suites import confinement
from neurowalk.experiments.suites.confinement import classify, first_left, ray_distances, situations


def _walk(points: list[tuple[float, float]], step: float = 0.05) -> np.ndarray:
    """Poses (x, y, yaw) along the straight legs between ``points``, heading along each leg; a turn on the spot
    (yaw swept in 10 degree steps) between legs."""
    rows: list[tuple[float, float, float]] = []
    for (x0, y0), (x1, y1) in itertools.pairwise(points):
        yaw = math.atan2(y1 - y0, x1 - x0)
        if rows:  # turn on the spot from the last heading to this one
            last = rows[-1][2]
            turn = (yaw - last + math.pi) % (2 * math.pi) - math.pi
            for a in np.linspace(last, last + turn, max(2, int(abs(math.degrees(turn)) / 10) + 1))[1:]:
                rows.append((x0, y0, float(a)))
        n = max(1, int(math.hypot(x1 - x0, y1 - y0) / step))
        rows += [(x0 + (x1 - x0) * t, y0 + (y1 - y0) * t, yaw) for t in np.linspace(0, 1, n + 1)]
    return np.array(rows)


def _arena(*boxes: Box) -> ArenaSpec:
    return ArenaSpec(name="test", boxes=boxes, start=(-2.0, 0.0, 0.0), bounds=(-3.0, 3.0, -3.0, 3.0))


# A U-shaped pocket opening to -x: back wall face at x = 0.9, side faces at y = +-0.35, from x = -0.1 to 1.0.
U_TRAP = _arena(
    Box(x=1.0, y=0.0, yaw=0.0, sx=0.2, sy=1.1),
    Box(x=0.45, y=0.45, yaw=0.0, sx=1.1, sy=0.2),
    Box(x=0.45, y=-0.45, yaw=0.0, sx=1.1, sy=0.2),
)
# A corridor along x: side faces at y = +-0.4, from x = -1 to 1.
CORRIDOR = _arena(Box(x=0.0, y=0.6, yaw=0.0, sx=2.0, sy=0.4), Box(x=0.0, y=-0.6, yaw=0.0, sx=2.0, sy=0.4))
# A 90-degree corner: faces at y = -1 and x = -1.
CORNER = _arena(Box(x=0.5, y=-1.1, yaw=0.0, sx=3.0, sy=0.2), Box(x=-1.1, y=0.5, yaw=0.0, sx=0.2, sy=3.0))


def test_ray_distances_to_a_box_face_its_corner_and_from_inside() -> None:
    box = Box(x=2.0, y=0.0, yaw=0.0, sx=1.0, sy=1.0)
    d = ray_distances([box], np.array([[0.0, 0.0]]), np.array([0.0, math.pi, math.pi / 2]), 5.0)
    assert d[0, 0] == pytest.approx(1.5) and np.isinf(d[0, 1]) and np.isinf(d[0, 2])
    turned = Box(x=2.0, y=0.0, yaw=math.pi / 4, sx=1.0, sy=1.0)  # a corner towards the origin
    assert ray_distances([turned], np.zeros((1, 2)), np.zeros(1), 5.0)[0, 0] == pytest.approx(2.0 - math.sqrt(0.5))
    assert ray_distances([box], np.array([[2.0, 0.1]]), np.zeros(1), 5.0)[0, 0] == 0.0
    assert np.isinf(ray_distances([box], np.zeros((1, 2)), np.zeros(1), 1.0)[0, 0])  # beyond the range


def test_a_pocket_closed_on_three_sides_is_a_trap_a_corridor_and_a_corner_are_not() -> None:
    inside = situations(U_TRAP, np.array([[0.65, 0.0, 0.0]]))
    assert inside["trap"][0] and inside["blocked_deg"][0] >= confinement.TRAP_BLOCKED_DEG
    assert not situations(CORRIDOR, np.array([[0.0, 0.0, 0.0]]))["trap"][0]
    corner = situations(CORNER, np.array([[-0.7, -0.7, math.pi / 4]]))
    assert not corner["trap"][0] and corner["blocked_deg"][0] == pytest.approx(210.0, abs=10.0)


def test_a_success_that_leaves_a_u_shaped_trap_escaped_a_trap() -> None:
    pose = _walk([(-1.5, 0.0), (0.65, 0.0), (-1.5, 0.0)])
    c = classify(U_TRAP, pose, True)
    assert c["class"] == "escaped a trap" and c["faced_trap"]
    assert c["left_trap"] is not None and c["left_trap"][0] > 0.3  # a point in the pocket
    stuck = classify(U_TRAP, _walk([(-1.5, 0.0), (0.65, 0.0)]), False)
    assert stuck["class"] == "failed" and stuck["left_trap"] is None and stuck["end_situation"] == "trap"


def test_a_success_through_a_corridor_passed_a_confined_space() -> None:
    pose = _walk([(-2.0, 0.0), (2.0, 0.0)])
    c = classify(CORRIDOR, pose, True, end_rows=10)
    assert c["class"] == "passed a confined space" and c["faced_confined"] and not c["faced_trap"]
    assert -1.3 <= c["left_confined"][0] <= 1.0  # at the mouth or inside
    assert c["end_situation"] == "open"  # the last 10 rows: out of the corridor
    assert classify(CORRIDOR, pose, False)["class"] == "failed"  # the run's outcome decides a failure
    wide = _arena(Box(x=0.0, y=0.9, yaw=0.0, sx=2.0, sy=0.4), Box(x=0.0, y=-0.9, yaw=0.0, sx=2.0, sy=0.4))
    assert classify(wide, pose, True)["class"] == "plain success"  # sides 0.7 m away: room to turn


def test_turning_out_of_a_corner_or_walking_in_the_open_is_a_plain_success() -> None:
    pose = _walk([(1.5, -0.7), (-0.7, -0.7), (-0.7, 1.5)])  # along one wall into the corner, out along the other
    c = classify(CORNER, pose, True)
    assert c["class"] == "plain success" and not c["faced_confined"] and not c["faced_trap"]
    assert classify(_arena(), _walk([(-2.0, 0.0), (2.0, 2.0)]), True)["class"] == "plain success"


def test_first_left_needs_a_later_point_far_enough() -> None:
    xy = np.array([[0.0, 0.0], [0.5, 0.0], [0.0, 0.0], [1.2, 0.0]])
    assert first_left(xy, np.array([True, False, False, False]), 1.0) == 0
    assert first_left(xy, np.array([False, False, False, True]), 1.0) is None  # nothing after the last point
    assert first_left(xy[:3], np.array([True, True, True]), 1.0) is None  # never 1 m away
