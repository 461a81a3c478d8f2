"""`neurowalk baseline`: the evolved recurrent network, the batched evaluation, the driver's files and resumption."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("gymnasium")
pytest.importorskip("cma")

from neurowalk.envs.policy import NetworkPolicy, evaluate, evaluate_batch
from neurowalk.experiments.baselines import comparison, evolved_rnn
from neurowalk.experiments.baselines.evolved_rnn import RecurrentPolicy, n_weights
from neurowalk.runners.store import ResultStore


def test_one_hidden_unit_step_by_hand():
    # theta = (W_in (1x2), W_rec (1x1), b_h, W_out (2x1), b_out (2)); readings 0.1 m and 0.4 m -> x = (0.5, -1)
    theta = np.array([0.3, -0.7, 0.5, 0.1, 1.2, -0.8, 0.05, -0.02])
    assert len(theta) == n_weights(1)
    pol = RecurrentPolicy(theta, hidden=1)
    a1 = pol(np.array([[0.1, 0.4]]))
    h1 = math.tanh(0.3 * 0.5 - 0.7 * -1.0 + 0.1)
    np.testing.assert_allclose(a1[0], [math.tanh(1.2 * h1 + 0.05), math.tanh(-0.8 * h1 - 0.02)], rtol=1e-14)
    a2 = pol(np.array([[0.4, 0.4]]))  # the recurrent weight carries h1 into the second step
    h2 = math.tanh(0.3 * -1.0 - 0.7 * -1.0 + 0.5 * h1 + 0.1)
    np.testing.assert_allclose(a2[0], [math.tanh(1.2 * h2 + 0.05), math.tanh(-0.8 * h2 - 0.02)], rtol=1e-14)
    pol.reset()
    np.testing.assert_array_equal(pol(np.array([[0.1, 0.4]])), a1)


def test_batched_copies_each_follow_their_own_weights():
    rng = np.random.default_rng(3)
    thetas = rng.normal(size=(3, n_weights(4)))
    obs = rng.uniform(0, 0.4, size=(30, 3, 2))
    batched = RecurrentPolicy(thetas)
    out = np.array([batched(o) for o in obs])
    assert np.all(np.abs(out) <= 1.0)
    for i in range(3):
        single = RecurrentPolicy(thetas[i])
        np.testing.assert_array_equal(np.array([single(o[i]) for o in obs]), out[:, i])
    with pytest.raises(ValueError, match="shape"):
        RecurrentPolicy(np.zeros(5))
    with pytest.raises(ValueError, match="3 weight sets for 2"):
        batched(np.zeros((2, 2)))


def test_batched_network_policy_is_the_single_one_per_copy():
    obs = np.random.default_rng(1).uniform(0, 0.4, size=(200, 4, 2))
    pol = NetworkPolicy("plastic")
    out = np.array([pol(o) for o in obs])
    for i in range(4):
        pol.reset()
        np.testing.assert_array_equal(np.array([pol(o[i]) for o in obs]), out[:, i])


def test_batched_evaluation_scores_as_the_single_one_without_noise():
    # without noise the vector environment is the single one bit for bit, so the two evaluations must agree exactly
    seeds = [10**9 + i for i in range(3)]
    single = evaluate(NetworkPolicy("braitenberg"), seeds, steps=3200, env_kwargs={"noise": 0.0})
    batch = evaluate_batch(NetworkPolicy("braitenberg"), seeds, steps=3200, env_kwargs={"noise": 0.0})
    assert single["runs"] == batch["runs"]
    assert single["success"] == batch["success"]


def test_neuroevolution_resumes_bit_for_bit(tmp_path):
    kw = {"population": 4, "envs": 2, "steps": 60, "hidden": 2, "progress": False, "log": lambda _: None}
    whole = evolved_rnn.train(tmp_path / "a", generations=3, **kw)
    evolved_rnn.train(tmp_path / "b", generations=1, **kw)
    resumed = evolved_rnn.train(tmp_path / "b", generations=3, **kw)
    assert whole["theta"] == resumed["theta"] and whole["curve"] == resumed["curve"]
    assert whole["env_steps"] == 3 * 4 * 2 * 60
    with pytest.raises(ValueError, match="other settings"):
        evolved_rnn.train(tmp_path / "b", generations=3, **{**kw, "envs": 3})


class _Evil:
    """Unpickling this creates a file: proof that a pickle was loaded."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def __reduce__(self) -> tuple:
        return (Path.touch, (self.path,))


def test_the_neuroevolution_state_is_json_and_a_crafted_pickle_runs_nothing(tmp_path):
    import pickle

    kw = {"population": 4, "envs": 2, "steps": 20, "hidden": 2, "progress": False, "log": lambda _: None}
    evolved_rnn.train(tmp_path / "a", generations=1, **kw)
    assert json.loads((tmp_path / "a" / "state.json").read_text())["format"] == 1
    (tmp_path / "b").mkdir()
    (tmp_path / "b" / "state.pkl").write_bytes(pickle.dumps({"es": _Evil(tmp_path / "pwned")}))
    with pytest.raises(ValueError, match=r"state\.pkl"):
        evolved_rnn.train(tmp_path / "b", generations=1, **kw)
    assert not (tmp_path / "pwned").exists()
    (tmp_path / "a" / "state.json").write_text('{"format": 1, "settings": ')  # cut short
    with pytest.raises(ValueError, match=r"state\.json"):
        evolved_rnn.train(tmp_path / "a", generations=2, **kw)


def test_run_writes_the_table_plot_and_data_and_reuses_finished_work(tmp_path):
    sizes = {"generations": 2, "population": 4, "envs": 2, "episode_steps": 50, "eval_envs": 3, "eval_steps": 3100}
    r = comparison.run(tmp_path, methods=["neuroevo"], quick=True, sizes=sizes, progress=False, log=lambda _: None)
    assert [row["name"] for row in r["rows"]] == ["plastic", "plastic-original", "static", "braitenberg", "neuroevo"]
    for row in r["rows"]:
        lo, hi = row["ci95"]
        assert row["n"] == 3 and lo <= row["rate"] <= hi and len(row["coverage"]) == 3
    assert r["rows"][-1]["train_env_steps"] == 2 * 4 * 2 * 50 and r["rows"][0]["train_env_steps"] is None
    saved = json.loads((tmp_path / "baselines.json").read_text())
    assert saved["rows"] == json.loads(json.dumps(r["rows"]))
    assert (tmp_path / "baselines.png").stat().st_size > 10_000
    assert "| evolved RNN (CMA-ES) |" in (tmp_path / "baselines.md").read_text()
    with ResultStore(tmp_path / "results.sqlite") as store:  # each policy's score: a job of the one runner
        stamps = {row["key"]: row["finished_at"] for row in store.rows("ok")}
    assert len(stamps) == 5
    again = comparison.run(tmp_path, methods=["neuroevo"], quick=True, sizes=sizes, progress=False, log=lambda _: None)
    assert again["rows"] == r["rows"]
    with ResultStore(tmp_path / "results.sqlite") as store:
        assert {row["key"]: row["finished_at"] for row in store.rows("ok")} == stamps  # nothing rescored
    bigger = {**sizes, "eval_envs": 4}  # other settings: scored again, beside the others
    comparison.run(tmp_path, methods=["neuroevo"], quick=True, sizes=bigger, progress=False, log=lambda _: None)
    with ResultStore(tmp_path / "results.sqlite") as store:
        assert len(store.rows("ok")) == 10


def test_sizes_and_methods_are_checked_before_any_work():
    with pytest.raises(ValueError, match="--eval-envs"):
        comparison.sizes_of(False, {"eval_envs": 0})
    with pytest.raises(ValueError, match="--population"):
        comparison.sizes_of(True, {"population": 1})
    with pytest.raises(ValueError, match="'a2c'"):
        comparison.check_methods(["neuroevo", "a2c"])
