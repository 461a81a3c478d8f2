"""Local leg control: forward model, searching reflex, elevation reflex (pure, no physics)."""

import numpy as np
import pytest

from neurowalk.neural.leg_control import LegControl, LegControlParams

STANCE = -1.0  # CTr pre-signal of a standing leg
SWING = 0.5  # a rising CTr pre-signal (leg lifting)


def _pre(ctr: float) -> np.ndarray:
    pre = np.zeros((3, 6))
    pre[1] = ctr
    return pre


def test_forward_model_expects_contact_in_stance_with_a_lag():
    lc = LegControl()
    lc.step(_pre(STANCE), np.ones(6))
    first = lc.expected.copy()
    for _ in range(20):
        lc.step(_pre(STANCE), np.ones(6))
    assert np.all(first > 0) and np.all(first < 0.5)  # lags behind the command
    assert np.allclose(lc.expected, 1.0, atol=1e-3)
    for _ in range(20):
        lc.step(_pre(SWING), np.zeros(6))
    assert np.allclose(lc.expected, 0.0, atol=1e-3)


def test_searching_reflex_lowers_a_leg_that_finds_no_ground_until_it_touches():
    lc = LegControl(LegControlParams(elevation=False))
    contact = np.ones(6)
    contact[0] = 0.0  # R1 stands over a hole
    depth = []
    for _ in range(40):
        pre = lc.step(_pre(STANCE), contact)
        depth.append(STANCE - pre[1, 0])
    assert depth[-1] > depth[5] > 0.0  # keeps reaching down
    assert depth[-1] <= lc.params.search_max + 1e-12
    assert np.allclose(lc.search[1:], 0.0, atol=1e-12)  # legs that stand are left alone
    contact[0] = 1.0  # found the ground: the depth is held
    held = lc.search[0]
    for _ in range(10):
        lc.step(_pre(STANCE), contact)
    assert lc.search[0] == pytest.approx(held)
    for _ in range(40):  # swing: the offset decays
        lc.step(_pre(SWING), np.zeros(6))
    assert lc.search[0] < 0.05 * held


def test_elevation_reflex_lifts_a_swinging_leg_that_hits_something():
    lc = LegControl(LegControlParams(searching=False))
    contact = np.zeros(6)
    contact[3] = 1.0  # L1 touches while it should swing
    pre = lc.step(_pre(SWING), contact)
    p = lc.params
    assert pre[1, 3] == p.elevation_ctr and pre[2, 3] == p.elevation_fti
    assert pre[0, 3] == pytest.approx(p.elevation_tc)
    assert np.all(pre[1, [0, 1, 2, 4, 5]] == SWING)  # the others untouched
    for _ in range(p.elevation_steps - 1):  # lasts elevation_steps, then ends
        pre = lc.step(_pre(SWING), np.zeros(6))
        assert pre[1, 3] == p.elevation_ctr
    pre = lc.step(_pre(SWING), np.zeros(6))
    assert pre[1, 3] == SWING


def test_switched_off_reflexes_change_nothing():
    lc = LegControl(LegControlParams(searching=False, elevation=False))
    pre = _pre(STANCE)
    out = lc.step(pre.copy(), np.zeros(6))
    assert np.array_equal(out, pre)


@pytest.mark.parametrize("field,value", [("contact_threshold", 1.5), ("model_weight", 1.0), ("elevation_steps", -1)])
def test_bad_parameters_are_named(field, value):
    with pytest.raises(ValueError, match=field):
        LegControlParams(**{field: value})


def _early_swing_touch(uneven: bool, elevation: bool) -> tuple[int, float]:
    """Stance, then a swing whose foot is still on the ground while the CTr command is barely up."""
    lc = LegControl(LegControlParams(elevation=elevation))
    contact = np.ones(6)
    contact[0] = 0.0  # R1 searches in stance (a hole), building up a depression
    for _ in range(30):
        lc.step(_pre(STANCE), contact, uneven)
    for _ in range(8):
        pre = lc.step(_pre(-0.9), np.ones(6), uneven)  # swing command, feet still touching
    return int(lc.elevating.max()), float(-0.9 - pre[1, 0])


def test_on_flat_ground_a_foot_leaving_late_does_not_trip_the_elevation_reflex_and_search_is_released():
    assert _early_swing_touch(uneven=False, elevation=True)[0] == 0
    assert _early_swing_touch(uneven=True, elevation=True)[0] > 0  # near a step any swing contact lifts the leg
    assert _early_swing_touch(uneven=False, elevation=False)[1] == pytest.approx(0.0)
    assert _early_swing_touch(uneven=True, elevation=False)[1] > 0.0  # the search depth fades over the swing


def test_uneven_terrain_is_remembered_for_terrain_hold_steps():
    lc = LegControl(LegControlParams(terrain_hold=10))
    assert not lc.uneven(0.0, np.zeros(2))
    assert lc.uneven(0.05, np.zeros(2))  # a step ahead
    held = [lc.uneven(0.0, np.zeros(2)) for _ in range(12)]
    assert held[:9] == [True] * 9 and not any(held[9:])  # true for 10 steps in all
    assert lc.uneven(0.0, np.array([0.0, 0.06]))  # the body is over a step
