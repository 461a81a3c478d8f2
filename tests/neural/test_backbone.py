"""Backbone joint control: phases from the terrain readings, climbable vs wall, smoothing."""

import math

import numpy as np
import pytest

from neurowalk.neural.backbone import PHASES, BackboneControl, BackboneParams

FLAT = np.zeros(2)


def _settle(bc: BackboneControl, ahead: float, ground: np.ndarray, n: int = 60) -> float:
    for _ in range(n):
        bc.step(ahead, ground)
    return bc.command


def test_leans_up_before_a_step_in_proportion_to_its_height_and_masks_the_sonar():
    low, high = BackboneControl(), BackboneControl()
    a, b = _settle(low, 0.05, FLAT), _settle(high, 0.09, FLAT)
    assert 0 < a < b <= BackboneParams().max_lean
    assert PHASES[low.phase] == "up" and low.climbing


def test_a_wall_is_not_climbed_and_not_masked():
    bc = BackboneControl()
    assert _settle(bc, 0.30, FLAT) == pytest.approx(0.0, abs=1e-9)
    assert PHASES[bc.phase] == "level" and not bc.climbing


def test_flat_ground_and_small_bumps_are_ignored():
    bc = BackboneControl()
    assert _settle(bc, 0.01, FLAT) == pytest.approx(0.0, abs=1e-9) and not bc.climbing


def test_leans_down_while_the_front_is_over_the_step_then_levels_once_the_centre_is():
    bc = BackboneControl()
    _settle(bc, 0.08, FLAT)
    down = _settle(bc, 0.08, np.array([0.08, 0.0]))
    assert down == pytest.approx(BackboneParams().down, abs=1e-3) and PHASES[bc.phase] == "down"
    assert _settle(bc, 0.08, np.array([0.08, 0.08])) == pytest.approx(0.0, abs=1e-3)


def test_command_is_smoothed():
    bc = BackboneControl(BackboneParams(smoothing=0.2))
    first = bc.step(0.08, FLAT)
    assert first == pytest.approx(0.2 * min(BackboneParams().max_lean, 7.5 * 0.08))
    assert abs(first) < math.radians(10)


def test_bad_thresholds_are_refused():
    with pytest.raises(ValueError, match="min_height"):
        BackboneParams(min_height=0.2, climbable=0.1)


def test_a_front_stuck_at_the_edge_presses_down_then_leans_up_again():
    p = BackboneParams(stall_steps=100, press_steps=20)
    bc = BackboneControl(p)
    phases = []
    for _ in range(160):
        bc.step(0.08, FLAT)  # a step ahead, the front never gets over it
        phases.append(PHASES[bc.phase])
    assert phases[:100] == ["up"] * 100
    assert phases[101:121] == ["down"] * 20  # the press-down after the stall
    assert phases[121:] == ["up"] * 39
