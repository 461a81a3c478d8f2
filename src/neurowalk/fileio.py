"""Files: written all or nothing (a temp file beside the target, then an atomic rename), and a user's Python file
read as a module (:func:`load_python_file`: a study, a controller)."""

from __future__ import annotations

import errno
import fcntl
import hashlib
import importlib.util
import json
import math
import os
import sys
import tempfile
import traceback
from pathlib import Path
from types import ModuleType
from typing import IO, Any

import numpy as np


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


def atomic_write(path: Path, write: Any) -> None:
    """Write via ``write(tmp_path)`` into a temp file beside ``path``, then rename over it."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=path.suffix)
    os.close(fd)
    try:
        write(tmp)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600; give the file the usual permissions
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

    atomic_write(Path(path), w)


def make_writable_folder(path: Path) -> None:
    """Make the folder ``path`` (and its parents) and check that a file can be written in it.

    The check is a real write, not ``os.access`` (which lets root "write" where nothing can be, e.g. /proc).
    Raises ValueError saying what is wrong (a file in the way, no permission, a name too long, ...).
    """
    try:
        if path.exists() and not path.is_dir():
            raise ValueError(f"{str(path)!r} is a file, not a folder")
        path.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise ValueError(f"cannot make the folder {str(path)!r} ({e.strerror})") from None
    try:
        with tempfile.TemporaryFile(dir=path):
            pass
    except OSError as e:
        raise ValueError(f"the folder {str(path)!r} is not writable ({e.strerror})") from None


class FolderBusyError(ValueError):
    """Another neurowalk process holds the output folder's lock."""


def exclusive_lock(path: Path) -> IO[bytes] | None:
    """Open ``path`` and hold it exclusively (the operating system's ``flock``: it goes with the process, so a killed
    one leaves none behind); the open file (close it to release), or None if another process holds it.

    Raises OSError where the file cannot be opened."""
    f = open(path, "ab")  # noqa: SIM115 (held open until the caller closes it)
    try:
        fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        f.close()
        return None
    return f


class FolderLock:
    """An output folder held exclusively (``flock`` on the folder itself: no file is left in it, and a killed
    process's lock goes with it); :meth:`close` (or the end of a ``with`` block) releases it."""

    def __init__(self, fd: int) -> None:
        self.fd = fd

    def close(self) -> None:
        """Release the folder (once; again does nothing)."""
        if self.fd >= 0:
            os.close(self.fd)
            self.fd = -1

    def __enter__(self) -> FolderLock:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def folder_lock(folder: Path, what: str = "run") -> FolderLock:
    """Hold the folder ``folder`` exclusively; FolderBusyError if another process (or another holder in this one)
    holds it. Raises OSError where the folder cannot be opened."""
    fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        raise FolderBusyError(
            f"{str(folder)!r} is in use by another neurowalk {what}; wait for it to finish or use another output folder"
        ) from None
    return FolderLock(fd)


_WRITE_ERRORS = {
    errno.ENOSPC: "disk full",
    errno.EDQUOT: "disk quota exceeded",
    errno.EROFS: "read-only file system",
    errno.EACCES: "permission denied",
    errno.EPERM: "permission denied",
    errno.ENOENT: "folder removed",
    errno.EIO: "input/output error",
}


def write_error(e: OSError) -> str:
    """What went wrong writing, in a few words with the file: e.g. ``disk full writing 'out/run/part-1.npz'``."""
    what = _WRITE_ERRORS.get(e.errno or 0, (e.strerror or str(e)).lower())
    name = e.filename if e.filename is not None else None
    return f"{what} writing {str(name)!r}" if name else what


def stale_temp_files(folder: Path) -> list[Path]:
    """Temp files that :func:`atomic_write` leaves only when its process is killed (``.NAME.XXXX.SUFFIX``)."""
    names = ("summary.json", "trajectory.npz", "run.png", "video.mp4")
    return [p for n in names for p in Path(folder).glob(f".{n}.*") if p.is_file()]


def user_ref(name: str) -> tuple[Path, str] | None:
    """The (file, name in it) of a reference to a user's Python file, ``FILE.py:NAME`` (a controller, a learning
    rule), or None for a built-in's name (which has no ``.py:``)."""
    path, _, attr = name.rpartition(":")
    return (Path(path), attr) if path.endswith(".py") else None


def user_file(name: str) -> Path | None:
    """The file of a user's ``FILE.py:NAME`` (a controller, a learning rule), None for a built-in's name: its bytes are
    part of its runs' fingerprint (:func:`neurowalk.fingerprint.code`)."""
    ref = user_ref(name)
    return ref[0] if ref is not None else None


def load_ref(name: str, prefix: str, error: type[ValueError]) -> tuple[ModuleType, object]:
    """The module of the user's ``FILE.py:NAME`` (:func:`load_python_file`) and its ``NAME``; ``error`` in one line
    where NAME is no Python name or the file defines none."""
    ref = user_ref(name)
    if ref is None:
        raise error(f"{name!r} is not FILE.py:NAME")
    path, attr = ref
    if not attr.isidentifier():
        raise error(f"{name!r}: {attr!r} after the colon is not a Python name")
    module = load_python_file(path, prefix, error)
    if not hasattr(module, attr):
        raise error(f"{path} defines no {attr!r} ({name!r})")
    return module, getattr(module, attr)


def load_python_file(path: Path, prefix: str, error: type[ValueError]) -> ModuleType:
    """A user's Python file run as a module named ``prefix`` + its stem (in ``sys.modules``: the module's dataclasses
    and a process pool's workers find it); ``error`` (a ValueError) in one line naming the file, and its line where
    it failed, where it cannot be read, does not compile or fails as it runs. A file read before with the same bytes
    is the module made then (a run of many configs runs it once)."""
    if not path.is_file():
        raise error(f"no such file {str(path)!r}")
    try:
        data = path.read_bytes()
        code = compile(data.decode("utf-8"), str(path), "exec")
    except SyntaxError as e:
        raise error(f"{path}, line {e.lineno}: SyntaxError: {e.msg}{_quoted(e.text)}") from None
    except (UnicodeDecodeError, OSError) as e:
        raise error(f"{path}: cannot be read as Python source ({type(e).__name__}: {e})") from None
    key = (str(path.resolve()), hashlib.sha256(data).hexdigest())
    if key in _LOADED:
        return _LOADED[key]
    name = f"{prefix}{path.stem.replace('-', '_')}"
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None:
        raise error(f"{path}: not a Python file")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        exec(code, module.__dict__)
    except Exception as e:
        del sys.modules[name]
        raise error(f"{_where(path, e)}: {type(e).__name__}: {e}") from None
    _LOADED[key] = module
    return module


_LOADED: dict[tuple[str, str], ModuleType] = {}  # (resolved path, SHA-256 of the bytes) -> the module


def _where(path: Path, e: BaseException) -> str:
    """``FILE, line N`` of the deepest frame of ``e`` in the user's file (``FILE`` where none is)."""
    own = [f for f in traceback.extract_tb(e.__traceback__) if Path(f.filename).resolve() == path.resolve()]
    if not own:
        return str(path)
    return f"{path}, line {own[-1].lineno}{_quoted(own[-1].line)}"


def _quoted(line: str | None) -> str:
    """`` (`the line`)`` of the user's file, or nothing."""
    text = (line or "").strip()
    return f" (`{text[:80]}`)" if text else ""
