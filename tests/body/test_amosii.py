"""Tests of the AMOSII MJCF writer and its sensor readers (model structure, statics, signs, sensors)."""

from __future__ import annotations

import dataclasses
import itertools
import math

import mujoco
import numpy as np
import pytest

from neurowalk import anatomy
from neurowalk.body.amosii_mjcf import (
    BodyParams,
    amosii_xml,
    export_model,
    foot_contacts,
    joint_qpos_indices,
    obstacle_contact,
    obstacle_height,
    read_us,
    stand_height,
    standing_pose,
    trunk_pose,
    up_z,
)

P = BodyParams()


@pytest.fixture(scope="module")
def model() -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_string(amosii_xml())


def _standing(world: str = "", seconds: float = 0.5) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """Build a model with ``world``, reset it to the stand keyframe and step it for ``seconds``."""
    m = mujoco.MjModel.from_xml_string(amosii_xml(world=world))
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("stand").id)
    mujoco.mj_step(m, d, nstep=round(seconds / m.opt.timestep))
    return m, d


def _feet(m: mujoco.MjModel, q: np.ndarray) -> np.ndarray:
    """World positions (6, 3) of the foot centres, LEGS order, for joint angles q (19,)."""
    d = mujoco.MjData(m)
    d.qpos[joint_qpos_indices(m)] = q
    mujoco.mj_kinematics(m, d)
    return np.array([d.site_xpos[m.site(f"foot_{leg}").id] for leg in anatomy.LEGS])


# --- structure -------------------------------------------------------------------------------


def test_actuators_are_the_19_in_anatomy_order_each_driving_its_joint(model):
    assert model.nu == anatomy.N_ACTUATORS == 19
    names = tuple(model.actuator(i).name for i in range(model.nu))
    assert names == anatomy.ACTUATORS
    driven = tuple(model.joint(model.actuator_trnid[i, 0]).name for i in range(model.nu))
    assert driven == anatomy.ACTUATORS


def test_options_and_total_mass(model):
    assert model.opt.timestep == P.timestep
    assert model.opt.integrator == mujoco.mjtIntegrator.mjINT_DISCRETE
    assert model.opt.solver == mujoco.mjtSolver.mjSOL_NEWTON and model.opt.jacobian == mujoco.mjtJacobian.mjJAC_SPARSE
    assert model.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC
    assert model.body_mass.sum() == pytest.approx(P.total_mass, rel=1e-9)
    # the mass the authors' simulator applies (original_code_facts.md §13): 6.70 kg, its shoulders weightless
    assert P.total_mass == pytest.approx(6.70, rel=0.01)
    assert model.opt.iterations == P.solver_iterations and model.opt.tolerance == P.solver_tolerance


def test_exactly_two_rangefinders_named_us_l_us_r(model):
    rangefinders = [
        model.sensor(i).name
        for i in range(model.nsensor)
        if model.sensor_type[i] == mujoco.mjtSensor.mjSENS_RANGEFINDER
    ]
    assert tuple(rangefinders) == anatomy.US_SENSORS


def test_export_model_writes_a_loadable_file_and_nothing_on_error(tmp_path):
    path = export_model(tmp_path / "amosii.xml")
    m = mujoco.MjModel.from_xml_path(str(path))
    assert m.nu == 19
    assert [p.name for p in tmp_path.iterdir()] == ["amosii.xml"]
    with pytest.raises(ValueError):
        export_model(tmp_path / "bad.xml", world="<geom type='nonsense'/>")
    assert [p.name for p in tmp_path.iterdir()] == ["amosii.xml"]


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("front_mass", -0.8),
        ("link_mass", 0.0),
        ("ctr_range", (1.0, -1.0)),
        ("fti_range", (-0.3, -2.0)),
        ("us_range", -0.4),
        ("timestep", 0.0),
        ("leg_kp", -30.0),
        ("joint_damping", -1.0),
        ("stand_fti", -0.1),
        ("leg_x", (0.0, 0.025, -0.165)),
        ("stand_tc", (0.4, 0.0)),
        ("bj_range", (0.1, 0.5)),
        ("shoulder_mass", -0.1),
        ("solver_iterations", 2.5),
        ("solver_tolerance", 0.0),
        ("integrator", "rk4"),
        ("solver", "newton"),
        ("contact_timeconst", 0.0),
        ("armature", -0.01),
    ],
)
def test_bad_params_raise_naming_the_field(field, value):
    with pytest.raises(ValueError, match=field):
        BodyParams(**{field: value})


# --- statics ---------------------------------------------------------------------------------


def test_stands_upright_for_5_s_without_warnings():
    m, d = _standing(seconds=0.0)
    heights = []
    for _ in range(10):
        mujoco.mj_step(m, d, nstep=round(0.5 / m.opt.timestep))
        assert up_z(m, d) >= 0.95
        heights.append(d.qpos[2])
    assert all(w.number == 0 for w in d.warning)
    assert min(heights) >= 0.03 and max(heights) <= 0.05
    assert min(heights) - P.trunk_height / 2 > 0.0  # the belly stays off the floor
    assert (foot_contacts(m, d) > 0.5).all()
    assert np.allclose(trunk_pose(m, d)[:2], 0.0, atol=0.005)
    assert np.abs(d.qpos[joint_qpos_indices(m)] - standing_pose()).max() < 0.1


def test_starts_in_the_standing_pose_and_contacts_vanish_in_the_air(model):
    d = mujoco.MjData(model)
    np.testing.assert_allclose(d.qpos[joint_qpos_indices(model)], standing_pose())
    assert d.qpos[2] == pytest.approx(stand_height(P) + P.start_clearance)
    d.qpos[2] = 1.0
    mujoco.mj_forward(model, d)
    assert (foot_contacts(model, d) == 0.0).all()


def test_trunk_pose_reports_yaw(model):
    d = mujoco.MjData(model)
    d.qpos[:2] = (0.3, -0.2)
    d.qpos[3:7] = (math.cos(0.35), 0.0, 0.0, math.sin(0.35))  # yaw 0.7 rad
    mujoco.mj_kinematics(model, d)
    np.testing.assert_allclose(trunk_pose(model, d), (0.3, -0.2, 0.7), atol=1e-12)


# --- sign conventions ------------------------------------------------------------------------


def test_zero_pose_is_straight_horizontal_and_lateral(model):
    feet = _feet(model, np.zeros(19))
    reach = P.leg_y + P.shoulder_length + P.coxa_length + P.femur_length
    reach += P.tibia_length - P.foot_radius
    side = np.array([-1 if leg[0] == "R" else 1 for leg in anatomy.LEGS])
    np.testing.assert_allclose(feet[:, 1], side * reach, atol=1e-9)
    np.testing.assert_allclose(feet[:, 2], model.qpos0[2] + P.leg_z, atol=1e-9)
    np.testing.assert_allclose(feet[:, 0], [P.leg_x[int(leg[1]) - 1] for leg in anatomy.LEGS])


def _moved(m: mujoco.MjModel, joint: str, leg: str, lo: float, hi: float) -> np.ndarray:
    """Foot displacement (3,) of ``leg`` when ``joint`` goes from lo to hi about the stance."""
    q = standing_pose()
    k, i = anatomy.LEGS.index(leg), anatomy.joint_index(joint, leg)
    q[i] = lo
    a = _feet(m, q)[k]
    q[i] = hi
    return _feet(m, q)[k] - a


@pytest.mark.parametrize("leg", anatomy.LEGS)
def test_tc_positive_swings_the_foot_forward(model, leg):
    assert _moved(model, "TC", leg, -0.3, 0.3)[0] > 0.02


@pytest.mark.parametrize("leg", anatomy.LEGS)
def test_ctr_positive_lifts_the_foot(model, leg):
    assert _moved(model, "CTr", leg, 0.6, 1.0)[2] > 0.02


@pytest.mark.parametrize("leg", anatomy.LEGS)
def test_fti_positive_extends_the_leg_outward(model, leg):
    # Walking range: the tibia points steeply down-outward; extension swings the foot outward,
    # and up or down as the tibia's angle below the horizontal dictates.
    lo, hi = -2.27, -1.6
    move = _moved(model, "FTi", leg, lo, hi)
    outward = 1 if leg[0] == "L" else -1
    assert outward * move[1] > 0.02
    tibia_angle = P.stand_ctr + (lo + hi) / 2  # below horizontal: < 0
    assert np.sign(move[2]) == np.sign(math.cos(tibia_angle))


def test_bj_positive_tilts_the_front_up(model):
    q = standing_pose()
    q[anatomy.BJ_INDEX] = 0.3
    lifted = _feet(model, q) - _feet(model, standing_pose())
    front = [anatomy.LEGS.index(leg) for leg in anatomy.LEGS if leg[1] == "1"]
    assert (lifted[front, 2] > 0.02).all()
    assert np.allclose(np.delete(lifted, front, axis=0), 0.0)


def test_left_and_right_legs_are_mirror_images(model):
    rng = np.random.default_rng(0)
    for _ in range(5):
        q = standing_pose()
        for joint in anatomy.LEG_JOINTS:
            for k in "123":
                q[anatomy.joint_index(joint, "L" + k)] = q[anatomy.joint_index(joint, "R" + k)] = rng.uniform(
                    -0.5, 0.5
                ) + (-1.8 if joint == "FTi" else 0.0)
        feet = _feet(model, q)
        right, left = feet[:3], feet[3:]
        np.testing.assert_allclose(left * (1, -1, 1), right, atol=1e-12)


# --- sensors ---------------------------------------------------------------------------------


def test_us_reads_no_echo_on_open_floor_in_any_leg_pose(model):
    assert np.isinf(read_us(*_standing())).all()  # standing, settled
    d = mujoco.MjData(model)
    qi = joint_qpos_indices(model)
    grid = [np.linspace(lo, hi, 7) for lo, hi in (P.tc_range_outer, P.ctr_range, P.fti_range)]
    for tc, ctr, fti in itertools.product(*grid):
        for bj in (0.0, 0.4):
            q = np.full(19, fti)
            q[list(anatomy.TC_INDICES)] = np.clip(tc, *P.tc_range_middle)
            q[[anatomy.joint_index("TC", g) for g in anatomy.LEGS if g[1] != "2"]] = tc
            q[list(anatomy.CTR_INDICES)] = ctr
            q[anatomy.BJ_INDEX] = bj
            d.qpos[qi] = q
            mujoco.mj_forward(model, d)
            assert np.isinf(read_us(model, d)).all(), (tc, ctr, fti, bj)


@pytest.mark.parametrize("side", [0, 1])
def test_us_sees_a_box_on_its_own_side_at_the_right_distance(side):
    m, d = _standing()
    site = m.site(anatomy.US_SENSORS[side]).id
    origin, ray = d.site_xpos[site], d.site_xmat[site].reshape(3, 3)[:, 2]
    centre = origin + 0.21 * ray  # box face 0.20 m along the ray, facing the sensor
    yaw = math.atan2(ray[1], ray[0])
    box = f'<geom type="box" size="0.01 0.06 0.1" pos="{centre[0]} {centre[1]} 0.1" euler="0 0 {yaw}"/>'
    us = read_us(*_standing(box))
    assert us[side] == pytest.approx(0.20, abs=0.005)
    assert np.isinf(us[1 - side])


def _wall(height: float, ahead: float = 0.25) -> str:
    """Return a 1 m deep, 2 m wide block whose face is ``ahead`` m in front of the robot's front face."""
    x = P.trunk_length / 2 + ahead + 0.5
    return f'<geom type="box" size="0.5 1 {height / 2}" pos="{x} 0 {height / 2}"/>'


def test_obstacle_height_tells_a_step_from_a_wall():
    flat = obstacle_height(*_standing())
    step = obstacle_height(*_standing(_wall(0.06)))
    wall = obstacle_height(*_standing(_wall(0.30)))
    far = obstacle_height(*_standing(_wall(0.30, ahead=0.6)))
    assert flat < 0.005
    assert step == pytest.approx(0.06, abs=0.01)
    assert wall > 0.2
    assert far < 0.005  # beyond the lookahead


def test_obstacle_height_is_measured_from_the_ground_under_the_feet():
    # The robot stands on a 0.10 m terrace; the 0.06 m step ahead rises from the terrace.
    x_step = P.trunk_length / 2 + 0.25
    terrace = f'<geom type="box" size="{(x_step + 1) / 2} 1 0.05" pos="{(x_step - 1) / 2} 0 0.05"/>'
    step = f'<geom type="box" size="0.5 1 0.08" pos="{x_step + 0.5} 0 0.08"/>'
    m = mujoco.MjModel.from_xml_string(amosii_xml(world=terrace + step))
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("stand").id)
    d.qpos[2] += 0.10
    mujoco.mj_step(m, d, nstep=100)
    assert up_z(m, d) > 0.95
    assert obstacle_height(m, d) == pytest.approx(0.06, abs=0.01)


def test_obstacle_contact_is_the_robot_touching_a_box_not_the_floor():
    m, d = _standing()
    assert d.ncon > 0 and not obstacle_contact(m, d)  # the feet on the floor do not count
    far = obstacle_contact(*_standing(_wall(0.10, ahead=0.30)))
    touching = obstacle_contact(*_standing(_wall(0.10, ahead=0.0)))  # box face at the front face
    beside = f'<geom type="box" size="0.5 0.1 0.05" pos="0 {0.17 + 0.1} 0.05"/>'  # against the left feet
    assert not far and touching and obstacle_contact(*_standing(beside))


def test_obstacle_contacts_replays_recorded_positions():
    from neurowalk.arenas import make_arena
    from neurowalk.body.physics import obstacle_contacts

    arena = make_arena("box", distance=0.3)
    m = mujoco.MjModel.from_xml_string(amosii_xml(world=arena.to_mjcf()))
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("stand").id)
    box = arena.boxes[0]
    qpos = np.tile(d.qpos, (3, 1))
    qpos[1, 0] = box.x - box.sx / 2 - P.trunk_length / 2  # front face on the box's face
    qpos[2, 0] = box.x  # trunk inside the box
    assert np.array_equal(obstacle_contacts(arena, qpos), [0.0, 1.0, 1.0])
    partial = obstacle_contacts(arena, qpos, rows=[1])
    assert np.isnan(partial[[0, 2]]).all() and partial[1] == 1.0
    with pytest.raises(ValueError, match="qpos"):
        obstacle_contacts(arena, qpos[:, :5])


def test_params_change_the_model():
    soft = dataclasses.replace(P, joint_stiffness=2.0, joint_damping=0.1, foot_friction=1.5)
    m = mujoco.MjModel.from_xml_string(amosii_xml(soft))
    hinge = m.joint(anatomy.ACTUATORS[0]).id
    assert m.jnt_stiffness[hinge] == 2.0
    assert m.dof_damping[m.jnt_dofadr[hinge]] == 0.1
    assert m.geom_friction[m.geom("foot_L2").id, 0] == 1.5


def test_integrator_armature_and_contact_time_constant_reach_every_part_of_the_model():
    """The physics options set the model's integrator, every hinge's armature (not the free joint's) and the time
    constant of every geom's contacts, the arena's boxes included (a contact mixes the two geoms' solref)."""
    from neurowalk.arenas import make_arena

    p = BodyParams(integrator="RK4", solver="CG", armature=0.03, contact_timeconst=0.05)
    m = mujoco.MjModel.from_xml_string(amosii_xml(p, world=make_arena("box").to_mjcf()))
    assert m.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4 and m.opt.solver == mujoco.mjtSolver.mjSOL_CG
    assert np.all(m.dof_armature[:6] == 0.0) and np.all(m.dof_armature[6:] == 0.03)
    boxes = [i for i in range(m.ngeom) if m.geom_bodyid[i] == 0 and m.geom_type[i] == mujoco.mjtGeom.mjGEOM_BOX]
    assert boxes and np.all(m.geom_solref[:, 0] == 0.05) and np.all(m.geom_solref[:, 1] == 1.0)


def test_a_control_step_with_sensors_in_its_last_physics_step_only_is_plain_stepping_bit_for_bit():
    """AmosII.advance leaves the sensors off in all but the last physics step of a control step: the state, the
    sensor data (an echo, foot contacts) and the warnings after it are those of plain ``mj_step`` steps, exactly."""
    from neurowalk.arenas import make_arena
    from neurowalk.body.amosii import AmosII
    from neurowalk.controller import FixedController

    arena = make_arena("box")
    a, b = (AmosII(arena, BodyParams(), control_hz=10.0, noise=0.0) for _ in range(2))
    for body in (a, b):
        body.reset(np.random.default_rng(0))
    ctrl = FixedController((-1.0, -1.0))
    echo = False
    for _ in range(900):  # 90 s: it walks into the box's range
        targets = ctrl.act(a.observe())
        for body in (a, b):
            body.apply(targets)
        a.advance()
        mujoco.mj_step(b.model, b.data, nstep=b.n_substeps)
        for name in ("qpos", "qvel", "act", "sensordata", "qacc_warmstart", "ctrl"):
            assert np.array_equal(getattr(a.data, name), getattr(b.data, name)), name
        echo |= bool(np.any(np.isfinite(a.observe().us_distance)))
    assert a.data.time == b.data.time and a.warnings() == b.warnings()
    assert a.model.opt.disableflags == b.model.opt.disableflags == 0
    assert a.n_substeps == 10 and echo  # it saw the box: the rays' reading is compared, not only empty ones


def test_each_servo_follows_its_target_through_its_lag_from_the_standing_pose():
    """servo_timeconst: every actuator filters its target (first order, time constant servo_timeconst), starting at
    the standing pose; after a step of the target its filtered target has moved 1 - exp(-t / tau) of the way; 0: the
    servos take their targets at once (no activation state)."""
    from neurowalk.arenas import make_arena
    from neurowalk.body.amosii import AmosII

    p = BodyParams(servo_timeconst=0.05)
    body = AmosII(make_arena("open"), p, control_hz=10.0, noise=0.0)
    body.reset(np.random.default_rng(0))
    m, d = body.model, body.data
    assert m.na == m.nu == 19 and np.all(m.actuator_dyntype == mujoco.mjtDyn.mjDYN_FILTEREXACT)
    assert np.all(m.actuator_dynprm[:, 0] == 0.05)
    np.testing.assert_allclose(d.act, standing_pose(p), atol=1e-8)  # the keyframe's 9 digits
    assert np.array_equal(d.act, d.ctrl)
    target = standing_pose(p) + 0.1
    body.apply(target)
    body.advance()  # 0.1 s: two time constants
    np.testing.assert_allclose(d.act - (target - 0.1), 0.1 * (1 - np.exp(-0.1 / 0.05)), atol=1e-8)
    assert mujoco.MjModel.from_xml_string(amosii_xml(BodyParams(servo_timeconst=0.0))).na == 0
