"""A study's files: its numbers (NAME.json, NAME.npz) and its picture (NAME.png), each written whole or not at all
(atomic renames); read back to redraw the picture without rerunning."""

from __future__ import annotations

import json
import sys
import tokenize
import traceback
import warnings
import zipfile
import zlib
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

import numpy as np

from neurowalk import profiling
from neurowalk.experiments import Result
from neurowalk.fileio import atomic_write, write_json
from neurowalk.plotting.style import look
from neurowalk.runners.stopping import deferred

if TYPE_CHECKING:
    from matplotlib.figure import Figure


class Drawn(Protocol):
    """What is written here: a study's name and how it draws its result (a :class:`~neurowalk.experiments.Study`)."""

    name: str
    plot: Callable[[Result], Figure]


def write(study: Drawn, result: Result, out: Path, written: dict[str, Path] | None = None) -> dict[str, Path]:
    """Write ``result``'s numbers (NAME.json, NAME.npz), then its picture (NAME.png), into ``out``; the files, by kind.

    Each file is written whole or not at all, the numbers first (a plot error, or a stop while drawing, loses none
    of them); ``written`` (if given) holds the files written so far, for the line of a stop.
    """
    paths = written if written is not None else {}
    with deferred():
        paths.update(save_data(result, out))
    with profiling.part("drawing"), look():  # a user's study draws with the look of the figures too
        picture = study.plot(result)
        with deferred():
            paths["png"] = save_figure(result, picture, out)
    return paths


def save_data(result: Result, out_dir: str | Path) -> dict[str, Path]:
    """Write NAME.json (the summary, whether it is quick and the code's fingerprint) and NAME.npz (if there are
    arrays) into ``out_dir``: all a redraw needs."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = {"json": out / f"{result.name}.json"}
    if result.arrays:
        paths["npz"] = out / f"{result.name}.npz"
        atomic_write(paths["npz"], lambda tmp: np.savez_compressed(Path(tmp), **result.arrays))
    stamp = {k: v for k, v in (("quick", result.quick), ("code", result.code)) if v is not None}
    write_json(paths["json"], {**result.summary, **stamp})
    return paths


def save_figure(result: Result, fig: Figure, out_dir: str | Path) -> Path:
    """Write NAME.png into ``out_dir``."""
    path = Path(out_dir) / f"{result.name}.png"
    atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=120, format="png"))
    return path


class DataError(ValueError):
    """Saved figure numbers that cannot be read back (missing, damaged, truncated, foreign); names the file."""


def load(name: str, out_dir: str | Path) -> Result:
    """Read back a saved result (to redraw a figure without rerunning); only reads, never changes the files.

    Raises:
        DataError: NAME.json missing, not UTF-8 JSON or not an object; NAME.npz (where there is one) not an npz
            archive of plain arrays (nothing in it is unpickled).
    """
    out = Path(out_dir)
    path = out / f"{name}.json"
    try:
        summary = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError, RecursionError) as e:
        why = e.strerror if isinstance(e, OSError) else "nested too deeply" if isinstance(e, RecursionError) else e
        raise DataError(f"cannot read {path} as figure data ({_one_line(why)})") from None
    if not isinstance(summary, dict):
        raise DataError(f"{path} is not figure data (a JSON {type(summary).__name__}, not an object)")
    arrays: dict[str, np.ndarray] = {}
    npz = out / f"{name}.npz"
    if npz.exists():
        try:
            z = np.load(npz, allow_pickle=False)
            if not isinstance(z, np.lib.npyio.NpzFile):
                raise ValueError("a single array, not an npz archive")
            with z:
                arrays = {k: z[k] for k in z.files}
        except (
            OSError,
            ValueError,
            EOFError,
            SyntaxError,
            tokenize.TokenError,
            MemoryError,
            zipfile.BadZipFile,
            zlib.error,
        ) as e:  # a damaged array header is parsed as a Python literal: its errors too
            raise DataError(f"cannot read {npz} as figure data ({_one_line(e)})") from None
    code, quick = summary.pop("code", None), summary.get("quick")  # some figures' numbers hold quick themselves
    code = code if isinstance(code, str) else None
    return Result(name, summary, arrays, code, quick if isinstance(quick, bool) else None)


def _one_line(why: object) -> str:
    """``why`` as one short line."""
    text = " ".join(str(why).split())
    return text if len(text) <= 160 else text[:157] + "..."


def redraw(study: Drawn, out: Path) -> Path:
    """Redraw NAME.png from the numbers NAME.json (NAME.npz) in ``out``; the picture's path. :class:`DataError`
    naming the file where they cannot be read or are not this study's (damaged, truncated, foreign), which is left
    as it is."""
    name = study.name
    again = f"rerun `neurowalk figure {name}` without --replot to make them again"
    if not (out / f"{name}.json").is_file():
        raise DataError(f"--replot: no {name}.json in {str(out)!r}; run the figure without --replot first")
    try:
        result = load(name, out)
    except DataError as e:
        raise DataError(f"{e}; {again}") from None
    with warnings.catch_warnings(record=True) as caught:  # shown only where the picture is drawn
        try:
            picture = study.plot(result)
        except Exception as e:  # JSON of another shape: a key, a type or an array missing or odd
            if "matplotlib.pyplot" in sys.modules:
                sys.modules["matplotlib.pyplot"].close("all")
            npz = out / f"{name}.npz"
            files = f"{out / name}.json" + (f", {npz}" if npz.exists() else f" (no {npz.name} beside it)")
            raise DataError(f"{files}: not the numbers of figure {name} ({failure_words(e)}); {again}") from None
    for w in caught:
        warnings.showwarning(w.message, w.category, w.filename, w.lineno)
    with deferred():
        return save_figure(result, picture, out)


def failure_words(e: BaseException, most: int = 160) -> str:
    """An exception in one line, with where it was raised: ``KeyError: 'counts', at fig9.py:123 in plot`` (a bug
    shows its line; a file of another shape, the key it lacks)."""
    why = " ".join(f"{type(e).__name__}: {e}".split())[:most]
    frames = traceback.extract_tb(e.__traceback__)
    if not frames:
        return why
    return f"{why}, at {Path(frames[-1].filename).name}:{frames[-1].lineno} in {frames[-1].name}"
