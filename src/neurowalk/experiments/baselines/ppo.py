"""PPO and recurrent PPO (stable-baselines3, sb3-contrib) on ``neurowalk/Explore-v0``: the learned baselines.

Both train on the vectorised surrogate environment through :class:`SurrogateVecEnv`, stable-baselines3's ``VecEnv``
over :class:`~neurowalk.envs.vector.ExploreVectorEnv`: observations are the readings mapped to [-1, 1] as for the
evolved network (:func:`.evolved_rnn.features`), the reward is the environment's (m^2 newly covered), every
episode ends by truncation after ``steps`` control steps (so all copies end together and restart on the next
training seeds: ``train_seed * 1_000_000 + e * n_envs + j`` for the e-th round of episodes, below the held-out
seeds of ``neurowalk baseline``). Checkpoints (``model.npz`` and ``progress.json``) are written every
``checkpoint_every`` steps; a run started again continues from the last one (the same environments onward, not
the same numbers bit for bit: torch's and stable-baselines3's state between checkpoints is not kept).

A checkpoint holds the policy's and its optimizer's tensors as plain arrays (``model.npz``, read with
``allow_pickle=False``) and the optimizer's settings as JSON inside it; the model is built again from
:data:`HYPER` and the run's settings and the arrays are put into it. stable-baselines3's own ``model.zip`` holds
cloudpickle, which can run code when read: a folder with one is refused.

Needs the ``rl`` extra (torch, stable-baselines3, sb3-contrib), imported in one place (:func:`import_rl`); see the
README for a CPU-only torch.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

from neurowalk.envs.vector import ExploreVectorEnv
from neurowalk.experiments.baselines.evolved_rnn import features
from neurowalk.fileio import atomic_write, write_json
from neurowalk.progress import Progress as ProgressBar
from neurowalk.runners.stopping import deferred


class RlMissingError(ImportError):
    """stable-baselines3 / sb3-contrib (the ``rl`` extra) is not installed."""


@dataclass(frozen=True)
class Rl:
    """What training and scoring use of the ``rl`` extra."""

    algo: Any  # the algorithm class: stable-baselines3's PPO or sb3-contrib's RecurrentPPO
    torch: Any
    vec_env: Any  # stable-baselines3's VecEnv
    callback: Any  # stable-baselines3's BaseCallback
    logger: Any  # stable-baselines3's Logger


def import_rl(algo: str) -> Rl:
    """The ``rl`` extra for ``algo`` (``ppo``: PPO, ``rppo``: RecurrentPPO); RlMissingError names the install."""
    try:
        if algo == "ppo":
            from stable_baselines3 import PPO

            algo_class = PPO
        else:
            from sb3_contrib import RecurrentPPO

            algo_class = RecurrentPPO
        import torch
        from stable_baselines3.common.callbacks import BaseCallback
        from stable_baselines3.common.logger import Logger
        from stable_baselines3.common.vec_env import VecEnv
    except ImportError as e:
        raise RlMissingError(
            f"{algo} needs the rl extra ({e.name} is missing): pip install -e '.[rl]' in neurowalk's folder (CPU "
            "torch first: pip install torch --index-url https://download.pytorch.org/whl/cpu)"
        ) from e
    return Rl(algo_class, torch, VecEnv, BaseCallback, Logger)


def make_vec_env(n_envs: int, steps: int, train_seed: int, first_round: int = 0) -> Any:
    """A :class:`SurrogateVecEnv` (built here, as its base class comes from stable-baselines3)."""

    class SurrogateVecEnv(import_rl("ppo").vec_env):  # either algorithm's: both take stable-baselines3's VecEnv
        """``n_envs`` copies of the surrogate task as a stable-baselines3 ``VecEnv`` (see the module text)."""

        def __init__(self) -> None:
            self.env = ExploreVectorEnv(n_envs, max_steps=steps)
            space = gym.spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float64)
            super().__init__(n_envs, space, self.env.single_action_space)
            self.round = first_round
            self._actions = np.zeros((n_envs, 2))

        def _new_round(self) -> np.ndarray:
            base = train_seed * 1_000_000 + self.round * n_envs
            self.round += 1
            return features(self.env.reset(seed=[base + j for j in range(n_envs)])[0])

        def reset(self) -> np.ndarray:
            return self._new_round()

        def step_async(self, actions: np.ndarray) -> None:
            self._actions = np.clip(np.asarray(actions, dtype=np.float64).reshape(n_envs, 2), -1.0, 1.0)

        def step_wait(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict[str, Any]]]:
            obs, reward, _, truncated, _ = self.env.step(self._actions)
            x = features(obs)
            infos: list[dict[str, Any]] = [{} for _ in range(n_envs)]
            if truncated.all():  # every copy ends together (same max_steps, no termination)
                for i in range(n_envs):
                    infos[i] = {"terminal_observation": x[i], "TimeLimit.truncated": True}
                x = self._new_round()
            return x, reward.astype(np.float32), truncated.copy(), infos

        def close(self) -> None:
            self.env.close()

        def get_attr(self, attr_name: str, indices: Any = None) -> list[Any]:
            return [getattr(self.env, attr_name)] * len(self._idx(indices))

        def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:
            setattr(self.env, attr_name, value)

        def env_method(self, method_name: str, *args: Any, indices: Any = None, **kwargs: Any) -> list[Any]:
            return [getattr(self.env, method_name)(*args, **kwargs)] * len(self._idx(indices))

        def env_is_wrapped(self, wrapper_class: type, indices: Any = None) -> list[bool]:
            return [False] * len(self._idx(indices))

        def _idx(self, indices: Any) -> list[int]:
            return list(range(n_envs)) if indices is None else list(np.atleast_1d(indices))

    return SurrogateVecEnv()


# stable-baselines3's defaults but for rollout sizes that fit 16 copies and a discount whose horizon (1000 steps,
# 100 s) spans an escape from a corner (tens of seconds of walking at about 1.4 cm/s)
_SHARED: dict[str, Any] = {"batch_size": 512, "n_epochs": 10, "learning_rate": 3e-4, "gamma": 0.999}
HYPER: dict[str, dict[str, Any]] = {
    "ppo": {"n_steps": 256, **_SHARED, "policy": "MlpPolicy", "policy_kwargs": {"net_arch": [64, 64]}},
    "rppo": {
        "n_steps": 128,
        **_SHARED,
        "policy": "MlpLstmPolicy",
        "policy_kwargs": {"lstm_hidden_size": 32, "net_arch": [64]},
    },
}


def train(
    algo: str,
    out: Path,
    *,
    total_steps: int,
    n_envs: int = 16,
    steps: int = 2000,
    seed: int = 0,
    train_seed: int = 0,
    checkpoint_every: int = 100_000,
    progress: bool = True,
    log: Callable[[str], None] = print,
) -> dict[str, Any]:
    """Train ``algo`` for ``total_steps`` environment steps (resuming from ``out/model.npz``); the training record.

    Returns ``env_steps``, ``wall_s`` (summed over sessions), ``hyperparameters``, ``curve`` (mean episode
    return of each round of episodes, m^2) and the settings; the model is ``out/model.npz``
    (:func:`save_model`). ValueError where ``out`` holds another run's settings or a pickled ``model.zip``.
    """
    rl = import_rl(algo)
    if total_steps < 1 or n_envs < 1 or steps < 1:
        raise ValueError(f"total_steps, n_envs and steps must be >= 1, got {total_steps}, {n_envs}, {steps}")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    settings = {"algo": algo, "n_envs": n_envs, "steps": steps, "seed": seed, "train_seed": train_seed}
    prog_path, model_path = out / "progress.json", out / MODEL
    refuse_pickled(out)
    record: dict[str, Any] = {**settings, "env_steps": 0, "wall_s": 0.0, "curve": []}
    if prog_path.is_file() and model_path.is_file():
        old = json.loads(prog_path.read_text())
        for key, value in settings.items():
            if old.get(key) != value:
                raise ValueError(
                    f"{str(out)!r} holds a {old.get('algo')} run with other settings ({key}: "
                    f"{old.get(key)!r}, asked {value!r}); use another output folder"
                )
        record = old
    rl.torch.manual_seed(seed)
    rounds = record["env_steps"] // (n_envs * steps)
    venv = make_vec_env(n_envs, steps, train_seed, first_round=rounds)
    model = new_model(rl, algo, venv, seed)
    if record["env_steps"]:
        load_model(rl, model, model_path)
    callback = _callback(rl, record, n_envs, total_steps, progress)
    while record["env_steps"] < total_steps:
        chunk = min(checkpoint_every, total_steps - record["env_steps"])
        t0 = time.perf_counter()
        model.learn(chunk, reset_num_timesteps=False, callback=callback)
        record["wall_s"] += time.perf_counter() - t0
        record["env_steps"] = int(model.num_timesteps)
        with deferred():  # the model and its progress agree: a Ctrl-C now stops the training after this checkpoint
            save_model(model, model_path)
            write_json(prog_path, {**record, "hyperparameters": HYPER[algo]})
    callback.close()
    log(f"{algo}: {record['env_steps']:,} env steps, {record['wall_s']:.0f} s")
    return {**record, "hyperparameters": HYPER[algo]}


def _callback(rl: Rl, record: dict[str, Any], n_envs: int, total: int, progress: bool) -> Any:
    class Progress(rl.callback):
        """Progress bar over env steps; the mean return of each round of episodes into the record's curve."""

        def __init__(self) -> None:
            super().__init__()
            self.returns = np.zeros(n_envs)
            start = record["env_steps"]
            self.bar = ProgressBar(
                total=total, initial=start, unit="step", desc="training", mininterval=0.5, disable=not progress
            )

        def _on_step(self) -> bool:
            self.returns += self.locals["rewards"]
            if self.locals["dones"].all():
                record["curve"].append(float(self.returns.mean()))
                self.returns[:] = 0.0
                self.bar.set_postfix(ret=f"{record['curve'][-1]:.2f} m2")
            self.bar.update(n_envs)
            return True

        def close(self) -> None:
            self.bar.close()

    return Progress()


MODEL = "model.npz"  # a checkpoint: the policy's and the optimizer's tensors, plain arrays


def new_model(rl: Rl, algo: str, venv: Any, seed: int = 0) -> Any:
    """``algo``'s model with :data:`HYPER`'s settings on ``venv``, its weights drawn from ``seed``; it logs nowhere
    (stable-baselines3's own logger would leave an empty ``SB3-<time>`` folder in the temporary folder at each
    ``learn``)."""
    hyper = dict(HYPER[algo])
    policy = hyper.pop("policy")
    model = rl.algo(policy, venv, seed=seed, device="cpu", verbose=0, **hyper)
    model.set_logger(rl.logger(folder=None, output_formats=[]))
    return model


def save_model(model: Any, path: Path) -> None:
    """Write ``model``'s policy and optimizer state to ``path`` (.npz, whole or not at all): every tensor as a plain
    array (``policy/NAME``, ``optimizer/PARAM/NAME``) and, as JSON bytes in ``meta``, the optimizer's parameter
    groups and the steps trained."""
    arrays = {f"policy/{k}": v.detach().cpu().numpy() for k, v in model.policy.state_dict().items()}
    opt = model.policy.optimizer.state_dict()
    for i, state in opt["state"].items():
        arrays.update({f"optimizer/{i}/{k}": np.asarray(v.detach().cpu() if hasattr(v, "detach") else v)
                       for k, v in state.items()})  # fmt: skip
    meta = {"param_groups": opt["param_groups"], "num_timesteps": int(model.num_timesteps)}
    arrays["meta"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
    atomic_write(Path(path), lambda tmp: np.savez(open(tmp, "wb"), **arrays))  # noqa: SIM115 (np.savez closes it)


def load_model(rl: Rl, model: Any, path: Path) -> None:
    """Put the state :func:`save_model` wrote to ``path`` into ``model`` (made by :func:`new_model` with the same
    algorithm); ValueError naming the file where it is not such a checkpoint."""
    try:
        with np.load(path, allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files}
        meta = json.loads(arrays.pop("meta").tobytes())
        policy = {k[len("policy/") :]: rl.torch.as_tensor(v) for k, v in arrays.items() if k.startswith("policy/")}
        state: dict[int, dict[str, Any]] = {}
        for k, v in arrays.items():
            if k.startswith("optimizer/"):
                _, i, name = k.split("/", 2)
                state.setdefault(int(i), {})[name] = rl.torch.as_tensor(v)
        model.policy.load_state_dict(policy, strict=True)
        groups = [
            {k: tuple(v) if isinstance(v, list) and k != "params" else v for k, v in g.items()}
            for g in meta["param_groups"]
        ]  # fmt: skip  (JSON's lists back to the tuples they were: betas)
        model.policy.optimizer.load_state_dict({"state": state, "param_groups": groups})
    except (OSError, ValueError, KeyError, RuntimeError) as e:
        raise ValueError(f"{path}: not a checkpoint of this model ({type(e).__name__}: {e})") from None
    model.num_timesteps = int(meta["num_timesteps"])


def refuse_pickled(out: Path) -> None:
    """ValueError where ``out`` holds stable-baselines3's ``model.zip`` (cloudpickle: reading it can run code)."""
    if (Path(out) / "model.zip").exists():
        raise ValueError(
            f"{Path(out) / 'model.zip'}: a checkpoint of an older neurowalk, in stable-baselines3's format, whose "
            "pickles can run code when read: not read; train again into another folder"
        )


class Sb3Policy:
    """A trained model as a batched policy for :func:`~neurowalk.envs.policy.evaluate_batch`: (n, 2) readings in m
    -> (n, 2) steering, deterministic (the mean action), with the LSTM's state kept per copy for ``rppo``."""

    def __init__(self, algo: str, path: Path) -> None:
        refuse_pickled(Path(path).parent)
        rl = import_rl(algo)
        self.model = new_model(rl, algo, make_vec_env(1, 1, 0))
        load_model(rl, self.model, path)
        self.recurrent = algo == "rppo"
        self.reset()

    def reset(self) -> None:
        """Episode start: the LSTM's state back to zero."""
        self.state: Any = None
        self.start: np.ndarray | None = None

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        x = features(obs)
        if not self.recurrent:
            return self.model.predict(x, deterministic=True)[0]
        if self.start is None:
            self.start = np.ones(len(x), dtype=bool)
        action, self.state = self.model.predict(x, state=self.state, episode_start=self.start, deterministic=True)
        self.start = np.zeros(len(x), dtype=bool)
        return action
