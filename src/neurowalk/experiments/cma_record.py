"""CMA-ES searches kept as JSON and resumed by replay: nothing pickled, so an output folder cannot run code.

A search's file holds its settings and, per generation, the candidates CMA-ES drew and the scores it was told.
Resuming builds a fresh ``cma.CMAEvolutionStrategy`` with the same seed and replays the generations: each
``ask`` is checked to draw exactly the recorded candidates, then ``tell`` gets the recorded scores. CMA-ES is
deterministic given its seed, so the replayed search is the one that was stopped, bit for bit. Used by
``neurowalk optimize`` (:mod:`.optimize.search`) and the neuroevolution baseline (:mod:`.baselines.evolved_rnn`).
The ``cma`` package (extra ``optimize``, or ``rl``) is imported in one place, :func:`import_cma`.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from neurowalk.fileio import atomic_write

FORMAT = 1  # the format of a search record this code writes and reads


class CmaMissingError(ImportError):
    """The ``cma`` package (extra ``neurowalk[optimize]``) is not installed."""


def import_cma(missing: str) -> Any:
    """The ``cma`` module; CmaMissingError with the message ``missing`` (what needs it, how to install it) where it is
    not installed."""
    try:
        import cma
    except ImportError as e:
        raise CmaMissingError(missing) from e
    return cma


@contextmanager
def own_rng(holder: dict[str, Any]) -> Iterator[None]:
    """Run CMA-ES calls on the numpy global random state kept in ``holder['rng']``, leaving the caller's as it was.

    ``cma`` samples from ``numpy.random``; keeping its state here makes the search independent of anything else
    that draws from the global generator.
    """
    outer = np.random.get_state()
    if holder.get("rng") is not None:
        np.random.set_state(holder["rng"])
    try:
        yield
    finally:
        holder["rng"] = np.random.get_state()
        np.random.set_state(outer)


def start(
    cma: Any, holder: dict[str, Any], x0: np.ndarray, sigma0: float, seed: int, population: int, **options: Any
) -> None:
    """A fresh, quiet CMA-ES of ``population`` candidates at ``x0`` into ``holder['es']``, seeded ``seed + 1`` (cma
    reads 0 as the time), built on the holder's generator (:func:`own_rng`); its samples come from a RandomState of
    its own (option ``randn``), so that a replayed search draws what an uninterrupted one would. ``options``: more
    of cma's options (e.g. ``bounds``)."""
    with own_rng(holder):
        holder["es"] = cma.CMAEvolutionStrategy(
            x0,
            sigma0,
            {
                "seed": seed + 1,
                "randn": np.random.RandomState(seed + 1).randn,
                "popsize": population,
                **options,
                "verbose": -9,
                "verb_log": 0,
                "verb_disp": 0,
            },
        )


def read(path: Path, settings: dict[str, Any]) -> dict[str, Any] | None:
    """The record at ``path`` (None if there is none), checked to be of a search with these ``settings``.

    Raises:
        ValueError (one line naming the file): damaged, foreign or newer, or of a search with other settings.
    """
    if not path.is_file():
        return None
    bad = f"{str(path)!r} is not a readable neurowalk search record"
    try:
        saved = json.loads(path.read_bytes())
        fmt, old = saved["format"], saved["settings"]
    except (OSError, ValueError, KeyError, TypeError) as e:
        raise ValueError(f"{bad} ({type(e).__name__}); remove it to start the search afresh") from None
    if not isinstance(fmt, int) or fmt > FORMAT:
        raise ValueError(f"{str(path)!r} was written by a newer neurowalk (format {fmt!r}); update neurowalk")
    if fmt < FORMAT or not isinstance(old, dict):
        raise ValueError(f"{bad} (bad header); remove it to start the search afresh")
    for key, value in settings.items():
        if old.get(key) != json.loads(json.dumps(plain(value))):
            raise ValueError(
                f"{str(path.parent)!r} holds a search with other settings ({key}: {old.get(key)!r}, "
                f"asked {value!r}); use another output folder"
            )
    return saved


def write(path: Path, record: dict[str, Any]) -> None:
    """Write ``record`` (with its format) as JSON, atomically; floats exactly, non-finite ones kept."""
    text = json.dumps(plain({"format": FORMAT, **record}), indent=1)
    atomic_write(path, lambda tmp: Path(tmp).write_text(text + "\n"))


def resume(
    path: Path,
    settings: dict[str, Any],
    old: str,
    what: str,
    fresh: Callable[[], dict[str, Any]],
    generations: Callable[[dict[str, Any]], Iterable[tuple[Sequence[Any], Sequence[float]]]],
) -> tuple[dict[str, Any], dict[str, Any] | None]:
    """A fresh search (``fresh()``: a holder with its CMA-ES, see :func:`start`) into which the search recorded at
    ``path`` (if any) is replayed; returns it and the record (None where there is none).

    ``old``: the file name of an older neurowalk's pickled ``what`` (refused, never read: it could run code);
    ``generations``: the function (record -> [(candidates, scores)]) giving the record's generations, raising
    KeyError, TypeError or ValueError (its message, if any, goes into the error) where it cannot. Each recorded
    generation is checked to be what the fresh CMA-ES draws before it is told the recorded scores.

    Raises:
        ValueError naming the file: an older pickle, a damaged, foreign or newer record, one of other ``settings``,
        or one whose candidates this seed does not draw (an edited or foreign record).
    """
    if path.with_name(old).is_file():
        raise ValueError(
            f"{str(path.with_name(old))!r} is {what} of an older neurowalk (a pickle, which neurowalk no longer "
            "reads: it could run code); remove it and run again"
        )
    saved = read(path, settings)
    state = fresh()
    if saved is None:
        return state, None
    try:
        for xs, scores in generations(saved):
            drawn = ask(state)
            if not np.array_equal(np.array(drawn), np.array(xs, dtype=float)):
                raise ValueError("its candidates are not those this seed draws")
            tell(state, drawn, scores)
    except (KeyError, TypeError, ValueError, IndexError) as e:
        why = type(e).__name__ if isinstance(e, LookupError) or not str(e) else str(e)
        raise ValueError(
            f"{str(path)!r} is not a readable neurowalk search record ({why}); remove it to start afresh"
        ) from None
    return state, saved


def ask(holder: dict[str, Any]) -> list[np.ndarray]:
    """The next generation's candidates (float arrays), drawn on the holder's generator (:func:`own_rng`)."""
    with own_rng(holder):
        return [np.asarray(x, dtype=float) for x in holder["es"].ask()]


def tell(holder: dict[str, Any], xs: Sequence[np.ndarray], scores: Sequence[float]) -> dict[str, Any]:
    """Tell the holder's CMA-ES the ``scores`` (minimised) of its candidates ``xs``; its stop conditions (empty:
    go on)."""
    with own_rng(holder):
        holder["es"].tell(list(xs), [float(v) for v in scores])
        return dict(holder["es"].stop())


def plain(x: Any) -> Any:
    """``x`` with numpy scalars and arrays as plain Python (floats exactly, non-finite ones kept)."""
    if isinstance(x, dict):
        return {str(k): plain(v) for k, v in x.items()}
    if isinstance(x, list | tuple | np.ndarray):
        return [plain(v) for v in x]
    if isinstance(x, bool | np.bool_):
        return bool(x)
    if isinstance(x, int | np.integer):
        return int(x)
    if isinstance(x, float | np.floating):
        return float(x)
    return x
