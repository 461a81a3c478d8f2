"""The fingerprint of the code that computes a run: ``code`` in ``summary.json``, in a figure's json and in every row
of a result store.

.. code-block:: text

    code = SHA-256 (16 hex digits) of
        the package's files that compute runs   every file under src/neurowalk but cli/ (the command line) and
                                                 text or pictures (.md, .png, .svg): networks, bodies, arenas,
                                                 loops, metrics, the studies' terms and measures, calibrations
        the libraries whose bits a run follows  numpy, MuJoCo, numba (their versions) and Python's (major.minor)
        the user's files a run reads            a study's file, a user's MJCF body (their contents, not names)

A result store takes a run as done only when its row was made under the same ``code`` (``runners/store.py``): an
edit of the learning rule, a metric or a keep term runs the runs again; an edit of docs/ or of the command line's
help does not. The compiled-kernel cache (``compiled.py``) is keyed by the same code.
"""

from __future__ import annotations

import functools
import hashlib
import json
import sys
from collections.abc import Callable, Iterable
from functools import cache
from importlib import metadata
from pathlib import Path
from typing import Any

#: The package's folder.
PACKAGE = Path(__file__).resolve().parent
#: Folders of the package left out: the command line (its parsing, help and printing make no run's numbers).
LEFT_OUT = ("cli",)
#: File kinds left out: text and pictures.
LEFT_OUT_SUFFIXES = (".md", ".png", ".svg", ".pyc")
#: The libraries whose versions go into the code: a run's bits follow them.
LIBRARIES = ("numpy", "mujoco", "numba")
DIGITS = 16


def package_files() -> list[Path]:
    """The package's files whose contents go into the code, sorted."""
    out = []
    for path in sorted(PACKAGE.rglob("*")):
        rel = path.relative_to(PACKAGE)
        if not path.is_file() or "__pycache__" in rel.parts or rel.parts[0] in LEFT_OUT:
            continue
        if path.suffix in LEFT_OUT_SUFFIXES:
            continue
        out.append(path)
    return out


@cache
def package_digest() -> str:
    """SHA-256 of :func:`package_files` (their paths in the package and their bytes); read once a process."""
    h = hashlib.sha256()
    for path in package_files():
        h.update(path.relative_to(PACKAGE).as_posix().encode() + b"\0")
        h.update(hashlib.sha256(path.read_bytes()).digest())
    return h.hexdigest()


@cache
def library_versions() -> dict[str, str]:
    """``{name: version}`` of :data:`LIBRARIES` (those installed) and Python's ``major.minor``."""
    out = {"python": f"{sys.version_info[0]}.{sys.version_info[1]}"}
    for name in LIBRARIES:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            continue
    return out


def file_digest(path: Path | str) -> str:
    """SHA-256 of a file's bytes (hex); ``"missing"`` where it cannot be read (a run of it fails on its own)."""
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError:
        return "missing"


def code(files: Iterable[Path | str] = ()) -> str:
    """The fingerprint (:data:`DIGITS` hex digits) of the package, the libraries and the user's ``files`` (their
    contents, in no particular order: a file moved elsewhere gives the same code)."""
    h = hashlib.sha256()
    h.update(package_digest().encode())
    h.update(json.dumps(library_versions(), sort_keys=True).encode())
    for digest in sorted({file_digest(f) for f in files}):
        h.update(digest.encode())
    return h.hexdigest()[:DIGITS]


def user_files(*fns: Callable[..., Any] | None) -> list[Path]:
    """The source files of ``fns`` (functions, partials, bound methods) that lie outside the package: a user's
    study file. Functions without a source file (built-ins) and the package's own are left out."""
    out: dict[Path, None] = {}
    for fn in fns:
        while isinstance(fn, functools.partial):
            fn = fn.func
        fn = getattr(fn, "__func__", fn)
        filename = getattr(getattr(fn, "__code__", None), "co_filename", None)
        if not filename:
            continue
        path = Path(filename).resolve()
        if path.is_file() and not path.is_relative_to(PACKAGE):
            out[path] = None
    return sorted(out)
