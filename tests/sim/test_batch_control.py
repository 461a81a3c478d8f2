"""BatchControllers: restarting one copy (reset_copy) gives its fresh start and leaves the others going."""

import numpy as np

from neurowalk.controller import FixedController, NeuralController
from neurowalk.sim.batch_control import BatchControllers


def _controllers() -> list:
    return [NeuralController("plastic"), FixedController((1.0, -1.0)), NeuralController("static")]


def test_reset_copy_restarts_that_copy_alone():
    dist = np.random.default_rng(0).uniform(0.05, 0.5, size=(30, 3, 2))
    running, fresh = BatchControllers(_controllers()), BatchControllers(_controllers())
    running.reset([None] * 3)
    assert running.compiled
    for d in dist[:10]:
        running.step(d)
    fresh.reset([None] * 3)
    for d in dist[:10]:
        fresh.step(d)
    running.reset_copy(0)
    restarted = BatchControllers(_controllers())
    restarted.reset([None] * 3)
    np.testing.assert_array_equal(running.targets[0], 0.0)
    for k in range(10, 30):
        a, b = running.step(dist[k]).copy(), fresh.step(dist[k]).copy()
        np.testing.assert_array_equal(a[1:], b[1:])  # copies 1 and 2 go on as if nothing happened
        np.testing.assert_array_equal(a[0], restarted.step(dist[k])[0])  # copy 0 from its start
        np.testing.assert_array_equal(running.b[0], restarted.b[0])
