"""Writing figure outputs: PNG, JSON and NPZ, all or nothing (atomic renames)."""

from __future__ import annotations

import json
import math
import os
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from neurowalk.experiments import Result

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def to_jsonable(x: Any) -> Any:
    """Convert numpy scalars/arrays to plain Python; non-finite floats become None."""
    if isinstance(x, dict):
        return {str(k): to_jsonable(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [to_jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return to_jsonable(x.tolist())
    if isinstance(x, np.bool_ | bool):
        return bool(x)
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, float | np.floating):
        return float(x) if math.isfinite(x) else None
    return x


def _atomic_write(path: Path, write: Any) -> None:
    """Write via ``write(tmp_path)`` into a temp file beside ``path``, then rename over it."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=path.suffix)
    os.close(fd)
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def write_json(path: Path, data: Any) -> None:
    """Write ``data`` as indented JSON, atomically."""

    def w(tmp: str) -> None:
        with open(tmp, "w") as f:
            json.dump(to_jsonable(data), f, indent=2)
            f.write("\n")

    _atomic_write(Path(path), w)


def save(result: Result, fig: Figure, out_dir: str | Path) -> dict[str, Path]:
    """Write NAME.png, NAME.json and NAME.npz (if there are arrays) into ``out_dir``."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = {"png": out / f"{result.name}.png", "json": out / f"{result.name}.json"}
    if result.arrays:
        paths["npz"] = out / f"{result.name}.npz"
        _atomic_write(paths["npz"], lambda tmp: np.savez_compressed(Path(tmp), **result.arrays))
    write_json(paths["json"], result.summary)
    _atomic_write(paths["png"], lambda tmp: fig.savefig(tmp, dpi=120, format="png"))
    return paths


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
