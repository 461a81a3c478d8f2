"""Lock-step worlds: many AMOSII runs stepped together through the one loop, the physics plugged in.

:class:`LockstepWorlds` is AMOSII's many worlds (:class:`~neurowalk.body.amosii_worlds.AmosIIWorlds`: the sensing
and sensor noise) with each run's config and controller, run by the one loop (:func:`~neurowalk.sim.loop.run_worlds`:
the controllers in one compiled call, the recording, the ``until`` rule); a subclass plugs in the physics
(``mujoco.batch`` threads, :mod:`neurowalk.sim.batch`; MuJoCo Warp, :mod:`neurowalk.sim.warp_engine`).
:class:`LockstepEngine` is the engine interface over such worlds: configs of one group (same steps and control rate)
share one call.
"""

from __future__ import annotations

from collections.abc import Hashable, Mapping, Sequence

import mujoco

from neurowalk.arenas import ArenaSpec
from neurowalk.body.amosii_params import BodyParams
from neurowalk.body.amosii_worlds import AmosIIWorlds
from neurowalk.body.registry import BODIES
from neurowalk.sim.batch_control import BatchControllers
from neurowalk.sim.config import Episode, EpisodeConfig, build_controller
from neurowalk.sim.engine_interface import Engine, EngineOptions
from neurowalk.sim.loop import TIMING, run_worlds

__all__ = ["LockstepEngine", "LockstepWorlds"]

#: The bodies lock-step worlds run: one model structure for every arena (obstacle slots; body/obstacle_slots.py).
LOCKSTEP_BODIES = tuple(name for name, info in BODIES.items() if info.lockstep)


class LockstepWorlds(AmosIIWorlds):
    """n runs of AMOSII (one per config) stepped together through the one loop; the physics is a subclass's.

    Args:
        configs: the runs (one group: same ``steps`` and ``control_hz``).
        arenas: each run's arena.
        model: the CPU ``MjModel`` of world 0 (sizes, names, sensor addresses; every world has its structure).
        params: the body's numbers. n_substeps: physics steps per control step.
        compiled: step the controllers in one compiled call (else each controller's ``act``).

    Each run's controller is its config's (:func:`~neurowalk.sim.config.build_controller`) and its sensor noise
    AMOSII's own source (its config's ``noise`` strength).

    Attributes:
        timing: seconds in each part of the loop's steps (:data:`~neurowalk.sim.loop.TIMING`), over every run.
    """

    def __init__(
        self,
        configs: Sequence[EpisodeConfig],
        arenas: Sequence[ArenaSpec],
        model: mujoco.MjModel,
        params: BodyParams,
        n_substeps: int,
        compiled: bool,
    ) -> None:
        self.configs = list(configs)
        super().__init__(arenas, [c.noise for c in self.configs], model, params, n_substeps)
        self.controllers = BatchControllers([build_controller(c) for c in self.configs], compiled=compiled)
        self.timing = dict.fromkeys(TIMING, 0.0)

    def label(self) -> str:
        """What the progress bar calls this run."""
        return f"batch of {self.n}"

    def run(self, *, progress: bool = False) -> list[Episode]:
        """Reset, run every world for its config's steps, and return one :class:`Episode` per config.

        Each episode's ``wall_time_s`` is the whole run's wall time divided by the number of runs. Stopped part-way
        (KeyboardInterrupt, e.g. Ctrl-C or SIGTERM in the CLI) it returns the episodes of the completed steps, each
        with ``summary["completed"]`` false (none completed: the interrupt is raised).
        """
        run = run_worlds(self.configs, self.arenas, self, self.controllers, progress=progress, label=self.label(),
                         timing=self.timing)  # fmt: skip
        if run.interrupted and not run.done:
            raise KeyboardInterrupt
        return run.episodes


class LockstepEngine(Engine):
    """Engines over lock-step worlds: many worlds per call; configs of one group (steps, control rate) share it."""

    many_worlds = True

    def check(self, configs: Sequence[EpisodeConfig], options: EngineOptions) -> None:
        """ValueError unless every config runs a lock-step body and all share this engine's group key."""
        super().check(configs, options)
        bad = [c for c in configs if c.body not in LOCKSTEP_BODIES]
        if bad:
            runs = ", ".join(repr(b) for b in LOCKSTEP_BODIES)
            raise ValueError(f"engine {self.name!r} runs body {runs} only, got body {bad[0].body!r}")
        for name in ("control_hz", "steps", "body_opts"):
            values = sorted({repr(_hashable(getattr(c, name))) for c in configs})
            if len(values) > 1:
                raise ValueError(
                    f"every config of one call of engine {self.name!r} needs the same {name}, got {', '.join(values)}"
                )

    def group_key(self, cfg: EpisodeConfig) -> Hashable:
        """Configs of the same length, control rate and body options run as one call's worlds."""
        return (cfg.steps, cfg.control_hz, _hashable(cfg.body_opts))


def _hashable(v: object) -> object:
    """``v`` with its mappings as sorted tuples of items (a group key's part)."""
    return tuple(sorted(v.items())) if isinstance(v, Mapping) else v
