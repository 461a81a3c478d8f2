"""Arenas with more structure: the complex path of paper Fig. 9, and random box fields (Fig. 6, Table 2)."""

from __future__ import annotations

import math

import numpy as np

from neurowalk.arenas import arena
from neurowalk.arenas.deadlocks import EXIT_MARGIN, HEIGHT, WALL, wall
from neurowalk.arenas.spec import ArenaSpec, Box
from neurowalk.body.amosii_params import BodyParams

_BODY = BodyParams()

# Geometry of the complex path (paper Fig. 9). The paper's text gives the layout ("side walls on the right,
# small obstacles on the left, and deadlock at the end of the path"; the robot enters the path, turns right at
# an obstacle on its left, walks to the end, turns left away from the dead end and goes out of the path); its
# numbers below come from the robot's sensor and leg geometry (``BodyParams``), none from run outcomes.
# * Sensor reach. Each ultrasonic ray starts us_y = 0.0175 m off the trunk axis, 1 mm ahead of the front face,
#   and is yawed us_yaw = 35° outward; echoes farther than us_range = 0.40 m read as none. A side parallel to
#   the path, d m from the robot's axis, meets its ray at r = (d - us_y) / sin(us_yaw): it is seen while
#   d < us_y + us_range sin(us_yaw) = 0.247 m (US_REACH).
# * Leg reach. Walking straight or turning on the spot, the feet reach 0.200 m to either side of the trunk
#   axis (foot centres, measured on the MuJoCo model), 0.215 m with the 0.015 m foot radius (FOOT_REACH), and
#   0.33 m from the trunk centre in any direction (TURN_RADIUS, the circle it needs to turn on the spot).
# * width = 0.46 m: the right wall's face and the left obstacles' faces 0.23 m either side of the centre line,
#   the middle of [FOOT_REACH, US_REACH]: the feet clear each side by 1.5 cm and the rays meet both sides at
#   0.37 m (93% of their range), so walking down the centre line the robot senses both. Wider than 2 x 0.247 m
#   and a side leaves the rays' reach; narrower than 2 x 0.215 m and the feet rub both sides.
# * obstacle = 0.20 m: "small" obstacles, half the robot's 0.43 m width and length.
# * spacing = 0.40 m (centre to centre): gaps as wide as the obstacles, so the left ray meets an obstacle on half
#   of the path (the right wall: all of it), and the 0.20 m gaps are narrower than the robot (0.43 m across the
#   feet): it cannot walk out between two obstacles.
# * The dead end: the end wall closes the path; the obstacle row stops OPENING = 0.70 m (2 x TURN_RADIUS,
#   rounded up) before it, so the end is a corner of the right wall and the end wall with room on the left to
#   turn away from it, as the paper's robot did before it went out of the path.
# * The robot starts on the centre line MOUTH = 0.30 m before the path's open end (the paper: it "first
#   entered the path" at 0:00): every box must stay ROBOT_RADIUS = 0.25 m clear of the start.
# * length = 3.0 m, the open end to the end wall (the paper gives none): six obstacles line the left side
#   before the opening at the default spacing.

#: Lateral reach (m) of the ultrasonic rays from the trunk axis: us_y + us_range sin(us_yaw) = 0.247 m.
US_REACH = _BODY.us_y + _BODY.us_range * math.sin(_BODY.us_yaw)
FOOT_REACH = 0.215  # m, feet to either side of the trunk axis while walking or turning (measured, foot radius incl.)
TURN_RADIUS = 0.33  # m, the feet's reach from the trunk centre while turning on the spot (measured)
MOUTH = 0.30  # m, from the start to the path's open end
OPENING = 0.70  # m, free left side between the last obstacle and the end wall


@arena("complex-path")
def complex_path(length: float = 3.0, width: float = 0.46, obstacle: float = 0.2, spacing: float = 0.4) -> ArenaSpec:
    """A path with a wall on the right, small obstacles on the left and a dead end (paper Fig. 9).

    The robot starts on the path's centre line (y = 0) facing +x, :data:`MOUTH` m before its open end.
    Options (m): ``length`` from the open end to the end wall; ``width`` between the right wall's face
    (y = -width/2) and the left obstacles' faces (y = +width/2); ``obstacle`` the side of the square left
    obstacles; ``spacing`` their centre-to-centre distance along the path. The obstacle row stops
    :data:`OPENING` m before the end wall. Walking down the centre line, the rays see both sides at the
    default width (see the comment block above for the reasons of every number).

    Exit region: the trunk centre more than ``EXIT_MARGIN`` (0.3 m) beyond the obstacle row's outer edge
    (the robot went out of the path on the left).
    """
    if not 0.3 <= width <= 2.0:
        raise ValueError(f"arena 'complex-path': width must be in [0.3, 2] m, got {width}")
    if not 0.05 <= obstacle <= 0.5:
        raise ValueError(f"arena 'complex-path': obstacle must be in [0.05, 0.5] m, got {obstacle}")
    if not obstacle < spacing <= 2.0:
        raise ValueError(f"arena 'complex-path': spacing must be in (obstacle = {obstacle}, 2] m, got {spacing}")
    if not OPENING + obstacle <= length <= 20.0:
        raise ValueError(f"arena 'complex-path': length must be in [{OPENING + obstacle:g}, 20] m, got {length}")
    x_end = MOUTH + length  # inner face of the end wall
    y_right, y_left = -width / 2, width / 2  # faces of the right wall and of the left obstacles
    y_outer = y_left + obstacle  # outer edge of the obstacle row
    boxes = [
        wall(MOUTH, y_right - WALL / 2, x_end + WALL, y_right - WALL / 2),
        wall(x_end + WALL / 2, y_right - WALL, x_end + WALL / 2, y_outer + EXIT_MARGIN),
    ]
    n = math.floor((length - OPENING - obstacle) / spacing + 1e-9) + 1
    for k in range(n):
        x = MOUTH + k * spacing + obstacle / 2
        boxes.append(Box(x=x, y=y_left + obstacle / 2, yaw=0.0, sx=obstacle, sy=obstacle, h=HEIGHT))
    exit_region = (-5.0, x_end + 5.0, y_outer + EXIT_MARGIN, y_outer + 5.0)
    bounds = (-EXIT_MARGIN - 0.3, x_end + WALL + 0.3, y_right - WALL - EXIT_MARGIN - 0.3, y_outer + EXIT_MARGIN + 0.5)
    return ArenaSpec(name="complex-path", boxes=tuple(boxes), exit_region=exit_region, bounds=bounds)


@arena("random")
def random_boxes(
    n_boxes: int = 10, size: float = 0.6, extent: float = 6.0, rng: np.random.Generator | None = None
) -> ArenaSpec:
    """Surrounding walls around an ``extent`` x ``extent`` m field of ``n_boxes`` boxes of side ``size`` (m).

    Positions and yaws are drawn from the run's Generator; no box comes within reach of the start
    (the centre, facing a random direction).
    """
    if not 0 <= n_boxes <= 60:
        raise ValueError(f"arena 'random': n_boxes must be in [0, 60], got {n_boxes}")
    if not 0.1 <= size <= 2.0:
        raise ValueError(f"arena 'random': size must be in [0.1, 2] m, got {size}")
    if not 2.0 <= extent <= 30.0:
        raise ValueError(f"arena 'random': extent must be in [2, 30] m, got {extent}")
    rng = rng if rng is not None else np.random.default_rng(0)
    h = extent / 2
    e = h + WALL / 2  # centre line of the surrounding walls
    walls = (wall(-h, e, h, e), wall(-h, -e, h, -e), wall(-e, -e, -e, e), wall(e, -e, e, e))
    keep_out = ArenaSpec.ROBOT_RADIUS + 0.25  # m of free floor around the start
    boxes: list[Box] = []
    for _ in range(1000 * max(n_boxes, 1)):
        if len(boxes) == n_boxes:
            break
        x, y = rng.uniform(-h + size / 2, h - size / 2, size=2)
        b = Box(x=float(x), y=float(y), yaw=float(rng.uniform(0, math.pi / 2)), sx=size, sy=size, h=HEIGHT)
        if not b.contains(np.zeros((1, 2)), margin=keep_out)[0]:
            boxes.append(b)
    if len(boxes) < n_boxes:
        raise ValueError(f"arena 'random': cannot place {n_boxes} boxes of {size} m in {extent} m")
    start = (0.0, 0.0, float(rng.uniform(-math.pi, math.pi)))
    return ArenaSpec(name="random", boxes=walls + tuple(boxes), start=start, bounds=(-h, h, -h, h))
