"""The one place that chooses an engine: a table from name to engine, and the rule for the planar bodies.

.. code-block:: text

    engine_for(cfg)      ENGINES[cfg.engine]  (mujoco: the CPU loop; mujoco.batch: its runs as lock-step worlds on
                         threads; warp: MuJoCo Warp)
                         a planar body: the surrogate's compiled loop, whatever physics engine is named
    call_groups(cfgs)    groups the configs by (engine, engine.group_key(cfg)), as many as a call takes

No other module compares an engine's name: what an engine can do, it says itself
(:class:`~neurowalk.sim.engine_interface.Engine`). ``mujoco.batch`` (:class:`~neurowalk.sim.batch.MujocoBatch`)
gives the CPU loop's runs bit for bit, as lock-step worlds on threads; a config names it as it names the others (its
runs are stored under their own keys: the store keys what was asked).
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Iterator, Sequence

from neurowalk.body.registry import body_info
from neurowalk.sim.batch import MujocoBatch
from neurowalk.sim.config import EpisodeConfig
from neurowalk.sim.cpu_loop import CpuLoop, SurrogateLoop
from neurowalk.sim.engine_interface import Engine, EngineOptions
from neurowalk.sim.warp_engine import Warp

__all__ = ["ENGINES", "PLANAR", "call_groups", "engine_for"]

ENGINES: dict[str, Engine] = {engine.name: engine for engine in (CpuLoop(), MujocoBatch(), Warp())}
"""The physics engines a config may name (``EpisodeConfig.engine``, ``--engine``): the CPU loop, its runs as
lock-step worlds on ``mujoco.batch`` threads (bit for bit the same), MuJoCo Warp."""
PLANAR: Engine = SurrogateLoop()
"""The engine of the planar (calibrated) bodies."""


def engine_for(cfg: EpisodeConfig) -> Engine:
    """The engine that runs ``cfg``: its named physics engine, or the surrogate's loop for a planar body."""
    return ENGINES[cfg.engine] if body_info(cfg.body).physics else PLANAR


def call_groups(
    configs: Sequence[EpisodeConfig],
    options: EngineOptions,
    *,
    engine_of: Callable[[EpisodeConfig], Engine] = engine_for,
    worlds: int | None = None,
) -> Iterator[tuple[list[int], Engine]]:
    """Indices of the configs that share one call (the same engine and ``engine.group_key``), at most ``worlds`` at a
    time (default: what the engine takes in one call with ``options``), with that engine (``engine_of(cfg)``)."""
    groups: dict[tuple[str, Hashable], list[int]] = {}
    engines: dict[str, Engine] = {}
    for i, cfg in enumerate(configs):
        engine = engine_of(cfg)
        engines[engine.name] = engine
        groups.setdefault((engine.name, engine.group_key(cfg)), []).append(i)
    for (name, _), group in groups.items():
        engine = engines[name]
        size = worlds or engine.worlds_per_call(options) or len(group)
        for c in range(0, len(group), size):
            yield group[c : c + size], engine
