"""A small recurrent network evolved by CMA-ES on ``neurowalk/Explore-v0``: the learned baseline without torch.

The policy sees what the two neurons see and steers as they do:

.. code-block:: text

    x(t) = 1 - d(t) / 0.2                               # (2,) readings d in m (0.4: no echo) -> [-1, 1]
    h(t) = tanh(W_in x(t) + W_rec h(t-1) + b_h)         # H hidden units (default 4), h(0) = 0
    a(t) = tanh(W_out h(t) + b_out)                     # (2,) steering (O1, O2)

so 2H + H^2 + H + 2H + 2 weights (38 for H = 4). CMA-ES searches them; a candidate's fitness is its mean episode
return (the area it newly covers, the environment's reward) over the generation's training environments, all
candidates on the same environments (common random numbers), every copy of every candidate in one vectorised
environment step. The environments of generation g are those of the reset seeds ``train_seed * 1_000_000 +
g * envs + j`` (j < envs; train_seed < 1000), below the held-out environments of ``neurowalk baseline`` (seeds from
10^9).
The search is saved as JSON after every generation (``state.json``: each generation's candidates and returns),
and a rerun replays it into a fresh CMA-ES of the same seed (:mod:`~neurowalk.experiments.cma_record`):
resumable, bit for bit.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from neurowalk.compiled import jit
from neurowalk.envs.vector import ExploreVectorEnv
from neurowalk.experiments import cma_record
from neurowalk.experiments.cma_record import import_cma
from neurowalk.progress import Progress
from neurowalk.runners.stopping import deferred

HIDDEN = 4
CMA_MISSING = "neuroevo needs cma: pip install -e '.[rl]' in neurowalk's folder"


def n_weights(hidden: int) -> int:
    """Number of weights of the network with ``hidden`` units."""
    return 2 * hidden + hidden * hidden + hidden + 2 * hidden + 2


def features(obs: np.ndarray) -> np.ndarray:
    """Readings (..., 2) in m -> inputs in [-1, 1]: 1 near an obstacle, -1 at the range (0.4 m) or no echo."""
    return 1.0 - np.asarray(obs, dtype=np.float64) / 0.2


@jit
def _rnn_step(theta: np.ndarray, hidden: int, obs: np.ndarray, h: np.ndarray, out: np.ndarray) -> None:
    """n networks one step: theta (n, P) weights, obs (n, 2) readings in m, h (n, H) in place, out (n, 2)."""
    tmp = np.empty(hidden)
    for i in range(obs.shape[0]):
        w = theta[i]
        x0, x1 = 1.0 - obs[i, 0] / 0.2, 1.0 - obs[i, 1] / 0.2
        rec = 2 * hidden
        bh = rec + hidden * hidden
        wo = bh + hidden
        bo = wo + 2 * hidden
        for j in range(hidden):
            s = w[2 * j] * x0 + w[2 * j + 1] * x1 + w[bh + j]
            for m in range(hidden):
                s += w[rec + j * hidden + m] * h[i, m]
            tmp[j] = np.tanh(s)
        h[i] = tmp
        for k in range(2):
            s = w[bo + k]
            for j in range(hidden):
                s += w[wo + k * hidden + j] * h[i, j]
            out[i, k] = np.tanh(s)


class RecurrentPolicy:
    """The recurrent network as a batched policy: (n, 2) readings in m -> (n, 2) steering.

    Args:
        theta: (P,) weights shared by every copy, or (n, P): one set per copy (a population on n copies).
        hidden: hidden units H (P = :func:`n_weights` (H)).
    """

    def __init__(self, theta: np.ndarray, hidden: int = HIDDEN) -> None:
        theta = np.asarray(theta, dtype=np.float64)
        if theta.shape[-1] != n_weights(hidden) or theta.ndim not in (1, 2):
            raise ValueError(f"theta must have shape (P,) or (n, P) with P = {n_weights(hidden)}, got {theta.shape}")
        self.theta, self.hidden = theta, hidden
        self.h: np.ndarray | None = None

    def reset(self) -> None:
        """Hidden state back to 0 (at the next call, for as many copies as it has rows)."""
        self.h = None

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        obs = np.ascontiguousarray(obs, dtype=np.float64)
        single = obs.ndim == 1
        obs = obs.reshape(-1, 2)
        n = len(obs)
        theta = self.theta if self.theta.ndim == 2 else np.broadcast_to(self.theta, (n, len(self.theta)))
        if len(theta) != n:
            raise ValueError(f"{len(theta)} weight sets for {n} observations")
        if self.h is None or len(self.h) != n:
            self.h = np.zeros((n, self.hidden))
        out = np.empty((n, 2))
        _rnn_step(np.ascontiguousarray(theta), self.hidden, obs, self.h, out)
        return out[0] if single else out


def episode_returns(theta: np.ndarray, seeds: list[int], steps: int, hidden: int = HIDDEN) -> np.ndarray:
    """Mean return (m^2 newly covered) of each weight set of theta (λ, P) over the environments of ``seeds``."""
    lam, m = len(theta), len(seeds)
    env = ExploreVectorEnv(lam * m, max_steps=steps)
    obs, _ = env.reset(seed=[s for _ in range(lam) for s in seeds])  # copy c * m + j: candidate c, env j
    policy = RecurrentPolicy(np.repeat(theta, m, axis=0), hidden)
    total = np.zeros(lam * m)
    for _ in range(steps):
        obs, reward, _, _, _ = env.step(policy(obs))
        total += reward
    return total.reshape(lam, m).mean(axis=1)


def train(
    out: Path,
    *,
    generations: int = 300,
    population: int = 16,
    envs: int = 16,
    steps: int = 2000,
    hidden: int = HIDDEN,
    sigma0: float = 0.5,
    seed: int = 0,
    train_seed: int = 0,
    progress: bool = True,
    log: Callable[[str], None] = print,
) -> dict[str, Any]:
    """CMA-ES over the network's weights (resumable from ``out/state.json``); returns the training record.

    Returns:
        ``theta`` (the search's final mean, list), ``hidden``, ``generations``, ``env_steps`` (environment steps
        taken), ``wall_s`` (training time, summed over sessions), ``curve`` (per generation: mean and best
        candidate return, m^2), and the settings.
    """
    cma = import_cma(CMA_MISSING)
    if min(generations, population, envs, steps) < 1 or population < 2:
        raise ValueError("generations, envs and steps must be >= 1 and population >= 2")
    if not 0 <= train_seed < 1000 or generations * envs > 1_000_000:
        raise ValueError(
            f"train_seed must be in [0, 1000) and generations * envs <= 1,000,000 (seed range of a "
            f"training run), got {train_seed} and {generations * envs}"
        )
    settings = {
        "population": population,
        "envs": envs,
        "steps": steps,
        "hidden": hidden,
        "sigma0": sigma0,
        "seed": seed,
        "train_seed": train_seed,
    }
    Path(out).mkdir(parents=True, exist_ok=True)
    path = Path(out) / "state.json"
    state = _state(cma, path, settings)
    done = len(state["curve"])
    quiet = not progress or done >= generations
    bar = Progress(total=generations, initial=done, unit="gen", desc="neuroevolution", mininterval=0.5, disable=quiet)
    while len(state["curve"]) < generations:
        returns = _generation(state, path)
        bar.update(1)
        bar.set_postfix(best=f"{returns.max():.2f} m2")
    bar.close()
    log(f"neuroevolution: {generations} generations, {state['env_steps']:,} env steps, {state['wall_s']:.0f} s")
    return {
        "theta": [float(v) for v in state["es"].mean],
        "hidden": hidden,
        "generations": generations,
        "env_steps": state["env_steps"],
        "wall_s": state["wall_s"],
        "curve": state["curve"],
        **settings,
    }


def _state(cma: Any, path: Path, settings: dict[str, Any]) -> dict[str, Any]:
    """The training of ``settings``: a fresh CMA-ES at zero weights, into which the generations recorded at ``path``
    (if any) are replayed. ValueError naming the file where its record cannot be read or is of other settings."""

    def fresh() -> dict[str, Any]:
        state = {"settings": settings, "curve": [], "rng": None, "wall_s": 0.0, "env_steps": 0, "generations": []}
        x0 = np.zeros(n_weights(settings["hidden"]))
        cma_record.start(cma, state, x0, settings["sigma0"], settings["seed"], settings["population"])
        return state

    kept: dict[str, Any] = {}

    def generations(saved: dict[str, Any]) -> list[tuple[Any, Any]]:
        gens = [(g["x"], g["scores"]) for g in saved["generations"]]
        kept.update(curve=list(saved["curve"]), wall_s=float(saved["wall_s"]), env_steps=int(saved["env_steps"]))
        return gens

    state, saved = cma_record.resume(path, settings, "state.pkl", "the neuroevolution state", fresh, generations)
    if saved is not None:
        state.update(kept, generations=list(saved["generations"]))
    return state


def _generation(state: dict[str, Any], path: Path) -> np.ndarray:
    """One generation of the training ``state``: its candidates walk the generation's training environments, CMA-ES
    is told their returns, and the record is saved to ``path`` whole; returns the mean return of each candidate
    (m^2)."""
    s = state["settings"]
    envs = s["envs"]
    g = len(state["curve"])
    t0 = time.perf_counter()
    xs = np.array(cma_record.ask(state))
    seeds = [s["train_seed"] * 1_000_000 + g * envs + j for j in range(envs)]
    returns = episode_returns(xs, seeds, s["steps"], s["hidden"])
    cma_record.tell(state, xs, -returns)
    state["generations"].append({"x": xs.tolist(), "scores": (-returns).tolist()})
    state["curve"].append({"mean": float(returns.mean()), "best": float(returns.max())})
    state["env_steps"] += s["population"] * envs * s["steps"]
    state["wall_s"] += time.perf_counter() - t0
    with deferred():  # a generation is saved whole: a Ctrl-C now stops the training after it
        cma_record.write(path, {k: state[k] for k in ("settings", "curve", "wall_s", "env_steps", "generations")})
    return returns
