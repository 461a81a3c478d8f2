"""Writing figure outputs: PNG, JSON and NPZ, all or nothing (atomic renames)."""

from __future__ import annotations

import json
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


def save(result: Result, fig: Figure, out_dir: str | Path) -> dict[str, Path]:
    """Write NAME.png, NAME.json and NAME.npz (if there are arrays) into ``out_dir``."""
    return {"png": save_figure(result, fig, out_dir), **save_data(result, out_dir)}


def load(name: str, out_dir: str | Path) -> Result:
    """Read back a saved result (to redraw a figure without rerunning)."""
    out = Path(out_dir)
    with open(out / f"{name}.json") as f:
        summary = json.load(f)
    arrays: dict[str, np.ndarray] = {}
    npz = out / f"{name}.npz"
    if npz.exists():
        with np.load(npz) as z:
            arrays = {k: z[k] for k in z.files}
    return Result(name=name, summary=summary, arrays=arrays)
