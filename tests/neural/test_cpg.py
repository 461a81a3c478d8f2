import numpy as np
import pytest

from neurowalk.neural.cpg import GAITS, CpgParams, period, simulate_cpg


def test_wave_gait_period_about_88_steps():
    cpg, pcpg = simulate_cpg(3000)
    assert period(cpg[500:, 0]) == pytest.approx(87.5, rel=0.02)
    assert period(pcpg[500:, 1]) == pytest.approx(period(cpg[500:, 1]), rel=0.01)


def test_period_shrinks_as_mi_grows():
    mis = sorted(GAITS.values())
    periods = [period(simulate_cpg(3000, CpgParams(mi=mi))[0][500:, 0]) for mi in mis]
    assert bool(np.all(np.diff(periods) < 0))


def test_pcpg_sawtooth_rises_for_about_a_sixth_of_the_cycle():
    _, y = simulate_cpg(3000)
    rising = np.diff(y[500:, 0]) > 0
    assert rising.mean() == pytest.approx(1 / 6, abs=0.03)
    assert y.min() >= -1 and y.max() <= 1


def test_bad_gait_and_params():
    with pytest.raises(ValueError, match="gait"):
        CpgParams.for_gait("gallop")
    with pytest.raises(ValueError, match="mi"):
        CpgParams(mi=-0.1)
    assert CpgParams.for_gait("tripod").mi == 0.18
