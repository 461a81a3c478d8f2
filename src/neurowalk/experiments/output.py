"""Writing figure outputs: PNG, JSON and NPZ, all or nothing (atomic renames)."""

from __future__ import annotations

import json
import tokenize
import zipfile
import zlib
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from neurowalk.experiments import Result
from neurowalk.fileio import atomic_write, write_json

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def save_data(result: Result, out_dir: str | Path) -> dict[str, Path]:
    """Write NAME.json and NAME.npz (if there are arrays) into ``out_dir``: all a redraw needs."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = {"json": out / f"{result.name}.json"}
    if result.arrays:
        paths["npz"] = out / f"{result.name}.npz"
        atomic_write(paths["npz"], lambda tmp: np.savez_compressed(Path(tmp), **result.arrays))
    write_json(paths["json"], result.summary)
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
    return Result(name=name, summary=summary, arrays=arrays)


def _one_line(why: object) -> str:
    """``why`` as one short line."""
    text = " ".join(str(why).split())
    return text if len(text) <= 160 else text[:157] + "..."
