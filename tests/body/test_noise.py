"""The coloured sensor noise: LPZRobots' filter, drawn in blocks yet bit for bit one draw per step."""

import math
import pickle

import numpy as np
import pytest

from neurowalk.body.noise import BLOCK, ColoredNoise, ColoredNoiseBatch


def _by_hand(seed: int, n: int, steps: int, strength: float = 0.02, tau: float = 0.05) -> np.ndarray:
    rng, v, out = np.random.default_rng(seed), np.zeros(n), []
    for _ in range(steps):
        v = v + (math.sqrt(tau) * strength * rng.uniform(-1.0, 1.0, n) - tau * v)  # the filter, in its order
        out.append(v.copy())
    return np.array(out)


def test_block_draws_give_the_per_step_noise_bit_for_bit():
    noise = ColoredNoise(27)
    noise.reset(np.random.default_rng(4))
    got = np.array([noise.step().copy() for _ in range(3 * BLOCK + 5)])  # across block boundaries
    np.testing.assert_array_equal(got, _by_hand(4, 27, 3 * BLOCK + 5))


def test_a_pickled_source_goes_on_with_the_same_numbers():
    noise = ColoredNoise(2)
    noise.reset(np.random.default_rng(9))
    for _ in range(BLOCK // 2):
        noise.step()
    copy = pickle.loads(pickle.dumps(noise))
    a = [noise.step().copy() for _ in range(BLOCK)]
    b = [copy.step().copy() for _ in range(BLOCK)]
    np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(np.array(a), _by_hand(9, 2, BLOCK // 2 + BLOCK)[BLOCK // 2 :])


def test_zero_strength_is_silent_and_reset_restarts():
    quiet = ColoredNoise(3, strength=0.0)
    quiet.reset(np.random.default_rng(0))
    assert not np.any([quiet.step() for _ in range(10)])
    noise = ColoredNoise(3)
    noise.reset(np.random.default_rng(1))
    first = [noise.step().copy() for _ in range(7)]
    noise.reset(np.random.default_rng(1))
    np.testing.assert_array_equal(first, [noise.step().copy() for _ in range(7)])


def test_the_batch_steps_every_world_as_its_own_source_does_bit_for_bit():
    """Worlds of other seeds, strengths (0 included: silent) and filter constants, across block boundaries: each row
    of the batch is its world's source stepped alone, bit for bit; a reset starts every world again."""
    settings = [(0.02, 0.05), (0.0, 0.05), (0.05, 0.3), (0.02, 0.05), (0.01, 1.0)]
    alone = [ColoredNoise(27, s, t) for s, t in settings]
    batch = ColoredNoiseBatch([ColoredNoise(27, s, t) for s, t in settings])
    for round_ in range(2):
        for k, source in enumerate(alone):
            source.reset(np.random.default_rng(10 * round_ + k))
        batch.reset([np.random.default_rng(10 * round_ + k) for k in range(len(settings))])
        for _ in range(2 * BLOCK + 7):
            got = batch.step()
            np.testing.assert_array_equal(got, np.stack([s.step() for s in alone]))
        assert not got[1].any()  # strength 0


def test_a_batch_refuses_sources_of_other_channels():
    with pytest.raises(ValueError, match=r"same channels, got \[2, 27\]"):
        ColoredNoiseBatch([ColoredNoise(27), ColoredNoise(2)])
