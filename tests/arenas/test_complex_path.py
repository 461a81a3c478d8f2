"""The complex path (paper Fig. 9): both sides within the ultrasonic rays' reach from the centre line."""

import math

import mujoco
import numpy as np
import pytest

from neurowalk.arenas import arena_options, make_arena
from neurowalk.arenas.generated import FOOT_REACH, MOUTH, OPENING, TURN_RADIUS, US_REACH
from neurowalk.body.amosii import AmosII
from neurowalk.body.amosii_params import BodyParams
from neurowalk.body.amosii_sensors import read_us


def _ray_hits(arena, x: float) -> np.ndarray:
    """US_L, US_R distances (m; inf: no echo) of the MuJoCo robot standing at (x, 0) on the centre line, facing +x."""
    body = AmosII(arena)
    body.reset(np.random.default_rng(0))
    body.data.qpos[0] = x
    mujoco.mj_forward(body.model, body.data)
    return read_us(body.model, body.data)


def _left_obstacle_ahead_of_ray(arena, x: float) -> bool:
    """Whether the left ray's line, cast from the robot at (x, 0), crosses an obstacle face at y = +width/2."""
    p = BodyParams()
    y_face = arena.options["width"] / 2
    ox = x + p.trunk_length / 2 + p.us_ahead
    hit_x = ox + (y_face - p.us_y) / math.tan(p.us_yaw)
    half = arena.options["obstacle"] / 2
    return any(abs(hit_x - b.x) < half - 0.01 for b in arena.boxes if abs(b.y - (y_face + half)) < 1e-9)


def test_default_width_lies_between_the_feet_and_the_rays_reach():
    width = arena_options("complex-path")["width"]
    assert abs(US_REACH - 0.247) < 1e-3
    assert FOOT_REACH < width / 2 < US_REACH


def test_walking_down_the_centre_line_the_rays_see_the_right_wall_and_the_left_obstacles():
    arena = make_arena("complex-path")
    p = BodyParams()
    xs = np.arange(MOUTH + 0.05, MOUTH + arena.options["length"] - OPENING - 0.3, 0.05)
    right, left_seen = [], 0
    for x in xs:
        d_left, d_right = _ray_hits(arena, float(x))
        right.append(d_right)
        if _left_obstacle_ahead_of_ray(arena, float(x)):
            assert d_left < p.us_range, f"left obstacle not seen from x = {x:.2f}"
            left_seen += 1
    expected = (arena.options["width"] / 2 - p.us_y) / math.sin(p.us_yaw)
    assert np.allclose(right, expected, atol=0.01)  # the right wall all the way, at the predicted range
    assert expected < p.us_range
    assert left_seen >= len(xs) // 3  # obstacles on half of the row (gaps as wide as the obstacles)


def test_the_old_geometry_was_out_of_reach_and_a_wider_path_is_too():
    # Sides at 0.45 m and 0.75 m (the earlier layout) or just beyond US_REACH are not seen from the centre line.
    wide = make_arena("complex-path", width=2 * (US_REACH + 0.02))
    d_left, d_right = _ray_hits(wide, MOUTH + 0.5)
    assert math.isinf(d_right) and math.isinf(d_left)


def test_layout_gaps_opening_and_exit():
    arena = make_arena("complex-path")
    o = arena.options
    row = sorted(b.x for b in arena.boxes if b.sx == o["obstacle"] and b.sy == o["obstacle"])
    assert len(row) == 6
    assert np.allclose(np.diff(row), o["spacing"])
    assert o["spacing"] - o["obstacle"] < 2 * FOOT_REACH  # the robot cannot walk out between two obstacles
    end_wall = MOUTH + o["length"]
    assert end_wall - (row[-1] + o["obstacle"] / 2) >= OPENING - 1e-9 >= 2 * TURN_RADIUS
    y0 = arena.exit_region[2]
    assert y0 == pytest.approx(o["width"] / 2 + o["obstacle"] + 0.3)
    assert not arena.boxes[0].contains(np.zeros((1, 2)), margin=0.25)[0]


@pytest.mark.parametrize(
    "opts,word",
    [
        ({"width": 0.2}, "width"),
        ({"width": 3.0}, "width"),
        ({"obstacle": 0.01}, "obstacle"),
        ({"spacing": 0.2}, "spacing"),  # no gap: spacing must exceed the obstacle
        ({"spacing": 0.1}, "spacing"),
        ({"spacing": 5.0}, "spacing"),
        ({"length": 0.5}, "length"),
        ({"length": 50.0}, "length"),
    ],
)
def test_bad_options_are_refused_naming_option_and_value(opts, word):
    (value,) = opts.values()
    with pytest.raises(ValueError, match=rf"{word}.*{value}"):
        make_arena("complex-path", **opts)


def test_bad_option_exits_2_from_the_command_line(tmp_path, capsys):
    from neurowalk.cli import main

    args = ["run", "--arena", "complex-path", "--arena-opt", "spacing=0.1", "--steps", "5", "--out", str(tmp_path)]
    code = main(args)
    assert code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "spacing" in err[0] and "0.1" in err[0]
