"""neurowalk's networks as policies on the environments, and one evaluation for networks and learned policies.

:class:`NetworkPolicy` maps an observation of ``neurowalk/Explore-v0`` (the two ultrasonic distances) to an action
(the steering pair) through one of the sensory networks (plastic, static, Braitenberg; any variant or params), as
the runs do: on the same body, sensing then steering, it gives the trajectory of ``neurowalk run --body
surrogate`` bit for bit. :func:`evaluate` scores any policy (a callable observation -> action with an optional
``reset()``) on the same environments and seeds with Table 2's success rule, so a learned policy and the two
neurons are compared on equal terms; :func:`evaluate_batch` does the same for a batched policy ((n, 2) -> (n, 2)) on
the vectorised environment, all environments in one compiled step (what ``neurowalk baseline`` scores with).
A :class:`NetworkPolicy` serves both: called with (n, 2) readings it steps n copies of its network at once.
:class:`ControllerPolicy` makes any controller (a user's file too) a policy.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from neurowalk.compiled import jit
from neurowalk.controller import Controller, make_controller
from neurowalk.envs.explore import ExploreEnv
from neurowalk.envs.task import STUCK_RADIUS, STUCK_WINDOW, within_disc
from neurowalk.envs.vector import ExploreVectorEnv
from neurowalk.neural.sensory import STEER, SensoryNetwork, sensory_input, sensory_step
from neurowalk.neural.variants import get_variant
from neurowalk.observation import Observation
from neurowalk.progress import Progress

NETWORKS: tuple[str, ...] = ("plastic", "static", "braitenberg")


class NetworkPolicy:
    """One of neurowalk's sensory networks as a policy: (2,) distances in m -> (2,) steering (O1, O2).

    Args:
        network: ``plastic``, ``static`` or ``braitenberg``.
        variant: ``paper`` (Eq. 1-6 as printed) or ``original`` (the authors' code); see ``neurowalk.neural.variants``.
        params: SensoryParams fields set on top of the variant.
        b0: start self-connection weight b of the plastic network (default: the variant's).
        q0: start learned inhibition q of the plastic network (default: the variant's).

    Call :meth:`reset` at the start of every episode (the weights go back to their start values). Called with (2,)
    readings it steps one network; with (n, 2) readings, n independent copies (each from the start state after
    :meth:`reset`; do not mix the two between resets).
    """

    def __init__(
        self,
        network: str = "plastic",
        *,
        variant: str = "paper",
        params: dict[str, float] | None = None,
        b0: float | None = None,
        q0: float | None = None,
    ) -> None:
        if network not in NETWORKS:
            raise ValueError(f"unknown network {network!r}; expected one of {', '.join(NETWORKS)}")
        self.network, self.variant = network, variant
        self.net = SensoryNetwork(network, params=get_variant(variant, params).sensory, b0=b0, q0=q0)  # type: ignore[arg-type]
        self.states: np.ndarray | None = None  # (n, STATE_SIZE) of the batched copies

    def reset(self) -> None:
        """Start weights, outputs 0 (for the single network and the batched copies)."""
        self.net.reset()
        self.states = None

    def __call__(self, observation: np.ndarray) -> np.ndarray:
        """One network step on the readings ``observation`` (left, right; m): (2,) -> (2,) steering, or (n, 2) ->
        (n, 2) for n copies."""
        p = self.net.packed_params
        if np.ndim(observation) == 2:
            obs = np.ascontiguousarray(observation, dtype=np.float64)
            if self.states is None or len(self.states) != len(obs):
                self.states = np.tile(self.net.state, (len(obs), 1))
            out = np.empty((len(obs), 2))
            _steps(self.states, obs, p, out)
            return out
        s = self.net.state
        sensory_step(s, sensory_input(float(observation[0]), p), sensory_input(float(observation[1]), p), p)
        return np.array([s[STEER], s[STEER + 1]])

    @property
    def weights(self) -> dict[str, list[float]]:
        """The network's current weights: b (2,), q (2,)."""
        return {"b": self.net.b.tolist(), "q": self.net.q.tolist()}


class ControllerPolicy:
    """A controller (a built-in's name, a user's ``FILE.py:NAME`` or a :class:`~neurowalk.controller.Controller`) as
    a policy of the environments: (2,) distances in m -> its steering (O1, O2) (``action="steering"``: the action of
    ``Explore-v0`` and ``ExplorePhysics-v0``) or its (19,) joint targets in rad (``action="joints"``).

    The controller sees what the environment observes: an :class:`~neurowalk.observation.Observation` of the two
    distances (its other readings at their defaults). Call :meth:`reset` at the start of every episode.
    """

    def __init__(self, controller: Controller | str, *, action: str = "steering", seed: int = 0) -> None:
        if action not in ("steering", "joints"):
            raise ValueError(f"unknown action {action!r}; expected steering or joints")
        self.controller = make_controller(controller) if isinstance(controller, str) else controller
        self.action, self._seed = action, seed

    def reset(self) -> None:
        """The controller's start state (its Generator from ``seed``)."""
        self.controller.reset(np.random.default_rng(self._seed))

    def __call__(self, observation: np.ndarray) -> np.ndarray:
        targets = self.controller.act(Observation(us_distance=np.array(observation, dtype=float)))
        return np.array(self.controller.steering, dtype=float) if self.action == "steering" else targets


def evaluate(
    policy: Callable[[np.ndarray], np.ndarray],
    seeds: Sequence[int],
    *,
    steps: int = 20_000,
    env_kwargs: dict[str, Any] | None = None,
    progress: bool = False,
) -> dict[str, Any]:
    """Run ``policy`` for ``steps`` control steps on ``neurowalk/Explore-v0`` reset with each seed; score it.

    Returns ``success`` (runs not stuck at the end: Table 2's rule, the last 3000 steps not within a 0.5 m disc),
    ``environments``, ``success_rate``, and per run (in seed order) ``runs``: seed, stuck, coverage, contacts.
    """
    if not len(seeds):
        raise ValueError("evaluate needs at least one seed")
    env = ExploreEnv(max_steps=steps, **(env_kwargs or {}))
    runs = []
    bar = None
    if progress:
        bar = Progress(total=len(seeds) * steps, unit="step", desc="evaluate", mininterval=0.5)
    for seed in seeds:
        obs, info = env.reset(seed=int(seed))
        if hasattr(policy, "reset"):
            policy.reset()
        truncated = False
        while not truncated:
            obs, _, _, truncated, info = env.step(policy(obs))
        if bar is not None:
            bar.update(steps)
        runs.append(
            {"seed": int(seed), "stuck": info["stuck"], "coverage": info["coverage"], "contacts": info["contacts"]}
        )
    if bar is not None:
        bar.close()
    return _score(runs, steps)


@jit
def _steps(states: np.ndarray, obs: np.ndarray, p: np.ndarray, out: np.ndarray) -> None:
    """n networks one step: states (n, STATE_SIZE) in place, readings obs (n, 2) m, steering into out (n, 2)."""
    for i in range(states.shape[0]):
        sensory_step(states[i], sensory_input(obs[i, 0], p), sensory_input(obs[i, 1], p), p)
        out[i, 0], out[i, 1] = states[i, STEER], states[i, STEER + 1]


def evaluate_batch(
    policy: Callable[[np.ndarray], np.ndarray],
    seeds: Sequence[int],
    *,
    steps: int = 20_000,
    env_kwargs: dict[str, Any] | None = None,
    progress: bool = False,
) -> dict[str, Any]:
    """:func:`evaluate` for a batched policy ((n, 2) readings in m -> (n, 2) steering), on the vectorised
    ``neurowalk/Explore-v0`` (copy i reset with ``seeds[i]``, all copies in one compiled step).

    The environments are those of :func:`evaluate` with the same seeds; the sensor noise is the vector
    environment's (the same statistics, other draws), so the two functions' scores differ run by run. Returns the
    dict of :func:`evaluate`.
    """
    if not len(seeds):
        raise ValueError("evaluate_batch needs at least one seed")
    n = len(seeds)
    env = ExploreVectorEnv(n, max_steps=steps, **(env_kwargs or {}))
    obs, info = env.reset(seed=[int(s) for s in seeds])
    if hasattr(policy, "reset"):
        policy.reset()
    window = np.zeros((min(STUCK_WINDOW, steps + 1), n, 2))  # the last positions (order does not matter)
    window[0] = info["pose"][:, :2]
    bar = None
    if progress:
        bar = Progress(total=n * steps, unit="step", desc="evaluate", mininterval=0.5)
    for k in range(1, steps + 1):
        obs, _, _, _, info = env.step(np.clip(policy(obs), -1.0, 1.0))
        window[k % len(window)] = info["pose"][:, :2]
        if bar is not None and k % 100 == 0:
            bar.update(100 * n)
    if bar is not None:
        bar.close()
    stuck = [
        steps + 1 >= STUCK_WINDOW and bool(within_disc(np.ascontiguousarray(window[:, i]), STUCK_RADIUS))
        for i in range(n)
    ]
    runs = [
        {
            "seed": int(s),
            "stuck": stuck[i],
            "coverage": float(info["coverage"][i]),
            "contacts": int(info["contacts"][i]),
        }
        for i, s in enumerate(seeds)
    ]
    return _score(runs, steps)


def _score(runs: list[dict[str, Any]], steps: int) -> dict[str, Any]:
    success = sum(not r["stuck"] for r in runs)
    return {
        "success": success,
        "environments": len(runs),
        "success_rate": success / len(runs),
        "steps": steps,
        "rule": "not stuck at the end: the last 3000 control steps not within a disc of radius 0.5 m",
        "runs": runs,
    }
