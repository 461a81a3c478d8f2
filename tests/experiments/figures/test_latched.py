"""The latched-spin figure: the Table 2 failure mechanism of the plastic network, found and explained."""

from __future__ import annotations

import numpy as np
import pytest

from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.figures import latched
from neurowalk.experiments.study import compute


@pytest.mark.xfail(
    strict=True,
    reason="issue 39: with the surrogate recalibrated on the 10 ms physics, a shown latch's b_on + mean q dips to "
    "4.29 after its start, under THRESHOLD - 0.3 = 4.4; the latch itself holds (end_turn_share >= 0.8): not yet "
    "looked into",
)
def test_latched_spins_hold_while_b_on_plus_mean_q_exceeds_the_input_weight() -> None:
    res = compute(FIGURES["latched-spin"], Settings(quick=True, workers=2))
    s = res.summary
    assert s["failures"]["latched spin"] >= 1 and s["shown"]
    for k, env in enumerate(s["shown"]):
        latch = res.arrays[f"env{k}/latch"]
        out = res.arrays[f"env{k}/outputs"]
        i0 = env["latched_from_step"] // s["stride"]
        assert env["end_turn_share"] >= 0.8
        # one neuron on, the other off, from the latch to the end, with no echo needed to keep it so
        assert np.all(np.abs(out[i0:, 0] - out[i0:, 1]) > 1.0)
        assert np.min(latch[i0:]) > latched.THRESHOLD - 0.3
