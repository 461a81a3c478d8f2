import numpy as np
import pytest

from neurowalk.neural.analysis import hysteresis_loop, single_neuron_branches, single_neuron_thresholds


@pytest.mark.parametrize("b", [1.5, 2.4, 3.0, 4.63])
def test_measured_thresholds_match_analytic(b):
    on, off = single_neuron_thresholds(b)
    loop = hysteresis_loop(b, 0.0, single=True)
    assert loop.switch_on == pytest.approx(on, abs=0.01)
    assert loop.switch_off == pytest.approx(off, abs=0.01)


def test_no_hysteresis_for_small_b():
    assert single_neuron_thresholds(0.8) is None
    assert hysteresis_loop(0.5, 0.0, single=True).width == pytest.approx(0.0, abs=1e-6)


def test_width_grows_with_b_then_two_state():
    widths = [hysteresis_loop(b, 0.0, single=True).width for b in (1.5, 2.0, 2.4, 3.0, 4.0, 5.0)]
    assert bool(np.all(np.diff(widths) > 0))
    big = hysteresis_loop(8.0, 0.0, single=True)  # no input in [-1, 1] switches it
    assert big.switch_on is None


def test_stability_of_branches():
    _, o, stable = single_neuron_branches(2.4)
    assert stable[np.argmin(np.abs(o))] == False  # noqa: E712  middle branch unstable
    assert stable[0] and stable[-1]
    assert np.all(stable == (2.4 * (1 - o**2) < 1))


def test_two_neuron_hysteresis_grows_with_b_and_latches_at_learned_weights():
    w = [hysteresis_loop(b, -3.5).width for b in (1.5, 2.0, 2.4, 2.7)]
    assert bool(np.all(np.diff(w) > 0))
    static = hysteresis_loop(2.4, -3.5)
    assert -1 < static.switch_off < static.switch_on < 0  # switches on within the sensor range
    learned = hysteresis_loop(4.63, -7.04)
    assert learned.switch_on is not None and learned.switch_off is None and learned.width == np.inf
    with pytest.raises(ValueError, match="c"):
        hysteresis_loop(2.0, 1.0)
