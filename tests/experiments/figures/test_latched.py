"""The latched-spin figure: the Table 2 failure mechanism of the plastic network, found and explained."""

from __future__ import annotations

import numpy as np

from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.figures import latched
from neurowalk.experiments.study import compute
from neurowalk.experiments.suites.random_envs import STEPS, spec
from neurowalk.sim.episode import EpisodeConfig, run_episode


def test_latched_spins_hold_by_their_weights_alone_or_by_an_echo_on_the_turning_side() -> None:
    """A latch holds with no echo while b_on + mean q exceeds the input weight (4.7); below it, only an echo on the
    side of the neuron that is on (its input above -1) holds it; by the end the weights alone hold it."""
    res = compute(FIGURES["latched-spin"], Settings(quick=True, workers=2))
    s = res.summary
    assert s["failures"]["latched spin"] >= 1 and s["shown"]
    for k, env in enumerate(s["shown"]):
        latch = res.arrays[f"env{k}/latch"]
        out = res.arrays[f"env{k}/outputs"]
        i0 = env["latched_from_step"] // s["stride"]
        assert env["end_turn_share"] >= 0.8
        # one neuron on, the other off, from the latch to the end
        assert np.all(np.abs(out[i0:, 0] - out[i0:, 1]) > 1.0)
        assert latch[-1] > latched.THRESHOLD  # by the end, no echo is needed to keep it so
        # the run again, with its inputs: wherever the weights alone would not hold the latch, an echo does
        tr = run_episode(EpisodeConfig.from_spec(spec(env, "plastic", STEPS, "surrogate"))).trajectory
        rows = np.arange(len(tr.outputs))
        on = np.where(tr.outputs[:, 0] > tr.outputs[:, 1], 0, 1)
        weights = tr.b[rows, on] + tr.q.mean(axis=1)
        np.testing.assert_array_equal(weights[:: s["stride"]], latch)  # the figure's trace is this run's
        after = slice(env["latched_from_step"], None)
        weak = weights[after] <= latched.THRESHOLD
        assert np.all(tr.inputs[rows, on][after][weak] > -1.0 + 1e-6)
