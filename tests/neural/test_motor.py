"""The locomotion network: wave gait, steering semantics (paper Table 1), joint ranges."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from neurowalk import anatomy, gait
from neurowalk.neural.cpg import CpgParams
from neurowalk.neural.motor import LocomotionNetwork, LocomotionParams

WARMUP = 300  # control steps before the delay lines and PCPG are filled


def run(steer, steps=1200, params=None):
    net = LocomotionNetwork(params)
    out = np.array([net.step(*steer).copy() for _ in range(steps)])
    return out[WARMUP:]


@pytest.fixture(scope="module")
def forward():
    return run((-1.0, -1.0))


def test_wave_gait_swings_hind_to_front_one_leg_at_a_time(forward):
    swing = gait.swing_mask(forward)
    assert gait.leg_sequence(swing) == ["R3", "R2", "R1", "L3", "L2", "L1"]
    for side in ((0, 1, 2), (3, 4, 5)):  # never two legs of one side together
        assert swing[:, side].sum(axis=1).max() == 1
    d = gait.duty_summary(swing)
    assert d["time_two_or_more_in_swing"] < 0.15  # only the L1 -> R3 hand-over overlaps
    assert swing.sum(axis=1).max() <= 2
    np.testing.assert_allclose(swing.mean(axis=0), 1 / 6, atol=0.03)


def test_forward_both_sides_swing_forward_in_phase(forward):
    swing = gait.swing_mask(forward)
    np.testing.assert_array_equal(gait.stroke_direction(forward, swing), np.ones(6))


@pytest.mark.parametrize(
    "steer,expected",
    [
        ((1.0, 1.0), [-1, -1, -1, -1, -1, -1]),  # backward
        ((-1.0, 1.0), [1, 1, 1, -1, -1, -1]),  # O1 < 0 < O2: turn left (left legs reverse)
        ((1.0, -1.0), [-1, -1, -1, 1, 1, 1]),
    ],  # turn right (right legs reverse)
)
def test_steering_semantics(steer, expected):
    out = run(steer)
    np.testing.assert_array_equal(gait.stroke_direction(out, gait.swing_mask(out)), expected)


def test_zero_steering_stops_the_stroke():
    out = run((0.0, 0.0))
    assert np.ptp(out[:, list(anatomy.TC_INDICES)], axis=0).max() < np.deg2rad(1.0)


def test_tripod_gait_is_faster():
    slow = gait.swing_onsets(gait.swing_mask(run((-1, -1))))[0]
    fast = gait.swing_onsets(gait.swing_mask(run((-1, -1), params=LocomotionParams(cpg=CpgParams.for_gait("tripod")))))[
        0
    ]
    assert np.mean(np.diff(fast)) < 0.5 * np.mean(np.diff(slow))


@settings(max_examples=20, deadline=None)
@given(st.lists(st.tuples(st.floats(-1, 1), st.floats(-1, 1)), min_size=1, max_size=30), st.integers(1, 40))
def test_targets_stay_in_joint_ranges(steers, hold):
    net = LocomotionNetwork()
    # Joint ranges (servo commands are clipped to them): TC ±70° (middle ±60°), CTr ±75°, FTi [-130°, -20°].
    tc = [70, 60, 70, 70, 60, 70]
    lo = np.deg2rad([-x for x in tc] + [-75] * 6 + [-130] * 6)
    hi = np.deg2rad(tc + [75] * 6 + [-20] * 6)
    for s in steers:
        for _ in range(hold):
            t = net.step(*s)
            assert np.all(np.isfinite(t))
            assert np.all(t[:18] >= lo - 1e-9) and np.all(t[:18] <= hi + 1e-9)
            assert t[anatomy.BJ_INDEX] == 0.0


def test_reset_reproduces_exactly():
    net = LocomotionNetwork()
    a = np.array([net.step(-1, 0.3).copy() for _ in range(200)])
    net.reset()
    b = np.array([net.step(-1, 0.3).copy() for _ in range(200)])
    np.testing.assert_array_equal(a, b)
