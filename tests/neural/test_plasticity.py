import math

import pytest

from neurowalk.neural.plasticity import activity, correlation_scaling_delta, fixed_point, reflex_signal


def test_delta_vanishes_at_fixed_point():
    w = fixed_point(0.0065, 0.0003, -0.01)
    assert correlation_scaling_delta(w, 1.0, 1.0, 1.0, 0.0065, 0.0003, -0.01) == pytest.approx(0.0, abs=1e-15)
    assert correlation_scaling_delta(w * 0.9, 1.0, 1.0, 1.0, 0.0065, 0.0003, -0.01) > 0
    assert correlation_scaling_delta(w * 1.1, 1.0, 1.0, 1.0, 0.0065, 0.0003, -0.01) < 0


def test_no_reflex_no_learning_only_scaling():
    d = correlation_scaling_delta(2.0, 1.0, 1.0, 0.0, 0.0065, 0.0003, -0.01)
    assert d == pytest.approx(0.0003 * (-0.01 - 1.0) * 4.0)


def test_activity_and_reflex():
    assert activity(-1.0, 0.0) == 0.0 and activity(1.0, 0.0) == 1.0
    assert activity(-0.99, 0.009) == 0.0 and activity(-0.99, 0.0) == pytest.approx(0.005)
    assert reflex_signal(-0.49, -0.5) == 1.0 and reflex_signal(-0.5, -0.5) == 0.0


def test_fixed_point_formula_and_bad_params():
    assert fixed_point(0.015, 0.0003, -0.01) == pytest.approx(math.sqrt(0.015 / (0.0003 * 1.01)))
    with pytest.raises(ValueError):
        fixed_point(0.01, 0.0, -0.01)
