import numpy as np
import pytest

from neurowalk import anatomy, gait
from neurowalk.controller import FixedController, NeuralController, make_controller
from neurowalk.observation import Observation

FREE = Observation(us_distance=np.array([np.inf, np.inf]))


def test_act_returns_fresh_19_targets_with_flat_backbone():
    c = NeuralController()
    a, b = c.act(FREE), c.act(FREE)
    assert a.shape == (anatomy.N_ACTUATORS,) and a[anatomy.BJ_INDEX] == 0.0
    assert a is not b


def test_free_space_walks_forward_obstacle_left_turns_right():
    c = NeuralController("static")
    out = np.array([c.act(FREE) for _ in range(900)])[300:]
    assert np.all(c.steering < 0)
    np.testing.assert_array_equal(gait.stroke_direction(out, gait.swing_mask(out)), np.ones(6))
    left = Observation(us_distance=np.array([0.15, np.inf]))
    out = np.array([c.act(left) for _ in range(900)])[300:]
    assert c.steering[0] > 0 > c.steering[1]  # O1 on, O2 off
    # O1 drives the right legs: they reverse, the robot turns right (away from the obstacle).
    np.testing.assert_array_equal(gait.stroke_direction(out, gait.swing_mask(out)), [-1, -1, -1, 1, 1, 1])


def test_plastic_weights_grow_near_obstacle_and_reset_restores():
    c = NeuralController("plastic")
    near = Observation(us_distance=np.array([0.1, np.inf]))
    first = np.array([c.act(near) for _ in range(50)])
    assert c.b[0] > 0.2 and c.b[1] == 0.0
    c.reset()
    np.testing.assert_array_equal(c.b, [0, 0])
    again = np.array([c.act(near) for _ in range(50)])
    np.testing.assert_array_equal(first, again)


def test_fixed_and_factory():
    f = make_controller("fixed", steer=(-1.0, 1.0))
    assert isinstance(f, FixedController) and f.act(FREE).shape == (19,)
    with pytest.raises(ValueError, match="steer"):
        FixedController((2.0, 0.0))
    with pytest.raises(ValueError, match="unknown controller"):
        make_controller("wheeled")
    with pytest.raises(ValueError, match="steering pair"):
        make_controller("fixed")
