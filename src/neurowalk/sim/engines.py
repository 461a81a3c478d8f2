"""The one place that chooses an engine: a table from name to engine, and the rule for the planar bodies.

.. code-block:: text

    engine_for(cfg)      ENGINES[cfg.engine]  (mujoco: the CPU loop; warp: MuJoCo Warp)
                         a planar body: the surrogate's compiled loop, whatever physics engine is named
    run_configs(cfgs)    groups the configs by (engine, engine.group_key(cfg)); one call per group

No other module compares an engine's name: what an engine can do, it says itself (:class:`~.engine.Engine`).
``mujoco.batch`` (:class:`~neurowalk.sim.batch.MujocoBatch`) runs the same configs as the CPU loop, bit for bit, as
lock-step worlds on threads; it is an engine object, not a config value.
"""

from __future__ import annotations

from collections.abc import Sequence

from neurowalk.body.registry import body_info
from neurowalk.sim.batch import MujocoBatch
from neurowalk.sim.config import ENGINES as ENGINE_NAMES
from neurowalk.sim.config import Episode, EpisodeConfig
from neurowalk.sim.cpu_loop import CpuLoop
from neurowalk.sim.engine import Engine, EngineOptions
from neurowalk.sim.surrogate_episode import SurrogateLoop
from neurowalk.sim.warp_engine import Warp

__all__ = ["ENGINES", "PLANAR", "engine_for", "run_configs"]

ENGINES: dict[str, Engine] = {engine.name: engine for engine in (CpuLoop(), Warp())}
"""The physics engines a config may name (``EpisodeConfig.engine``, ``--engine``)."""
PLANAR: Engine = SurrogateLoop()
"""The engine of the planar (calibrated) bodies."""
BATCH: Engine = MujocoBatch()
"""The CPU loop's runs as lock-step worlds on ``mujoco.batch`` threads."""
assert tuple(ENGINES) == ENGINE_NAMES, "sim.config.ENGINES names the engines of this table, in its order"


def engine_for(cfg: EpisodeConfig) -> Engine:
    """The engine that runs ``cfg``: its named physics engine, or the surrogate's loop for a planar body."""
    return ENGINES[cfg.engine] if body_info(cfg.body).physics else PLANAR


def run_configs(configs: Sequence[EpisodeConfig], options: EngineOptions | None = None) -> list[Episode]:
    """Every config's episode, in order: configs that may share a call (same engine and group key) share one.

    Stopped part-way (KeyboardInterrupt), a group's runs hold their completed steps; runs that had not started are
    None.
    """
    options = options or EngineOptions()
    groups: dict[tuple[str, object], list[int]] = {}
    for i, cfg in enumerate(configs):
        engine = engine_for(cfg)
        groups.setdefault((engine.name, engine.group_key(cfg)), []).append(i)
    out: list[Episode | None] = [None] * len(configs)
    for idx in groups.values():
        batch = [configs[i] for i in idx]
        engine = engine_for(batch[0])
        engine.check(batch, options)
        for i, ep in zip(idx, engine.run(batch, options), strict=False):
            out[i] = ep
    return out  # type: ignore[return-value]
