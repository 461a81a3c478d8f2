"""The versions the committed reproduction ran on (``requirements.lock`` at the repository's root) against those
installed: what ``neurowalk reproduce`` says in one line where they differ, and the report names.

The promise is bit for bit on the same versions and CPU type; under other versions the numbers may move in their
last bits (numpy's and numba's compiled code), so a reproduction says so before it starts. The lock file is found
beside the package's source, as in a checkout; an installed wheel has none, and then nothing is compared.
"""

from __future__ import annotations

from importlib import metadata
from pathlib import Path

import neurowalk

LOCK = Path(neurowalk.__file__).resolve().parents[2] / "requirements.lock"
"""Where a checkout holds the lock file (``src/neurowalk`` two folders below the root)."""


def read_lock(path: Path | None = None) -> dict[str, str] | None:
    """{name: version} of the lock file's (``path``, default :data:`LOCK`) ``name==version`` lines (comments and
    blank lines skipped), or None where there is no file.

    Raises:
        ValueError: a line that is neither a comment nor ``name==version``, with its number.
    """
    path = LOCK if path is None else path
    if not path.is_file():
        return None
    pins: dict[str, str] = {}
    for i, raw in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        name, sep, version = line.partition("==")
        if not sep or not name.strip() or not version.strip():
            raise ValueError(f"{path}:{i}: not name==version: {raw!r}")
        pins[name.strip().lower()] = version.strip()
    return pins


def _installed(name: str) -> str | None:
    """The installed version of distribution ``name``, or None where it is not installed."""
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return None


def differences(pins: dict[str, str]) -> list[str]:
    """``"numpy 2.3.0 (locked 2.4.6)"`` for each pinned package installed at another version or not at all."""
    out = []
    for name, want in sorted(pins.items()):
        have = _installed(name)
        if have != want:
            out.append(f"{name} {have or 'not installed'} (locked {want})")
    return out


def versions_line(path: Path | None = None) -> str | None:
    """The one line ``neurowalk reproduce`` prints where the installed versions differ from the lock file's, else
    None (also where there is no lock file)."""
    path = LOCK if path is None else path
    pins = read_lock(path)
    if pins is None:
        return None
    off = differences(pins)
    if not off:
        return None
    shown = ", ".join(off[:4]) + (f" and {len(off) - 4} more" if len(off) > 4 else "")
    return (
        f"reproduce: {len(off)} installed package versions differ from {path.name}, which the committed "
        f"reproduction ran on: {shown}; numbers may differ in their last bits (pip install -r {path.name} -e .)"
    )
