"""The planar surrogate: geometry kernels, no penetration, determinism, calibrated motion, agreement with physics."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from neurowalk.arenas import make_arena
from neurowalk.arenas.spec import ArenaSpec, Box
from neurowalk.body import surrogate_kernel as kern
from neurowalk.body.surrogate import Surrogate, box_rows, load_calibration
from neurowalk.experiments.calibration import WARMUP, WINDOW, body_velocity, drive
from neurowalk.sim.episode import EpisodeConfig, run_episode


def _rows(*boxes: Box) -> np.ndarray:
    return box_rows(ArenaSpec(name="t", boxes=boxes, start=(0.0, 0.0, 0.0)))


def test_ray_hits_the_near_face_of_a_box_and_misses_beyond_range() -> None:
    rows = _rows(Box(x=1.0, y=0.0, yaw=0.0, sx=0.2, sy=1.0, h=0.1))
    assert kern.ray_boxes(0.0, 0.0, 1.0, 0.0, rows, 2.0) == pytest.approx(0.9)
    assert math.isinf(kern.ray_boxes(0.0, 0.0, 1.0, 0.0, rows, 0.5))  # the face is 0.9 m away
    assert math.isinf(kern.ray_boxes(0.0, 0.0, -1.0, 0.0, rows, 2.0))  # pointing away
    a = math.radians(20)  # hits the face at y = 0.33 m, inside its half height of 0.5 m
    assert kern.ray_boxes(0.0, 0.0, math.cos(a), math.sin(a), rows, 2.0) == pytest.approx(0.9 / math.cos(a))
    assert kern.ray_boxes(1.0, 0.0, 1.0, 0.0, rows, 2.0) == 0.0  # inside


def test_ray_sees_a_rotated_box_at_its_corner() -> None:
    rows = _rows(Box(x=1.0, y=0.0, yaw=math.pi / 4, sx=0.2, sy=0.2, h=0.1))
    assert kern.ray_boxes(0.0, 0.0, 1.0, 0.0, rows, 2.0) == pytest.approx(1.0 - 0.1 * math.sqrt(2))


def _penetration(pose: np.ndarray, circles: np.ndarray, rows: np.ndarray) -> float:
    """Deepest overlap (m) of any footprint circle with any box over poses (T, 3)."""
    c, s = np.cos(pose[:, 2])[:, None], np.sin(pose[:, 2])[:, None]
    wx = pose[:, :1] + c * circles[:, 0] - s * circles[:, 1]
    wy = pose[:, 1:2] + s * circles[:, 0] + c * circles[:, 1]
    worst = 0.0
    for cx, cy, bc, bs, hx, hy in rows:
        px, py = bc * (wx - cx) + bs * (wy - cy), -bs * (wx - cx) + bc * (wy - cy)
        d = np.hypot(px - np.clip(px, -hx, hx), py - np.clip(py, -hy, hy))
        inside = (np.abs(px) <= hx) & (np.abs(py) <= hy)
        worst = max(worst, float(np.max(np.where(inside, np.inf, circles[:, 2] - d))))
    return worst


@pytest.mark.parametrize(("arena", "controller"), [("narrow-passage", "static"), ("difficult", "plastic")])
def test_the_footprint_never_enters_a_box(arena: str, controller: str) -> None:
    ep = run_episode(EpisodeConfig(arena=arena, controller=controller, body="surrogate", steps=8000, seed=1))
    assert _penetration(ep.trajectory.pose, load_calibration().circles, box_rows(ep.arena)) < 1e-3


def test_walking_into_a_wall_stops_at_the_wall() -> None:
    cfg = EpisodeConfig(arena="box", controller="fixed", steer=(-1.0, -1.0), body="surrogate", steps=3000, seed=0)
    ep = run_episode(cfg)
    assert ep.summary["surrogate_contacts"] > 100  # pushed against the box for many steps
    assert _penetration(ep.trajectory.pose, load_calibration().circles, box_rows(ep.arena)) < 1e-3
    assert np.ptp(ep.trajectory.pose[-500:, 0]) < 0.02  # m: no longer advancing


def test_push_out_moves_an_overlapping_body_clear_of_a_wall() -> None:
    rows = _rows(Box(x=0.0, y=0.5, yaw=0.0, sx=4.0, sy=0.2, h=0.1))
    circles = np.array([[0.0, 0.0, 0.1], [0.2, 0.0, 0.1]])
    state = np.zeros(kern.RUN_STATE)
    state[kern.Y] = 0.35  # circles reach y = 0.45, the wall starts at 0.4
    assert kern.push_out(state, 0.0, circles, rows, 0.3) > 0
    assert state[kern.Y] == pytest.approx(0.3)
    assert state[kern.X] == pytest.approx(0.0)


def test_same_seed_same_run_bit_for_bit_and_another_seed_differs() -> None:
    cfg = EpisodeConfig(arena="random", controller="plastic", body="surrogate", steps=4000, seed=3)
    a, b = run_episode(cfg).trajectory, run_episode(cfg).trajectory
    for name in ("pose", "inputs", "outputs", "b", "q", "us_distance"):
        assert np.array_equal(getattr(a, name), getattr(b, name), equal_nan=True), name
    c = run_episode(EpisodeConfig(arena="random", controller="plastic", body="surrogate", steps=4000, seed=4))
    assert not np.array_equal(a.pose, c.trajectory.pose)


def _velocity(steer: tuple[float, float]) -> np.ndarray:
    run = Surrogate(make_arena("open"), noise=0.0).run(
        WARMUP + WINDOW, np.random.default_rng(0), None, None, steer=steer
    )
    return body_velocity(run.pose[WARMUP:], 10.0)


def test_steering_directions_follow_the_calibration() -> None:
    fwd, back = _velocity((-1.0, -1.0)), _velocity((1.0, 1.0))
    left, right = _velocity((-1.0, 1.0)), _velocity((1.0, -1.0))
    assert fwd[0] > 0.005 and back[0] < -0.005  # m/s: walks forward with no obstacle, backward when both see one
    assert left[2] > 0.02 and right[2] < -0.02  # rad/s: O2 = +1 turns left, O1 = +1 turns right
    assert abs(left[0]) < 0.3 * fwd[0] and abs(right[0]) < 0.3 * fwd[0]  # turning almost on the spot
    cal = load_calibration()
    i = int(np.argmin(np.abs(cal.grid + 1.0)))
    assert fwd[0] == pytest.approx(cal.velocity[i, i, 0], rel=0.02)


def test_the_start_up_delay_holds_the_body_still() -> None:
    cal = load_calibration()
    run = Surrogate(make_arena("open"), noise=0.0).run(cal.startup_steps + 200, np.random.default_rng(0), None, None,
                                                        steer=(-1.0, -1.0))  # fmt: skip
    assert np.allclose(run.pose[: cal.startup_steps, :2], 0.0)
    assert run.pose[-1, 0] > 0.01


def test_surrogate_agrees_with_physics_between_grid_points() -> None:
    """Held-out steering pairs: speed and turning rate within 15% of full scale (the issue's bar)."""
    cal = load_calibration()
    full_v = float(np.max(np.abs(cal.velocity[..., 0])))
    full_w = float(np.max(np.abs(cal.velocity[..., 2])))
    for pair in ((-0.75, -0.4), (-0.4, 0.75), (0.15, -0.75)):
        phys = body_velocity(drive(np.tile(pair, (WARMUP + WINDOW, 1)))[WARMUP:], 10.0)
        sur = _velocity(pair)
        assert abs(sur[0] - phys[0]) < 0.15 * full_v, pair
        assert abs(sur[2] - phys[2]) < 0.15 * full_w, pair


def test_the_shipped_calibration_records_how_it_was_measured() -> None:
    cal = load_calibration()
    assert cal.meta["command"] == "neurowalk calibrate" and "how" in cal.meta
    v = cal.meta["validation"]
    assert v["speed_error_max"] < 0.15 and v["yaw_rate_error_max"] < 0.15
    assert cal.tau_s > 0 and cal.control_hz == 10.0


def test_a_corrupt_calibration_file_is_reported_with_its_path(tmp_path) -> None:  # type: ignore[no-untyped-def]
    bad = tmp_path / "cal.json"
    bad.write_text(json.dumps({"grid": [0, 1]}))
    with pytest.raises(ValueError, match=r"cal\.json"):
        load_calibration(bad)


@pytest.mark.slow
def test_same_escape_outcome_as_physics_in_the_dead_ends() -> None:
    for arena, controller in (
        ("narrow-passage", "plastic"),
        ("narrow-passage", "static"),
        ("simple-deadlock", "static"),
    ):
        outcome = {
            body: run_episode(EpisodeConfig(arena=arena, controller=controller, body=body, steps=5000, seed=0)).summary[
                "escaped"
            ]
            for body in ("amosii", "surrogate")
        }
        assert outcome["amosii"] == outcome["surrogate"], (arena, controller, outcome)
