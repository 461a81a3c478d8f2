"""`--body mjcf:FILE`: a user's robot, written here (not shipped), driven by the plastic network."""

from __future__ import annotations

import numpy as np
import pytest

from neurowalk.cli import main
from neurowalk.sim.episode import EpisodeConfig, run_episode

# A small differential-drive robot in the convention's terms, but with its own names: rangefinders "eye_left" and
# "eye_right" (±35° outward, 4 cm up, at the front), wheel motors "motor_r" and "motor_l" (0.46 rad/s limit on 3 cm
# wheels: AMOSII's 1.4 cm/s), a rear caster; a keyframe "home" standing on the wheels.
ROBOT = """<mujoco model="user-robot">
  <option timestep="0.01" integrator="implicitfast"/>
  <worldbody>
    <light pos="0 0 3" dir="0 0 -1" directional="true"/>
    <geom name="ground" type="plane" size="0 0 0.05" friction="1 0.005 0.0001"/>
    <body name="base" pos="0 0 0.03">
      <freejoint/>
      <geom type="box" size="0.2 0.15 0.02" pos="-0.05 0 0.01" mass="5" contype="2" conaffinity="1"/>
      <geom name="caster" type="sphere" size="0.01" pos="-0.22 0 -0.02" friction="0.01 0.005 0.0001" mass="0.1"/>
      <site name="s_left" pos="0.14 0.02 0.01" zaxis="0.8192 0.5736 0"/>
      <site name="s_right" pos="0.14 -0.02 0.01" zaxis="0.8192 -0.5736 0"/>
      <body name="wr" pos="0 -0.17 0">
        <joint name="jr" type="hinge" axis="0 1 0" armature="0.05"/>
        <geom type="cylinder" size="0.03 0.01" zaxis="0 1 0" friction="1.5 0.005 0.0001" mass="0.2"/>
      </body>
      <body name="wl" pos="0 0.17 0">
        <joint name="jl" type="hinge" axis="0 1 0" armature="0.05"/>
        <geom type="cylinder" size="0.03 0.01" zaxis="0 1 0" friction="1.5 0.005 0.0001" mass="0.2"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <velocity name="motor_r" joint="jr" kv="5" ctrlrange="-0.46 0.46" forcerange="-0.5 0.5"/>
    <velocity name="motor_l" joint="jl" kv="5" ctrlrange="-0.46 0.46" forcerange="-0.5 0.5"/>
  </actuator>
  <sensor>
    <rangefinder name="eye_left" site="s_left"/>
    <rangefinder name="eye_right" site="s_right"/>
  </sensor>
  <keyframe><key name="home" qpos="0 0 0.03 1 0 0 0 0 0"/></keyframe>
</mujoco>
"""
OPTS = {"left": "eye_left", "right": "eye_right", "right_motor": "motor_r", "left_motor": "motor_l"}


@pytest.fixture
def robot(tmp_path):
    path = tmp_path / "robot.xml"
    path.write_text(ROBOT)
    return f"mjcf:{path}"


def test_a_user_robot_runs_the_plastic_network_and_escapes_the_simple_deadlock(robot):
    ep = run_episode(EpisodeConfig(body=robot, body_opts=OPTS, arena="simple-deadlock", steps=4000))
    assert ep.summary["escaped"], ep.summary["final_pose"]
    assert ep.summary["body"] == robot and ep.summary["body_opts"] == OPTS
    assert np.nanmax(ep.trajectory.inputs) > 0.0  # it saw the walls on its way in
    static = run_episode(EpisodeConfig(body=robot, body_opts=OPTS, arena="simple-deadlock", steps=4000,
                                       controller="static"))  # fmt: skip
    assert not static.summary["escaped"]  # the static network stays trapped (the plastic one's learning matters)


def test_a_built_in_body_exported_runs_again_as_a_user_file(tmp_path):
    path = tmp_path / "wheeled.xml"
    assert main(["export-model", "--body", "wheeled", "--arena", "open", "--out", str(path)]) == 0
    native = run_episode(EpisodeConfig(body="wheeled", arena="simple-deadlock", steps=600, seed=2))
    user = run_episode(EpisodeConfig(body=f"mjcf:{path}", arena="simple-deadlock", steps=600, seed=2))
    # the file's numbers are written to 6-9 digits: the same run to a micrometre
    np.testing.assert_allclose(user.trajectory.qpos, native.trajectory.qpos, atol=1e-5)


@pytest.mark.parametrize(
    "edit,opts,word",
    [
        (
            [("<freejoint/>", ""), ('<keyframe><key name="home" qpos="0 0 0.03 1 0 0 0 0 0"/></keyframe>', "")],
            OPTS,
            "free joint",
        ),
        ([], {"left": "eye_left", "right": "nose"}, "'nose'"),
        ([], {**OPTS, "left_motor": "jl"}, "'jl'"),
        ([('ctrlrange="-0.46 0.46" ', "")] * 2, OPTS, "speed="),
        ([], {**OPTS, "key": "away"}, "'away'"),
        ([], {**OPTS, "speed": "fast"}, "speed"),
        ([], {**OPTS, "wheels": "2"}, "'wheels'"),
        ([("<worldbody>", "<worldbody><bogus/>")], OPTS, "cannot load"),
    ],
)
def test_a_file_off_the_convention_is_named(tmp_path, edit, opts, word):
    path = tmp_path / "bad.xml"
    text = ROBOT
    for old, new in edit:
        assert old in text
        text = text.replace(old, new, 1)
    path.write_text(text)
    with pytest.raises(ValueError, match=word):
        EpisodeConfig(body=f"mjcf:{path}", body_opts=opts)
    with pytest.raises(ValueError, match="no such file"):
        EpisodeConfig(body=f"mjcf:{tmp_path / 'none.xml'}")


def test_the_exported_amosii_runs_again_as_a_legged_user_file(tmp_path):
    path = tmp_path / "amosii.xml"
    assert main(["export-model", "--arena", "open", "--out", str(path)]) == 0
    cfg = {"arena": "simple-deadlock", "steps": 200, "seed": 1, "noise": 0.0}  # no noise: AMOSII's has more channels
    native = run_episode(EpisodeConfig(body="amosii", **cfg))
    user = run_episode(EpisodeConfig(body=f"mjcf:{path}", **cfg))  # drive=legs: it has AMOSII's 19 actuator names
    np.testing.assert_allclose(user.trajectory.qpos, native.trajectory.qpos, atol=1e-9)
    np.testing.assert_allclose(user.trajectory.joint_angles, native.trajectory.joint_angles, atol=1e-9)
    with pytest.raises(ValueError, match="drive"):
        EpisodeConfig(body=f"mjcf:{path}", body_opts={"drive": "tracks"})
    with pytest.raises(ValueError, match="wheel_R"):
        EpisodeConfig(body=f"mjcf:{path}", body_opts={"drive": "wheels"})
