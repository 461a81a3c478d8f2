"""PPO / recurrent PPO baselines (the ``rl`` extra; skipped without stable-baselines3 and sb3-contrib)."""

from __future__ import annotations

import json
import tempfile

import numpy as np
import pytest

pytest.importorskip("gymnasium")
pytest.importorskip("stable_baselines3")
pytest.importorskip("sb3_contrib")

from neurowalk.experiments.baselines import ppo
from neurowalk.experiments.baselines.evolved_rnn import features


def test_vec_env_ends_every_copy_together_and_restarts_on_the_next_training_seeds():
    venv = ppo.make_vec_env(3, 5, train_seed=2)
    first = venv.reset()
    assert first.shape == (3, 2) and np.all(np.abs(first) <= 1.0)
    for _k in range(5):
        venv.step_async(np.full((3, 2), -1.0))
        obs, reward, dones, infos = venv.step_wait()
        assert reward.shape == (3,) and np.all(reward >= 0.0)
    assert dones.all() and all(i["TimeLimit.truncated"] for i in infos)
    last = np.array([i["terminal_observation"] for i in infos])
    assert not np.array_equal(last, obs)  # obs is already the next round's first observation
    from neurowalk.envs.vector import ExploreVectorEnv

    ref = ExploreVectorEnv(3, max_steps=5)  # round 1 of train_seed 2: seeds 2,000,003..5
    np.testing.assert_array_equal(features(ref.reset(seed=[2_000_003, 2_000_004, 2_000_005])[0]), obs)


@pytest.mark.parametrize("algo", ["ppo", "rppo"])
def test_training_checkpoints_and_resumes_and_the_policy_acts_in_bounds(tmp_path, algo, monkeypatch):
    temp = tmp_path / "temp"  # stable-baselines3's own logger would make SB3-<time> folders here at each learn()
    temp.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(temp))
    monkeypatch.delenv("SB3_LOGDIR", raising=False)
    out = tmp_path / "run"
    n_steps = ppo.HYPER[algo]["n_steps"]
    per_rollout = n_steps * 2
    kw = {"n_envs": 2, "steps": 100, "checkpoint_every": per_rollout, "progress": False, "log": lambda _: None}
    rec = ppo.train(algo, out, total_steps=per_rollout, **kw)
    assert rec["env_steps"] == per_rollout and (out / "model.npz").is_file()
    with np.load(out / "model.npz", allow_pickle=False) as z:  # plain arrays only: nothing in it runs code
        assert all(z[k].dtype != object for k in z.files) and "meta" in z.files
    assert json.loads((out / "progress.json").read_text())["env_steps"] == per_rollout
    more = ppo.train(algo, out, total_steps=2 * per_rollout, **kw)
    assert more["env_steps"] == 2 * per_rollout and len(more["curve"]) >= len(rec["curve"])
    with pytest.raises(ValueError, match="other settings"):
        ppo.train(algo, out, total_steps=3 * per_rollout, **{**kw, "n_envs": 4})
    policy = ppo.Sb3Policy(algo, out / "model.npz")
    obs = np.random.default_rng(0).uniform(0, 0.4, size=(5, 2))
    a = policy(obs)
    assert a.shape == (5, 2) and np.all(np.isfinite(a))
    policy.reset()
    np.testing.assert_array_equal(policy(obs), a)  # deterministic, and reset() restarts the LSTM's state
    assert list(temp.glob("SB3-*")) == []  # no logger folder left in the temporary folder


@pytest.mark.parametrize("algo", ["ppo", "rppo"])
def test_a_checkpoint_puts_back_the_policy_and_the_optimizer_exactly(tmp_path, algo):
    rl = ppo.import_rl(algo)
    venv = ppo.make_vec_env(2, 50, 0)
    trained = ppo.new_model(rl, algo, venv, seed=1)
    trained.learn(ppo.HYPER[algo]["n_steps"] * 2)  # the optimizer has state (Adam's moments) after an update
    ppo.save_model(trained, tmp_path / "model.npz")
    fresh = ppo.new_model(rl, algo, venv, seed=2)  # other weights to begin with
    ppo.load_model(rl, fresh, tmp_path / "model.npz")
    for (k, a), b in zip(trained.policy.state_dict().items(), fresh.policy.state_dict().values(), strict=True):
        assert rl.torch.equal(a, b), k
    want, got = trained.policy.optimizer.state_dict(), fresh.policy.optimizer.state_dict()
    assert want["param_groups"] == got["param_groups"] and want["state"].keys() == got["state"].keys()
    for i in want["state"]:
        assert all(rl.torch.equal(want["state"][i][k], got["state"][i][k]) for k in want["state"][i])
    assert fresh.num_timesteps == trained.num_timesteps


def test_a_pickled_stable_baselines3_checkpoint_is_refused_unread(tmp_path):
    (tmp_path / "model.zip").write_bytes(b"PK... cloudpickle inside")
    for call in (lambda: ppo.train("ppo", tmp_path, total_steps=10), lambda: ppo.Sb3Policy("ppo", tmp_path / "x")):
        with pytest.raises(ValueError, match=r"model.zip: .*pickles can run code"):
            call()
