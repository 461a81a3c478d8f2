"""What an episode records, one row per control step, and its file format (``trajectory.npz``)."""

from __future__ import annotations

import shutil
import zipfile
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
from numpy.lib import format as npformat

from neurowalk import anatomy
from neurowalk.fileio import atomic_write
from neurowalk.sim.checkpoint import Checkpoint, CheckpointError

CHECKPOINT = "checkpoint.npz"  # a streamed physics run's last checkpoint, in its parts folder
STATE = "state."  # the prefix of a controller's declared state's columns in trajectory.npz


@dataclass
class Trajectory:
    """Per-step records (row k = after control step k).

    Attributes:
        t: (T,) time in s. pose: (T, 3) x m, y m, yaw rad. inputs: (T, 2) network inputs (I1, I2).
        outputs: (T, 2) steering (O1, O2). b, q: (T, 2) sensory weights (NaN for a fixed controller).
        targets: (T, 19) commanded joint angles, rad, actuator order. joint_angles: (T, 19) measured
        (noise-free) joint angles. us_distance: (T, 2) ultrasonic readings as the controller saw
        them (m, inf = no echo). foot_contact: (T, 6). up_z: (T,) trunk up-vector z. qpos: (T, nq)
        full physics state positions (for replay and video). state: the controller's declared state
        (``Controller.recorded``), by name, each (T, ...); in ``trajectory.npz`` as ``state.NAME``.
    """

    t: np.ndarray
    pose: np.ndarray
    inputs: np.ndarray
    outputs: np.ndarray
    b: np.ndarray
    q: np.ndarray
    targets: np.ndarray
    joint_angles: np.ndarray
    us_distance: np.ndarray
    foot_contact: np.ndarray
    up_z: np.ndarray
    qpos: np.ndarray
    state: dict[str, np.ndarray] = field(default_factory=dict)

    @classmethod
    def empty(cls, steps: int, nq: int, state: Mapping[str, tuple[int, ...]] | None = None) -> Trajectory:
        """Preallocated arrays for ``steps`` rows (``state``: the controller's declared state's row shapes)."""
        shapes = {**cls.shapes(nq), **{STATE + k: s for k, s in (state or {}).items()}}
        return cls.from_arrays({k: np.full((steps, *s), np.nan) for k, s in shapes.items()})

    def arrays(self) -> dict[str, np.ndarray]:
        """Every column by its name in ``trajectory.npz`` (the controller's state as ``state.NAME``)."""
        out = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "state"}
        out.update({STATE + k: v for k, v in self.state.items()})
        return out

    @classmethod
    def from_arrays(cls, arrays: Mapping[str, np.ndarray]) -> Trajectory:
        """The trajectory of columns named as :meth:`arrays` names them."""
        state = {k[len(STATE) :]: v for k, v in arrays.items() if k.startswith(STATE)}
        return cls(**{k: v for k, v in arrays.items() if not k.startswith(STATE)}, state=state)

    def map(self, fn: Callable[[np.ndarray], np.ndarray]) -> Trajectory:
        """The trajectory of ``fn`` of each column (e.g. ``tr.map(np.copy)``, rows picked by ``lambda v: v[rows]``)."""
        return Trajectory.from_arrays({k: fn(v) for k, v in self.arrays().items()})

    @staticmethod
    def shapes(nq: int) -> dict[str, tuple[int, ...]]:
        """Each column's shape of one row (``nq``: the model's qpos size)."""
        n = anatomy.N_ACTUATORS
        return {
            "t": (),
            "pose": (3,),
            "inputs": (2,),
            "outputs": (2,),
            "b": (2,),
            "q": (2,),
            "targets": (n,),
            "joint_angles": (n,),
            "us_distance": (2,),
            "foot_contact": (6,),
            "up_z": (),
            "qpos": (nq,),
        }

    #: The columns a control loop writes (``t`` last: a row with a time is complete); the others (pose, joint
    #: angles, up_z) are derived from qpos (:func:`~neurowalk.sim.recorder.derive_columns`).
    RECORDED: ClassVar[tuple[str, ...]] = (
        "inputs", "outputs", "b", "q", "targets", "us_distance", "foot_contact", "qpos", "t"
    )  # fmt: skip

    def __len__(self) -> int:
        return len(self.t)

    def head(self, n: int) -> Trajectory:
        """The first ``n`` rows (views)."""
        return self.rows(0, n)

    def rows(self, start: int, stop: int) -> Trajectory:
        """Rows [start, stop) (views)."""
        return self.map(lambda v: v[start:stop])

    def save(self, path: str | Path) -> None:
        """Write ``trajectory.npz`` (compressed) atomically."""
        arrays: dict[str, Any] = self.arrays()  # (numpy's stub reads a name as its allow_pickle)
        atomic_write(Path(path), lambda tmp: np.savez_compressed(Path(tmp), **arrays))

    @classmethod
    def load(cls, path: str | Path) -> Trajectory:
        """Read a ``trajectory.npz``."""
        with np.load(path, allow_pickle=False) as z:
            names = [f.name for f in fields(cls) if f.name != "state"]
            return cls.from_arrays({k: z[k] for k in [*names, *(k for k in z.files if k.startswith(STATE))]})


class PartWriter:
    """Writes a running episode's rows to numbered part files, so a killed run keeps what it did.

    Called as ``writer(rows, start)`` (the sink of :func:`~neurowalk.sim.episode.run_episode`), it saves the
    rows of steps ``start, start + 1, ...`` as ``part-<start>.npz`` in ``folder``. :meth:`read` concatenates
    the parts back into one :class:`Trajectory`; :meth:`join` writes them into one ``trajectory.npz`` a part
    at a time, so that memory stays bounded by the part size.
    """

    def __init__(self, folder: str | Path) -> None:
        self.folder = Path(folder)

    def __call__(self, rows: Trajectory, start: int) -> None:
        """Save ``rows``, the steps from ``start`` on."""
        self.folder.mkdir(parents=True, exist_ok=True)
        rows.save(self.folder / f"part-{start:010d}.npz")

    write = __call__

    def paths(self) -> list[Path]:
        """The part files, in step order."""
        return sorted(self.folder.glob("part-*.npz"))

    def pieces(self) -> Iterator[tuple[int, Trajectory]]:
        """(start step, rows) of each part, in step order, one part in memory at a time."""
        for path in self.paths():
            yield int(path.stem.split("-")[1]), Trajectory.load(path)

    def count(self) -> int:
        """Rows in the parts."""
        n = 0
        for p in self.paths():
            with np.load(p, allow_pickle=False) as z:
                n += int(z["t"].shape[0])
        return n

    def count_before(self, step: int) -> int:
        """Rows the parts hold before ``step``, counted from step 0 without a gap (a resume needs them all)."""
        n = 0
        for p in self.paths():
            start = int(p.stem.split("-")[1])
            if start != n or start >= step:
                break
            with np.load(p, allow_pickle=False) as z:
                n += int(z["t"].shape[0])
        return min(n, step)

    def drop_from(self, step: int) -> None:
        """Delete the parts that start at or after ``step`` (a resumed run writes them again)."""
        for p in self.paths():
            if int(p.stem.split("-")[1]) >= step:
                p.unlink()

    def read(self) -> Trajectory:
        """All parts, in order, as one trajectory."""
        parts = [rows for _, rows in self.pieces()]
        if not parts:
            raise ValueError(f"no trajectory parts in {str(self.folder)!r}")
        cols = [p.arrays() for p in parts]
        return Trajectory.from_arrays({k: np.concatenate([c[k] for c in cols]) for k in cols[0]})

    def qpos_rows(self, rows: np.ndarray) -> np.ndarray:
        """The recorded positions of the given steps, (len(rows), nq), read from the parts that hold them only."""
        rows = np.asarray(rows, dtype=int)
        paths = self.paths()
        if not paths:
            raise ValueError(f"no trajectory parts in {str(self.folder)!r}")
        starts = [int(p.stem.split("-")[1]) for p in paths]
        out: np.ndarray | None = None
        for j, (path, start) in enumerate(zip(paths, starts, strict=True)):
            end = starts[j + 1] if j + 1 < len(starts) else None
            pick = (rows >= start) & (rows < end if end is not None else True)
            if not pick.any():
                continue
            with np.load(path, allow_pickle=False) as z:
                qpos = z["qpos"]
            if out is None:
                out = np.full((len(rows), qpos.shape[1]), np.nan)
            out[pick] = qpos[rows[pick] - start]
        return out if out is not None else np.full((len(rows), 0), np.nan)

    def join(self, path: str | Path, steps: int | None = None) -> int:
        """Write the parts (the first ``steps`` rows; default all) as one ``trajectory.npz`` at ``path``.

        The file is the one :meth:`Trajectory.save` writes of :meth:`read` (same arrays, compressed), built one
        column and one part at a time; written atomically. Returns the number of rows.
        """
        paths = self.paths()
        if not paths:
            raise ValueError(f"no trajectory parts in {str(self.folder)!r}")
        total = self.count() if steps is None else min(steps, self.count())

        def write(tmp: str) -> None:
            with np.load(paths[0], allow_pickle=False) as z:
                names = list(z.files)  # the columns of the parts (each part has the same)
            with zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED, allowZip64=True) as zf:
                for name in names:
                    with np.load(paths[0], allow_pickle=False) as z:
                        first = z[name]
                    header = {
                        "descr": npformat.dtype_to_descr(first.dtype),
                        "fortran_order": False,
                        "shape": (total, *first.shape[1:]),
                    }
                    with zf.open(f"{name}.npy", "w", force_zip64=True) as out:
                        npformat.write_array_header_2_0(out, header)
                        left = total
                        for p in paths:
                            if left <= 0:
                                break
                            with np.load(p, allow_pickle=False) as z:
                                col = np.ascontiguousarray(z[name][:left])
                            out.write(col.tobytes())
                            left -= len(col)

        atomic_write(Path(path), write)
        return total

    def remove(self) -> None:
        """Delete the folder: the parts, what a resume needs, and temp files a killed run left (once saved)."""
        if self.folder.is_dir():
            shutil.rmtree(self.folder)

    def write_checkpoint(self, ckpt: Checkpoint) -> None:
        """Keep the whole state after ``ckpt.step`` steps (atomically; the parts before it are written already)."""
        ckpt.save(self.folder / CHECKPOINT)

    def read_checkpoint(self) -> Checkpoint | None:
        """The last checkpoint, or None if there is none.

        Raises:
            CheckpointError: it is damaged or foreign, or of the older pickle format (which is never read).
        """
        if (self.folder / "checkpoint.pkl").is_file():
            raise CheckpointError(
                f"{str(self.folder / 'checkpoint.pkl')!r} is a checkpoint of an older neurowalk (a pickle, which "
                "neurowalk no longer reads: it could run code); run again with --overwrite"
            )
        path = self.folder / CHECKPOINT
        return Checkpoint.load(path) if path.is_file() else None


def poses_from_qpos(qpos: np.ndarray) -> np.ndarray:
    """(T, 3) planar poses (x m, y m, yaw rad) from free-joint positions ``qpos`` (T, >= 7; quaternion w x y z)."""
    w, x, y, z = qpos[:, 3], qpos[:, 4], qpos[:, 5], qpos[:, 6]
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return np.column_stack([qpos[:, 0], qpos[:, 1], yaw])


def up_z_from_qpos(qpos: np.ndarray) -> np.ndarray:
    """(T,) z component of the trunk's up axis (1 upright, 0 on its side) from ``qpos`` (T, >= 7)."""
    x, y = qpos[:, 4], qpos[:, 5]
    return 1 - 2 * (x * x + y * y)
