"""The Engine interface: how a list of episode configs becomes episodes.

.. code-block:: text

    engine = engine_for(cfg)                     # sim/engines.py: the one place that chooses
    engine.check(cfgs, options)                  # refuses what it cannot run, in one line
    engine.group_key(cfg)                        # configs with equal keys may share one call
    episodes = engine.run(cfgs, options)         # many worlds at once, or one after another
    episode = engine.run_one(cfg, options, stream)   # one run, its rows streamed (sink, checkpoints, resume)

An engine says what it can do: ``many_worlds`` (one call steps many configs in lock step), ``resumable`` (goes on
from a checkpoint). Which bodies an engine runs is the body table's to say (``BodyInfo.engines``), and a config is
checked against it where it is made (:class:`~neurowalk.sim.config.EpisodeConfig`). The engines: the CPU loop and
the planar surrogate's compiled chunks (:mod:`neurowalk.sim.cpu_loop`), and lock-step worlds
(:mod:`neurowalk.sim.lockstep`) with the physics plugged in: ``mujoco.batch`` (:mod:`neurowalk.sim.batch`) and
MuJoCo Warp (:mod:`neurowalk.sim.warp_engine`); every one runs the one loop (:mod:`neurowalk.sim.loop`).

Options travel as objects: :class:`EngineOptions` (device, threads, progress) and :class:`Streaming` (sink, part
size, checkpoints, resume).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Hashable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

from neurowalk.sim.checkpoint import Checkpoint
from neurowalk.sim.config import Episode, EpisodeConfig, RunInterruptedError
from neurowalk.sim.summarize import PICTURE_ROWS
from neurowalk.sim.trajectory import Trajectory

__all__ = ["Engine", "EngineOptions", "OneWorldPerCall", "Resume", "Streaming"]


@dataclass(frozen=True)
class EngineOptions:
    """How an engine runs, not what it runs (the configs say that).

    Attributes:
        device: MuJoCo Warp's device, ``cpu`` or ``cuda`` (None: ``cuda`` where a GPU is present, else ``cpu``).
        threads: physics threads of ``mujoco.batch``.
        progress: show a progress bar (rate, time left).
        pad_boxes: the CPU loop builds AMOSII's model with that many obstacle slots (the lock-step engines'
            model, bit for bit the plain model's physics); None: the plain model.
    """

    device: str | None = None
    threads: int = 2
    progress: bool = False
    pad_boxes: int | None = None

    def __post_init__(self) -> None:
        if self.device not in (None, "cpu", "cuda"):
            raise ValueError(f"unknown device {self.device!r}; expected cpu or cuda")
        if self.threads < 1:
            raise ValueError(f"threads must be >= 1, got {self.threads}")


@dataclass(frozen=True)
class Resume:
    """Where a stopped run goes on: its checkpoint (the step and the whole state), the rows before it.

    ``head``: the rows before ``step``, as one trajectory or as (start, rows) pieces in step order (e.g. a
    :class:`~neurowalk.sim.trajectory.PartWriter`'s parts, read one at a time).
    """

    checkpoint: Checkpoint
    head: Trajectory | Iterable[tuple[int, Trajectory]]


@dataclass(frozen=True)
class Streaming:
    """Where one run's rows go while it runs.

    Attributes:
        sink: if given, called as ``sink(rows, start)`` after every ``chunk`` steps and at the end, ``rows`` a
            :class:`Trajectory` of the steps ``start, start + 1, ...`` (valid during the call only). A sink with a
            ``qpos_rows(rows)`` method (as :class:`~neurowalk.sim.trajectory.PartWriter`) lets a streamed run replay
            the obstacle contacts of its wedged periods.
        chunk: rows per sink call (the part size).
        keep_rows: keep every row in memory as ``Episode.trajectory``. False (with a sink): memory is bounded by
            ``chunk`` and the summary's columns; ``Episode.trajectory`` holds every ``Episode.row_stride``-th row.
        checkpoint: resumable engines: called as ``checkpoint(ckpt)`` after each chunk's sink call, ``ckpt`` a
            :class:`~neurowalk.sim.checkpoint.Checkpoint` of the whole body and controller.
        resume: resumable engines: go on from such a checkpoint, bit for bit the run that was not stopped.
        picture_rows: with ``keep_rows=False``, the most rows ``Episode.trajectory`` keeps (for a picture).
        stop: if given, the one-world engines ask it as the run goes (the physics loop every 100 steps, the planar
            one every chunk): True stops the run there as a KeyboardInterrupt would. A command gives its
            ``stop_requested``: a stop signal came whose KeyboardInterrupt a library swallowed (one silently
            dropped amid numpy's imports let a 3,000,000-step run go on to its end).
    """

    sink: Callable[[Trajectory, int], Any] | None = None
    chunk: int = 10_000
    keep_rows: bool = True
    checkpoint: Callable[[Checkpoint], Any] | None = None
    resume: Resume | None = None
    picture_rows: int = PICTURE_ROWS
    stop: Callable[[], bool] | None = None

    def __post_init__(self) -> None:
        if self.chunk < 1:
            raise ValueError(f"chunk must be at least 1 row, got {self.chunk}")
        if not self.keep_rows and self.sink is None:
            raise ValueError("keep_rows=False needs a sink: the rows would be lost")


class Engine(ABC):
    """How configs become episodes. Subclasses set the class attributes and :meth:`run`."""

    name: ClassVar[str]
    """The engine's name (a config's ``engine`` for the physics engines)."""
    many_worlds: ClassVar[bool] = False
    """One call steps many configs together (else they run one after another)."""
    devices: ClassVar[tuple[str, ...]] = ()
    """The devices it runs on, by ``EngineOptions.device`` (none: the CPU, no choice)."""
    resumable: ClassVar[bool] = False
    """:meth:`run_one` goes on from a checkpoint (``Streaming.resume``) and writes them (``Streaming.checkpoint``)."""

    def check(self, configs: Sequence[EpisodeConfig], options: EngineOptions) -> None:
        """ValueError, one line, unless this engine can run ``configs`` together with ``options``."""
        if not configs:
            raise ValueError(f"engine {self.name!r} needs at least one config")

    def group_key(self, cfg: EpisodeConfig) -> Hashable:
        """Configs with equal keys may share one :meth:`run` call."""
        return (cfg.steps, cfg.control_hz) if self.many_worlds else id(cfg)

    def worlds_per_call(self, options: EngineOptions) -> int | None:
        """The most configs one :meth:`run` call should take with ``options`` (None: no limit)."""
        return None if self.many_worlds else 1

    def resolve(self, options: EngineOptions) -> EngineOptions:
        """``options`` with what this engine decides by itself filled in (e.g. the device); ValueError, one line, for
        options it cannot take. Called once, before any work."""
        if options.device is not None and options.device not in self.devices:
            raise ValueError(f"engine {self.name!r} has no device {options.device!r}")
        return options

    @abstractmethod
    def run(self, configs: Sequence[EpisodeConfig], options: EngineOptions) -> list[Episode]:
        """One :class:`Episode` per config, in order. Stopped part-way (KeyboardInterrupt), the episodes of the
        completed steps, each with ``summary["completed"]`` false."""

    def run_one(self, cfg: EpisodeConfig, options: EngineOptions, stream: Streaming) -> Episode:
        """One run, its rows handed to ``stream.sink`` (here: after the run; streaming engines: as it goes).

        Raises:
            RunInterruptedError: the run stopped part-way; it carries the episode of the completed steps.
        """
        if stream.resume is not None or stream.checkpoint is not None:
            raise ValueError(f"a run on engine {self.name!r} cannot be resumed (no checkpoints); run it again")
        self.check([cfg], options)
        ep = self.run([cfg], options)[0]
        done = len(ep.trajectory)
        if stream.sink is not None:
            for start in range(0, done, stream.chunk):
                stream.sink(ep.trajectory.rows(start, min(start + stream.chunk, done)), start)
        if done < cfg.steps:
            raise RunInterruptedError(ep)
        return ep


class OneWorldPerCall(Engine):
    """An engine that runs one world at a time: :meth:`run` is :meth:`run_one` of each config in turn."""

    def run(self, configs: Sequence[EpisodeConfig], options: EngineOptions) -> list[Episode]:
        """Each config's episode, one after another (a stopped run ends the list with its completed steps)."""
        self.check(configs, options)
        out = []
        for cfg in configs:
            try:
                out.append(self.run_one(cfg, options, Streaming()))
            except RunInterruptedError as stop:
                out.append(stop.episode)
                break
        return out

    @abstractmethod
    def run_one(self, cfg: EpisodeConfig, options: EngineOptions, stream: Streaming) -> Episode:
        """One run, its rows streamed to ``stream.sink`` as it goes."""
