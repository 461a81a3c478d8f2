"""The engines of one world a run: the CPU loop (``mujoco``: AMOSII, the wheeled robot, a user's MJCF robot; resumable)
and the planar bodies' compiled chunks (``surrogate``), both through the one loop (:mod:`neurowalk.sim.loop`).

A long run streams its rows to a sink in chunks (:class:`~neurowalk.sim.engine_interface.Streaming`) and, with
``keep_rows=False``, keeps in memory only one chunk and the columns its summary needs; a physics run writes
checkpoints from which a stopped run goes on bit for bit.
"""

from __future__ import annotations

from neurowalk.body.surrogate import Surrogate
from neurowalk.body.world import CompiledWorld, OneWorld
from neurowalk.sim.batch_control import BatchControllers
from neurowalk.sim.config import Episode, EpisodeConfig, RunInterruptedError, build
from neurowalk.sim.engine_interface import EngineOptions, OneWorldPerCall, Streaming
from neurowalk.sim.loop import run_worlds

__all__ = ["CpuLoop", "SurrogateLoop"]


class CpuLoop(OneWorldPerCall):
    """The CPU loop (engine ``mujoco``): one world per run, runs one after another; resumable, streams its rows."""

    name = "mujoco"
    resumable = True

    def run_one(self, cfg: EpisodeConfig, options: EngineOptions, stream: Streaming) -> Episode:
        """One run, its rows streamed to ``stream.sink`` as it goes, from ``stream.resume`` if given.

        Raises:
            RunInterruptedError: on KeyboardInterrupt; it carries the episode of the completed steps (the sink has
                received all of them).
        """
        arena, body, ctrl = build(cfg, pad_boxes=options.pad_boxes)
        # the planar surrogate is a compiled world (chunks of steps) of its own; a per-step body, one world
        world: CompiledWorld | OneWorld = body if isinstance(body, Surrogate) else OneWorld(body)
        run = run_worlds([cfg], [arena], world, BatchControllers([ctrl], compiled=False), stream,
                         progress=options.progress)  # fmt: skip
        ep = run.episodes[0]
        if isinstance(body, Surrogate):
            ep.summary["surrogate_contacts"] = body.contacts
        if run.interrupted:
            raise RunInterruptedError(ep)
        return ep


class SurrogateLoop(CpuLoop):
    """The planar bodies' engine: each run's body and network in compiled chunks; streams its rows."""

    name = "surrogate"
    resumable = False

    def run_one(self, cfg: EpisodeConfig, options: EngineOptions, stream: Streaming) -> Episode:
        """One run; a planar run is not resumed (it reruns in seconds)."""
        if stream.resume is not None or stream.checkpoint is not None:
            raise ValueError(f"a run of body {cfg.body!r} cannot be resumed (no checkpoints); run it again")
        return super().run_one(cfg, options, stream)
