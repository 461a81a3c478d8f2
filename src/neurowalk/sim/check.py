"""``check_engine``: the engine contract tested, as Gymnasium's ``check_env`` tests an environment's.

.. code-block:: python

    from neurowalk.sim.check import check_engine
    from neurowalk.sim.engines import ENGINES

    check_engine(ENGINES["mujoco.batch"])       # EngineContractError: one line naming what is wrong

Two short runs of a body the engine runs (the box arena, two seeds) through :meth:`~neurowalk.sim.engine_interface.
Engine.run`: one episode per config, in order, of the config's steps, one row a control step, summaries complete;
the same configs again give the same rows, bit for bit; :meth:`~neurowalk.sim.engine_interface.Engine.run_one`
streams the same rows to a sink; a resumable engine goes on from its checkpoint to the same run.
"""

from __future__ import annotations

import numpy as np

from neurowalk.body.registry import BODIES
from neurowalk.sim.checkpoint import Checkpoint
from neurowalk.sim.config import DEFAULT_ENGINE, EpisodeConfig
from neurowalk.sim.engine_interface import Engine, EngineOptions, Resume, Streaming
from neurowalk.sim.trajectory import Trajectory

__all__ = ["EngineContractError", "check_engine"]


class EngineContractError(ValueError):
    """An engine breaks the contract the runners rely on; the message is one line naming what."""


def check_engine(
    engine: Engine, *, options: EngineOptions | None = None, steps: int = 12, controller: str = "plastic"
) -> None:
    """Test ``engine`` against the engine contract with ``steps``-step runs of ``controller`` (a user's
    ``FILE.py:NAME`` too) (``options``: its device, threads); raise :class:`EngineContractError` (one line naming the
    engine and what is wrong) where it breaks it."""
    try:
        _check(engine, engine.resolve(options or EngineOptions()), steps, controller)
    except EngineContractError as e:
        raise EngineContractError(f"engine {engine.name!r}: {e}") from None


def _check(engine: Engine, options: EngineOptions, steps: int, controller: str) -> None:
    body = next((name for name, info in BODIES.items() if engine.name in info.engines), None)
    planar = body is None
    body = body or next(name for name, info in BODIES.items() if not info.physics)
    kind = DEFAULT_ENGINE if planar else engine.name
    configs = [EpisodeConfig(arena="box", steps=steps, seed=s, body=body, engine=kind, controller=controller)
               for s in (1, 2)]  # fmt: skip
    engine.check(configs, options)
    if engine.many_worlds and engine.group_key(configs[0]) != engine.group_key(configs[1]):
        raise EngineContractError("two runs of one length and rate must share a call (group_key)")
    first = engine.run(configs, options)
    if len(first) != len(configs):
        raise EngineContractError(f"run() gave {len(first)} episodes for {len(configs)} configs")
    for i, (ep, cfg) in enumerate(zip(first, configs, strict=True)):
        if ep.config != cfg:
            raise EngineContractError(f"episode {i} is not config {i}'s: run() must keep the configs' order")
        tr = ep.trajectory
        if len(tr) != steps or ep.summary.get("steps") != steps or ep.summary.get("completed") is not True:
            raise EngineContractError(f"episode {i} has {len(tr)} rows of {steps} steps, or a summary not complete")
        if not np.allclose(np.diff(tr.t), 1.0 / cfg.control_hz):
            raise EngineContractError(f"episode {i}'s rows are not one a control step (t, {1 / cfg.control_hz} s)")
    again = engine.run(configs, options)
    for i, (a, b) in enumerate(zip(first, again, strict=True)):
        if (name := _differ(a.trajectory, b.trajectory)) is not None:
            raise EngineContractError(f"the same config gave another {name} (run {i}): not deterministic")
    pieces: list[tuple[int, Trajectory]] = []
    checkpoints: dict[int, Checkpoint] = {}
    chunk = max(1, steps // 3)
    stream = Streaming(sink=lambda rows, start: pieces.append((start, _copy(rows))), chunk=chunk)
    if engine.resumable:
        stream = Streaming(sink=stream.sink, chunk=chunk, checkpoint=lambda c: checkpoints.setdefault(c.step, c))
    one = engine.run_one(configs[0], options, stream)
    cols = [p.arrays() for _, p in pieces]
    streamed = Trajectory.from_arrays({k: np.concatenate([c[k] for c in cols]) for k in cols[0]})
    if [s for s, _ in pieces] != list(range(0, steps, chunk)) or _differ(streamed, first[0].trajectory) is not None:
        raise EngineContractError("run_one() must stream run()'s rows to its sink, a chunk at a time, in order")
    if _differ(one.trajectory, first[0].trajectory) is not None:
        raise EngineContractError("run_one() must give run()'s episode")
    if engine.resumable:
        if not checkpoints:
            raise EngineContractError("a resumable engine must write a checkpoint after each chunk")
        step = min(checkpoints)
        head = [(s, p) for s, p in pieces if s < step]
        resumed = engine.run_one(configs[0], options, Streaming(chunk=chunk, resume=Resume(checkpoints[step], head)))
        if (name := _differ(resumed.trajectory, first[0].trajectory)) is not None:
            raise EngineContractError(f"a run resumed from step {step} gave another {name} than the whole run")


def _differ(a: Trajectory, b: Trajectory) -> str | None:
    """The first of a run's columns in which ``a`` and ``b`` differ (NaN equal to NaN), or None."""
    if a.arrays().keys() != b.arrays().keys():
        return "columns"
    for name, col in a.arrays().items():
        if not np.array_equal(col, b.arrays()[name], equal_nan=True):
            return name
    return None


def _copy(rows: Trajectory) -> Trajectory:
    return rows.map(np.array)
