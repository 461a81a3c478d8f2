"""Checkpoints of a running physics episode as arrays and JSON: nothing in them can run code.

A checkpoint is the whole mutable state of a run's body and controller after some control step: MuJoCo's
integration state (``mj_getState``), each Generator's ``bit_generator.state``, and every array and number the
networks and the sensor noise hold. It is found by walking the objects' attributes (:func:`capture`), so a new
piece of state in a network is checkpointed without a line here, and a kind of value that cannot be written as
arrays or JSON stops the walk with an error naming it. :func:`restore` walks a freshly built body and controller
of the same config the same way and puts the values back.

MuJoCo's derived quantities (positions of bodies, contacts, sensor readings) after ``mj_step`` are those of the
state *before* its last physics step, and the next observation reads them. A checkpoint therefore keeps the
integration state one physics step before the control step's end
(:meth:`~neurowalk.body.world.OneWorld.advance_keeping_previous`), and :func:`restore` sets that state and takes
the last physics step again, which gives every derived quantity bit for bit; the state after it is checked against
the one saved.

File: ``checkpoint.npz`` (``np.savez``, read with ``allow_pickle=False``): the arrays by path, plus ``__meta__``,
the JSON of the step, the format version and the scalar values.
"""

from __future__ import annotations

import dataclasses
import enum
import json
import types
import zipfile
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from neurowalk.fileio import atomic_write

FORMAT = 1  # the checkpoint format this code writes and reads
_STATE = mujoco.mjtState.mjSTATE_INTEGRATION
_SCALARS = (type(None), bool, int, float, str)


class CheckpointError(ValueError):
    """A checkpoint that cannot be used: damaged, foreign, of another format or of another run."""


@dataclass
class Checkpoint:
    """A run's state after ``step`` control steps: ``arrays`` (path -> array) and ``values`` (path -> JSON)."""

    step: int
    arrays: dict[str, np.ndarray]
    values: dict[str, Any]  # JSON values

    def save(self, path: str | Path) -> None:
        """Write ``checkpoint.npz`` atomically (no pickle)."""
        meta = {"format": FORMAT, "step": self.step, "values": self.values}
        blob = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
        arrays: dict[str, Any] = {"__meta__": blob, **self.arrays}  # (np.savez types its keywords)
        atomic_write(Path(path), lambda tmp: np.savez(tmp, **arrays))

    @classmethod
    def load(cls, path: str | Path) -> Checkpoint:
        """Read a checkpoint; :class:`CheckpointError` (naming the file) if it is damaged or foreign."""
        where = str(path)
        try:
            with np.load(path, allow_pickle=False) as z:
                arrays = {k: z[k] for k in z.files}
            meta = json.loads(bytes(arrays.pop("__meta__")).decode())
            fmt, step, values = meta["format"], meta["step"], meta["values"]
        except (OSError, ValueError, KeyError, TypeError, AttributeError, EOFError, zipfile.BadZipFile) as e:
            raise CheckpointError(f"{where!r} is not a readable neurowalk checkpoint ({_why(e)})") from None
        if not isinstance(fmt, int) or fmt > FORMAT:
            raise CheckpointError(f"{where!r} was written by a newer neurowalk (format {fmt!r}); update neurowalk")
        if fmt < FORMAT or not isinstance(step, int) or step < 0 or not isinstance(values, dict):
            raise CheckpointError(f"{where!r} is not a readable neurowalk checkpoint (bad header)")
        return cls(step, arrays, values)


def _why(e: BaseException) -> str:
    text = str(e).splitlines()[0] if str(e) else ""
    return f"{type(e).__name__}: {text}"[:120] if text else type(e).__name__


def capture(step: int, roots: dict[str, object], previous: np.ndarray | None) -> Checkpoint:
    """The state of ``roots`` (e.g. ``{"body": body, "controller": ctrl}``) after ``step`` control steps.

    ``previous``: the integration state before the body's last physics step
    (:meth:`~neurowalk.body.world.OneWorld.advance_keeping_previous`).
    """
    arrays: dict[str, np.ndarray] = {}
    values: dict[str, object] = {}
    for path, value, _set in _leaves(roots):
        if isinstance(value, np.ndarray):
            arrays[path] = value.copy()
        elif isinstance(value, np.generic):
            arrays[path] = np.asarray(value)
        elif isinstance(value, np.random.Generator):
            values[path] = {"generator": value.bit_generator.state}
        elif isinstance(value, _Mj):
            m, d = value.model, value.data
            if previous is None:
                raise ValueError(f"a checkpoint of {path} needs the integration state before its last physics step")
            now = np.empty(mujoco.mj_stateSize(m, _STATE))
            mujoco.mj_getState(m, d, now, _STATE)
            arrays[f"{path}#previous"], arrays[f"{path}#state"] = previous.copy(), now
            arrays[f"{path}#warnings"] = np.array([w.number for w in d.warning], dtype=np.int64)
        else:
            values[path] = list(value) if isinstance(value, tuple) else value
    return Checkpoint(step, arrays, values)


def restore(ckpt: Checkpoint, roots: dict[str, object]) -> None:
    """Put ``ckpt``'s state into ``roots``, freshly built (and reset) from the same config as the captured ones.

    Raises:
        CheckpointError: the checkpoint's contents do not fit these objects (another run's, or damaged).
    """
    seen: set[str] = set()
    for path, live, put in _leaves(roots):
        try:
            _restore_one(ckpt, path, live, put, seen)
        except (KeyError, ValueError, TypeError) as e:
            if isinstance(e, CheckpointError):
                raise
            raise CheckpointError(f"the checkpoint does not fit this run at {path!r} ({_why(e)})") from None
    extra = (set(ckpt.arrays) | set(ckpt.values)) - seen
    if extra:
        raise CheckpointError(f"the checkpoint holds state this run does not have: {sorted(extra)[0]!r}")


def _restore_one(ckpt: Checkpoint, path: str, live: Any, put: Callable[[object], None], seen: set[str]) -> None:
    if isinstance(live, np.ndarray):
        saved = ckpt.arrays[path]
        seen.add(path)
        if saved.shape == live.shape and saved.dtype == live.dtype and live.flags.writeable:
            live[...] = saved  # in place: arrays shared between objects stay shared
        elif saved.dtype == live.dtype and saved.ndim == live.ndim:
            put(saved.copy())
        else:
            raise ValueError(f"array {saved.dtype}{saved.shape}, expected {live.dtype} of {live.ndim} dimensions")
    elif isinstance(live, np.generic):
        saved = ckpt.arrays[path]
        seen.add(path)
        if saved.shape != () or saved.dtype != live.dtype:
            raise ValueError(f"scalar {saved.dtype}{saved.shape}, expected {live.dtype}")
        put(saved[()])
    elif isinstance(live, np.random.Generator):
        live.bit_generator.state = ckpt.values[path]["generator"]
        seen.add(path)
    elif isinstance(live, _Mj):
        _restore_mujoco(ckpt, path, live)
        seen.update(f"{path}#{k}" for k in ("previous", "state", "warnings"))
    else:
        value = ckpt.values[path]
        seen.add(path)
        if isinstance(live, tuple):
            value = tuple(value)
        if type(value) is not type(live) and not (isinstance(live, float) and type(value) is int):
            raise ValueError(f"{type(value).__name__}, expected {type(live).__name__}")
        put(type(live)(value) if live is not None else value)


def _restore_mujoco(ckpt: Checkpoint, path: str, mj: _Mj) -> None:
    """Set the state before the last physics step, take that step again, check it ends where the run did."""
    m, d = mj.model, mj.data
    prev, end = ckpt.arrays[f"{path}#previous"], ckpt.arrays[f"{path}#state"]
    warnings = ckpt.arrays[f"{path}#warnings"]
    size = mujoco.mj_stateSize(m, _STATE)
    if prev.shape != (size,) or end.shape != (size,) or warnings.shape != (len(d.warning),):
        raise ValueError(f"MuJoCo state of {prev.shape}, this model's is ({size},)")
    mujoco.mj_setState(m, d, prev, _STATE)
    mujoco.mj_step(m, d)
    now = np.empty(size)
    mujoco.mj_getState(m, d, now, _STATE)
    if not np.array_equal(now, end, equal_nan=True):
        raise CheckpointError("the checkpoint's physics state does not continue to its own end state (damaged)")
    for w, n in zip(d.warning, warnings, strict=True):
        w.number = int(n)


@dataclass(frozen=True)
class _Mj:
    """A MuJoCo model and its data, met as an object's ``model`` and ``data`` attributes."""

    model: mujoco.MjModel
    data: mujoco.MjData


def _skipped(value: object) -> bool:
    """Values that are not state: code, types, MuJoCo models, immutable configs (frozen dataclasses), enums."""
    if isinstance(value, types.FunctionType | types.BuiltinFunctionType | types.MethodType | type | types.ModuleType):
        return True
    if isinstance(value, mujoco.MjModel | enum.Enum) or type(value).__module__.startswith("numba"):
        return True
    params = getattr(type(value), "__dataclass_params__", None)
    return dataclasses.is_dataclass(value) and params is not None and params.frozen


def _leaves(roots: dict[str, object]) -> Iterator[tuple[str, object, Callable[[object], None]]]:
    """(path, value, setter) of every piece of state under ``roots``, in a fixed order."""
    seen: set[int] = set()
    yield from _walk(roots, "", seen)


def _walk(obj: object, path: str, seen: set[int]) -> Iterator[tuple[str, object, Callable[[object], None]]]:
    if id(obj) in seen:
        return
    seen.add(id(obj))
    if isinstance(obj, dict):
        items = list(obj.items())
        if not all(isinstance(k, str) for k, _ in items):
            raise TypeError(f"cannot checkpoint {path or 'the state'}: a dict with keys that are not text")
        yield from _children(items, path, lambda k, v: obj.__setitem__(k, v), seen)
    elif isinstance(obj, list):
        yield from _children(list(enumerate(obj)), path, obj.__setitem__, seen)
    elif isinstance(obj, tuple):
        yield from _children(list(enumerate(obj)), path, None, seen)
    else:
        state = vars(obj) if hasattr(obj, "__dict__") else {s: getattr(obj, s) for s in _slots(obj)}
        mj = state.get("data") if isinstance(state.get("model"), mujoco.MjModel) else None
        items = [(k, _Mj(state["model"], v) if v is mj and mj is not None else v) for k, v in state.items()]
        yield from _children(items, path, lambda k, v: setattr(obj, str(k), v), seen)


def _children(
    items: list[tuple[object, object]], path: str, setter: Callable[[Any, Any], None] | None, seen: set[int]
) -> Iterator[tuple[str, object, Callable[[object], None]]]:
    for key, value in items:
        where = f"{path}/{key}" if path else str(key)
        if not isinstance(value, _Mj) and _skipped(value):
            continue
        leaf = isinstance(value, (np.ndarray, np.generic, np.random.Generator, _Mj, *_SCALARS)) or (
            isinstance(value, tuple) and all(isinstance(v, _SCALARS) for v in value)
        )
        if isinstance(value, np.ndarray) and value.dtype.hasobject:
            raise TypeError(f"cannot checkpoint {where}: an array of Python objects")
        if isinstance(value, mujoco.MjData):
            raise TypeError(f"cannot checkpoint {where}: MuJoCo data without its model beside it")
        if leaf:

            def put(v: object, k: object = key, where: str = where) -> None:
                if setter is None:
                    raise TypeError(f"{where} sits in a tuple and cannot be replaced")
                setter(k, v)

            yield where, value, put
        elif isinstance(value, dict | list | tuple) or hasattr(value, "__dict__") or _slots(value):
            yield from _walk(value, where, seen)
        else:
            raise TypeError(f"cannot checkpoint {where}: a {type(value).__name__}")


def _slots(obj: object) -> list[str]:
    return [s for c in type(obj).__mro__ for s in getattr(c, "__slots__", ()) if hasattr(obj, s)]
