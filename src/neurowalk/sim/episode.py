"""``run_episode``: one run of a config, on the engine that runs it (:mod:`neurowalk.sim.engines`).

.. code-block:: text

    engine = engine_for(cfg)               # the CPU loop, MuJoCo Warp, or the planar surrogate's loop
    engine.check([cfg], options)           # what the config cannot say about itself (a device, a group)
    episode = engine.run_one(cfg, options, stream)

The config was checked when it was made (:class:`~neurowalk.sim.config.EpisodeConfig`). The names a run needs
(config, episode, summary, streaming options) are re-exported here.
"""

from __future__ import annotations

from neurowalk.sim.config import BODIES, MAX_STEPS, Episode, EpisodeConfig, RunInterruptedError, build, seeds
from neurowalk.sim.engine_interface import EngineOptions, Resume, Streaming
from neurowalk.sim.engines import engine_for
from neurowalk.sim.summarize import PICTURE_ROWS, summarize

__all__ = [
    "BODIES",
    "MAX_STEPS",
    "PICTURE_ROWS",
    "EngineOptions",
    "Episode",
    "EpisodeConfig",
    "Resume",
    "RunInterruptedError",
    "Streaming",
    "build",
    "run_episode",
    "seeds",
    "summarize",
]


def run_episode(
    cfg: EpisodeConfig,
    *,
    progress: bool = False,
    stream: Streaming | None = None,
    options: EngineOptions | None = None,
) -> Episode:
    """Run one episode and summarise it.

    Args:
        cfg: the run.
        progress: show a progress bar (rate, time left); ``options.progress`` where options are given.
        stream: where the rows go while it runs (sink, part size, checkpoints, resume; :class:`Streaming`).
        options: how the engine runs (device, threads; :class:`EngineOptions`).

    Raises:
        RunInterruptedError: on KeyboardInterrupt; it carries the episode of the completed steps (the sink
            has received all of them).
    """
    engine = engine_for(cfg)
    options = options or EngineOptions(progress=progress)
    engine.check([cfg], options)
    return engine.run_one(cfg, options, stream or Streaming())
