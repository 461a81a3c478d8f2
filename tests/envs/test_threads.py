"""ThreadChooser: runs a kernel on the faster of 1 and all threads, probes the other, changes no result."""

from __future__ import annotations

import numba
import numpy as np

from neurowalk.envs.threads import ThreadChooser
from neurowalk.envs.vector import ExploreVectorEnv


def _feed(ch: ThreadChooser, per_call: dict[int, float], calls: int) -> list[int]:
    """Counts of ``calls`` calls where a call on n threads takes ``per_call[n]`` seconds."""
    used = []
    for _ in range(calls):
        used.append(ch._threads)
        ch.record(per_call[ch._threads])
    return used


def test_it_measures_both_counts_first_then_keeps_the_faster_and_probes_the_other():
    ch = ThreadChooser(2, block=4, probe=5)
    used = _feed(ch, {1: 1.0, 2: 2.0}, 4 * 20)  # one thread is the faster (a busy core)
    assert used[:4] == [2] * 4 and used[4:8] == [1] * 4 and ch.chosen == 1
    blocks = [used[i] for i in range(0, len(used), 4)]
    assert blocks.count(2) == 1 + sum(1 for b in range(2, 20) if b % 5 == 0)  # the first block and every 5th


def test_a_change_of_load_is_followed():
    ch = ThreadChooser(2, block=4, probe=3)
    _feed(ch, {1: 1.0, 2: 0.5}, 40)
    assert ch.chosen == 2
    _feed(ch, {1: 1.0, 2: 3.0}, 200)  # another process takes a core: two threads get slower
    assert ch.chosen == 1
    _feed(ch, {1: 1.0, 2: 0.5}, 200)  # and leaves
    assert ch.chosen == 2


def test_one_thread_is_all_a_single_thread_chooser_uses():
    ch = ThreadChooser(1, block=2)
    assert set(_feed(ch, {1: 1.0}, 20)) == {1} and ch.per_call == {}


def test_calls_put_numbas_setting_back():
    ch = ThreadChooser(2, block=1)
    before = numba.get_num_threads()
    assert ch(lambda x: x + 1, 1) == 2
    assert numba.get_num_threads() == before and ch._calls == 0 and 2 in ch.per_call


def test_the_vector_environment_gives_the_same_steps_on_any_thread_count():
    def rollout(threads: int) -> tuple[np.ndarray, np.ndarray]:
        env = ExploreVectorEnv(64, max_steps=50)
        env.threads = ThreadChooser(threads, block=2, probe=2)  # switches count every other block
        env.reset(seed=5)
        acts = np.random.default_rng(0).uniform(-1, 1, size=(60, 64, 2))
        obs = [env.step(a)[0] for a in acts]
        return np.array(obs), env.pose.copy()

    one, two = rollout(1), rollout(numba.config.NUMBA_NUM_THREADS)
    assert np.array_equal(one[0], two[0]) and np.array_equal(one[1], two[1])


def test_probe_0_keeps_the_most_threads():
    ch = ThreadChooser(2, block=2, probe=0)
    assert set(_feed(ch, {1: 1.0, 2: 5.0}, 40)) == {2}
