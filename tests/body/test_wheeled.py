"""Tests of the wheeled body: its numbers against AMOSII's, the MJCF, Table 1's directions in physics, the sensors."""

from __future__ import annotations

import dataclasses
import itertools
import math

import mujoco
import numpy as np
import pytest

from neurowalk import anatomy
from neurowalk.arenas import make_arena
from neurowalk.arenas.spec import ArenaSpec
from neurowalk.body.amosii_mjcf import BodyParams, amosii_xml, stand_height
from neurowalk.body.surrogate import load_calibration
from neurowalk.body.wheeled import CHASSIS_BODY, WheeledParams, wheeled_xml
from neurowalk.body.wheeled_body import Wheeled, chassis_pose, read_us

P = WheeledParams()
OPEN = ArenaSpec(name="open", start=(0.2, -0.1, 0.7))  # a start yaw, so that "robot frame" means something
_T = mujoco.mjtGeom
BOX, SPHERE, CAPSULE, CYLINDER = (
    int(t) for t in (_T.mjGEOM_BOX, _T.mjGEOM_SPHERE, _T.mjGEOM_CAPSULE, _T.mjGEOM_CYLINDER)
)


def _extent(model: mujoco.MjModel, data: mujoco.MjData, root: int) -> tuple[np.ndarray, np.ndarray]:
    """Exact world bounding box (lo (3,), hi (3,)) in m of the geoms of the body tree under ``root``."""
    pts = []
    for g in range(model.ngeom):
        if model.body_rootid[model.geom_bodyid[g]] != root:
            continue
        c, rot, size = data.geom_xpos[g], data.geom_xmat[g].reshape(3, 3), model.geom_size[g]
        kind = int(model.geom_type[g])
        if kind == BOX:
            pts += [c + rot @ (np.array(s) * size) for s in itertools.product((-1, 1), repeat=3)]
        elif kind in (CAPSULE, SPHERE):
            ends = [c + rot @ [0, 0, e * size[1]] for e in (-1, 1)] if kind == CAPSULE else [c]
            pts += [e + size[0] * np.array(a) for e in ends for a in np.vstack([np.eye(3), -np.eye(3)])]
        elif kind == CYLINDER:  # bounding box of the two rim circles
            axis = rot[:, 2]
            rim = size[0] * np.sqrt(np.maximum(0.0, 1.0 - axis**2))
            pts += [c + e * size[1] * axis + s * rim for e in (-1, 1) for s in (-1, 1)]
        else:
            raise AssertionError(f"unexpected geom type {kind}")
    pts = np.array(pts)
    return pts.min(axis=0), pts.max(axis=0)


def _drive(body: Wheeled, steering: tuple[float, float], steps: int, seed: int = 0) -> np.ndarray:
    """Reset ``body`` with ``seed``, hold ``steering`` for ``steps`` control steps; (steps + 1, 3) chassis poses."""
    body.reset(np.random.default_rng(seed))
    poses = [body.observe().pose]
    for _ in range(steps):
        body.apply(np.array(steering, dtype=float))
        body.advance()
        poses.append(body.observe().pose)
    return np.array(poses)


def _robot_frame(poses: np.ndarray) -> tuple[float, float, float]:
    """(forward m, left m, yaw change rad) from the first pose to the last, in the first pose's frame."""
    (x0, y0, a0), (x1, y1, a1) = poses[0], poses[-1]
    dx, dy = x1 - x0, y1 - y0
    c, s = math.cos(a0), math.sin(a0)
    dyaw = math.atan2(math.sin(a1 - a0), math.cos(a1 - a0))
    return c * dx + s * dy, -s * dx + c * dy, dyaw


# --- numbers taken from AMOSII --------------------------------------------------------------------


def test_footprint_sensors_mass_and_speed_are_amosiis():
    bp = BodyParams()
    m = mujoco.MjModel.from_xml_string(amosii_xml(bp))
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("stand").id)
    mujoco.mj_forward(m, d)
    lo, hi = _extent(m, d, m.body("trunk").id)
    assert P.length == pytest.approx(hi[0] - lo[0], abs=1e-3)
    assert P.width == pytest.approx(hi[1] - lo[1], abs=1e-3)
    assert P.front == pytest.approx(hi[0] - d.xpos[m.body("trunk").id][0], abs=1e-3)  # axle = trunk centre
    assert P.us_height == pytest.approx(stand_height(bp) + bp.us_z, abs=1e-4)
    assert (P.us_yaw, P.us_range, P.us_y) == (bp.us_yaw, bp.us_range, bp.us_y)
    assert P.mass == pytest.approx(bp.total_mass)
    cal = load_calibration()
    i = int(np.flatnonzero(cal.grid == -1.0)[0])
    # AMOSII's forward speed of the calibration the wheeled robot was made for (0.01415 m/s); at issue 51's physics
    # AMOSII walks 1.4% faster (0.01435 m/s). Matching it again means the wheeled records made again (left to a
    # later change): held here to 2%.
    assert P.speed == pytest.approx(cal.velocity[i, i, 0], rel=0.02)


def test_model_spans_the_footprint_and_stands_on_its_wheels():
    body = Wheeled(make_arena("open"), noise=0.0)
    body.reset(np.random.default_rng(0))
    for _ in range(5):
        body.advance()
    m, d = body.model, body.data
    lo, hi = _extent(m, d, m.body(CHASSIS_BODY).id)
    assert hi[0] == pytest.approx(P.front, abs=1e-3) and lo[0] == pytest.approx(P.front - P.length, abs=1e-3)
    assert hi[1] == pytest.approx(P.width / 2, abs=1e-3) and lo[1] == pytest.approx(-P.width / 2, abs=1e-3)
    assert lo[2] == pytest.approx(0.0, abs=1e-3)  # resting on the floor
    touching = {m.geom(c.geom[i]).name for c in d.contact[: d.ncon] for i in (0, 1)}
    assert touching == {"floor", "wheel_L", "wheel_R", "caster_rear"}
    assert body.up_z() > 0.9999
    for name in anatomy.US_SENSORS:
        assert d.site_xpos[m.site(name).id][2] == pytest.approx(P.us_height, abs=1e-3)
    assert body.warnings() == {}


def test_interface_mirrors_amosii():
    arena = ArenaSpec(name="start", start=(0.5, -0.3, 1.0))
    body = Wheeled(arena)
    assert (body.name, body.action, body.arena, body.params, body.control_hz) == ("wheeled", "steering", arena, P, 10.0)
    assert body.n_substeps == 10  # 0.1 s control period / 0.01 s physics step
    assert body.model.nu == 2 and body.model.nq == 9
    body.reset(np.random.default_rng(1))
    obs = body.observe()
    np.testing.assert_allclose(obs.pose, arena.start, atol=1e-9)
    assert np.all(body.data.qvel == 0.0) and np.all(body.data.ctrl == 0.0)
    np.testing.assert_array_equal(chassis_pose(body.model, body.data), obs.pose)
    assert obs.us_distance.shape == (2,) and obs.time == 0.0
    np.testing.assert_array_equal(obs.foot_contact, np.zeros(6))
    np.testing.assert_array_equal(obs.joint_angles, np.zeros(19))
    np.testing.assert_array_equal(body.true_joint_angles(), np.zeros(19))
    body.apply(np.array([-1.0, -1.0]))
    body.advance()
    assert body.observe().time == pytest.approx(0.1)


def test_apply_clips_and_rejects_bad_steering():
    body = Wheeled(make_arena("open"))
    body.apply(np.array([-5.0, 3.0]))
    np.testing.assert_allclose(body.data.ctrl, [P.omega_max, -P.omega_max])  # (right from O1, left from O2)
    for bad in ([0.0], [0.0, 0.0, 0.0], [math.nan, 0.0], [0.0, math.inf]):
        with pytest.raises(ValueError, match="steering"):
            body.apply(np.array(bad))


def test_xml_is_self_contained_and_takes_the_arenas_world():
    arena = make_arena("box", distance=0.5)
    xml = wheeled_xml(P, world=arena.to_mjcf())
    assert "<include" not in xml and "file=" not in xml
    m = mujoco.MjModel.from_xml_string(xml)
    assert m.geom("obstacle_0").id >= 0
    assert m.key("rest").qpos[2] == pytest.approx(P.wheel_radius + P.start_clearance)


# --- Table 1 in physics ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("steering", "direction"),
    [((-1.0, -1.0), "forward"), ((1.0, 1.0), "backward"), ((-1.0, 1.0), "left"), ((1.0, -1.0), "right"),
     ((0.0, 0.0), "stop")],
)  # fmt: skip
def test_table1_directions(steering, direction):
    fwd, left, dyaw = _robot_frame(_drive(Wheeled(OPEN), steering, 150))
    if direction == "forward":
        assert fwd > 0.15 and abs(left) < 0.005 and abs(dyaw) < 0.01
    elif direction == "backward":
        assert fwd < -0.15 and abs(left) < 0.005 and abs(dyaw) < 0.01
    elif direction in ("left", "right"):
        sign = 1.0 if direction == "left" else -1.0
        assert sign * dyaw > 0.8 and math.hypot(fwd, left) < 0.01  # on the spot
    else:
        assert abs(fwd) < 1e-3 and abs(left) < 1e-3 and abs(dyaw) < 1e-3


def test_forward_speed_is_the_calibrations_amosii_speed():
    cal = load_calibration()
    i = int(np.flatnonzero(cal.grid == -1.0)[0])
    poses = _drive(Wheeled(OPEN), (-1.0, -1.0), 200)
    speed = _robot_frame(poses[50:])[0] / (150 * 0.1)  # m/s over the last 15 s
    assert speed == pytest.approx(cal.velocity[i, i, 0], rel=0.1)
    assert speed == pytest.approx(P.speed, rel=0.02)


def test_half_command_drives_at_half_speed_and_turn_rate_follows_the_track():
    speed = _robot_frame(_drive(Wheeled(OPEN), (-0.5, -0.5), 150)[50:])[0] / 10.0
    assert speed == pytest.approx(0.5 * P.speed, rel=0.05)
    rate = _robot_frame(_drive(Wheeled(OPEN), (-1.0, 1.0), 150)[50:])[2] / 10.0
    assert rate == pytest.approx(2.0 * P.speed / P.track, rel=0.1)


@pytest.mark.parametrize("scale", [0.1, 0.05, 4.0])  # 0.1: Khepera-sized
def test_scaled_robot_has_scaled_size_and_speed(scale):
    params = WheeledParams(scale=scale)
    still = Wheeled(make_arena("open"), params)  # facing +x: the world box is the footprint
    still.reset(np.random.default_rng(0))
    lo, hi = _extent(still.model, still.data, still.model.body(CHASSIS_BODY).id)
    np.testing.assert_allclose(hi - lo, scale * np.array([P.length, P.width, P.us_height + P.height / 2]), rtol=0.01)
    body = Wheeled(OPEN, params)
    poses = _drive(body, (-1.0, -1.0), 200)
    fwd, left, dyaw = _robot_frame(poses[50:])
    assert fwd / 15.0 == pytest.approx(scale * P.speed, rel=0.1)
    assert abs(left) < 5e-3 * scale and abs(dyaw) < 0.01
    assert body.up_z() > 0.999 and body.warnings() == {}


# --- rangefinders ----------------------------------------------------------------------------------


def test_rangefinders_read_a_box_at_a_known_distance():
    distance = 0.35  # m from the start (the axle) to the box's near face
    body = Wheeled(make_arena("box", distance=distance), noise=0.0)
    body.reset(np.random.default_rng(0))
    body.advance()
    expected = (distance - (P.front - P.us_inset)) / math.cos(P.us_yaw)
    np.testing.assert_allclose(body.observe().us_distance, [expected, expected], atol=0.01)
    np.testing.assert_allclose(read_us(body.model, body.data), [expected, expected], atol=1e-3)


def test_rangefinders_read_a_wall_the_robot_presses_against():
    body = Wheeled(make_arena("box", distance=0.3), noise=0.0)
    poses = _drive(body, (-1.0, -1.0), 100)  # reaches the box after about 50 steps, then pushes
    assert poses[-1, 0] == pytest.approx(0.3 - P.front, abs=2e-3)  # stopped by the box, not through it
    assert np.all(body.observe().us_distance < 0.01)
    assert body.up_z() > 0.999


def test_rangefinders_never_see_the_robot():
    """Open floor: no echo in range while driving and turning, and each ray's first hit is no robot geom.

    The rays start inside the chassis box; the rangefinder skips its own body's geoms, as ``mj_ray`` with
    ``bodyexclude`` = the chassis does here. A ray nearly level with the floor may meet it hundreds of metres away.
    """
    body = Wheeled(make_arena("open"), noise=0.0)
    body.reset(np.random.default_rng(0))
    m, d = body.model, body.data
    chassis = m.body(CHASSIS_BODY).id
    robot = m.body_rootid[m.geom_bodyid] == chassis
    geomid = np.zeros(1, dtype=np.int32)
    for steering in [(-1.0, -1.0)] * 30 + [(-1.0, 1.0)] * 60 + [(1.0, 1.0)] * 30 + [(1.0, -1.0)] * 60:
        body.apply(np.array(steering))
        body.advance()
        np.testing.assert_array_equal(body.observe().us_distance, [np.inf, np.inf])
        for name in anatomy.US_SENSORS:
            site = m.site(name).id
            dist = mujoco.mj_ray(m, d, d.site_xpos[site], d.site_xmat[site][2::3], None, 1, chassis, geomid)
            assert dist == -1.0 or (dist > 10.0 * P.us_range and not robot[geomid[0]])


def test_noise_acts_on_the_normalised_signal():
    body = Wheeled(make_arena("box", distance=0.35), noise=0.02)
    body.reset(np.random.default_rng(3))
    body.advance()
    clean = read_us(body.model, body.data)
    noisy = np.array([body.observe().us_distance for _ in range(50)])
    assert not np.array_equal(noisy[0], clean)
    assert np.all(np.abs(noisy - clean) < 0.02 * P.us_range)  # |noise| stays below the strength in US units


# --- determinism and validation --------------------------------------------------------------------


def test_same_seed_same_trajectory_bit_for_bit():
    arena = make_arena("random", rng=np.random.default_rng(0))

    def run(seed: int) -> tuple[np.ndarray, np.ndarray]:
        body = Wheeled(arena)
        body.reset(np.random.default_rng(seed))
        us = []
        for k in range(200):
            obs = body.observe()
            us.append(obs.us_distance)
            body.apply(np.array([-1.0, -1.0]) if (k // 40) % 2 == 0 else np.array([-1.0, 0.5]))
            body.advance()
        return body.data.qpos.copy(), np.array(us)

    (q1, u1), (q2, u2), (_, u3) = run(7), run(7), run(8)
    assert q1.tobytes() == q2.tobytes() and u1.tobytes() == u2.tobytes()
    assert not np.array_equal(u1, u3)  # another seed, other noise


@pytest.mark.parametrize(
    ("field", "value"),
    [("scale", 0.0), ("scale", -1.0), ("wheel_radius", math.nan), ("speed", math.inf), ("mass", 0.1),
     ("us_yaw", 2.0), ("com_x", 0.05), ("motor_kv", 100.0), ("caster_gap", 0.05), ("width", 0.08),
     ("caster_friction", -0.1), ("timestep", True)],
)  # fmt: skip
def test_bad_params_raise_naming_the_field_and_value(field, value):
    with pytest.raises(ValueError, match=rf"WheeledParams\.{field} .*{value!r}".replace("(", r"\(")):
        dataclasses.replace(P, **{field: value})


def test_a_scaled_robot_reads_distances_in_its_own_units():
    # the double-size robot with the box at double the distance sees what the full-size robot sees
    full = Wheeled(make_arena("box", distance=0.3), noise=0.0)
    double = Wheeled(make_arena("box", distance=0.6), WheeledParams(scale=2.0), noise=0.0)
    for body in (full, double):
        body.reset(np.random.default_rng(0))
        body.advance()
    assert np.all(np.isfinite(full.observe().us_distance))
    np.testing.assert_allclose(double.observe().us_distance, full.observe().us_distance, atol=2e-3)
