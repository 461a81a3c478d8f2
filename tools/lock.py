"""Write ``requirements.lock`` at the repository's root: the exact versions, in this environment, of neurowalk's
runtime dependencies and everything they pull in (the closure of ``pip install .``'s requirements, extras left out),
one ``name==version`` a line. Run it in the environment that ran the committed reproduction (docs/results/), whose
records name the same versions (``tests/experiments/reproduce/test_pinned.py`` holds them equal).

Run: ``python tools/lock.py``. Install from it: ``pip install -r requirements.lock -e .``.
"""

from __future__ import annotations

import platform
import sys
from importlib import metadata
from pathlib import Path

from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

ROOT = Path(__file__).resolve().parents[1]


def closure(root: str = "neurowalk") -> dict[str, str]:
    """{name: version} of the installed distributions ``root`` requires at run time, transitively (markers
    evaluated here, extras not followed)."""
    seen: dict[str, str] = {}
    todo = [Requirement(r) for r in metadata.requires(root) or []]
    while todo:
        req = todo.pop()
        if req.marker is not None and not req.marker.evaluate({"extra": ""}):
            continue
        name = canonicalize_name(req.name)
        if name in seen:
            continue
        seen[name] = metadata.version(req.name)
        todo += [Requirement(r) for r in metadata.requires(req.name) or []]
    return dict(sorted(seen.items()))


def main() -> None:
    """Write the lock file."""
    lines = [
        "# The exact versions of neurowalk's run-time dependencies in the environment that ran the committed",
        "# reproduction (docs/results/): made by tools/lock.py. Install: pip install -r requirements.lock -e .",
        f"# Python {platform.python_version()}, {platform.system()} {platform.machine()}",
        *(f"{name}=={version}" for name, version in closure().items()),
    ]
    (ROOT / "requirements.lock").write_text("\n".join(lines) + "\n", encoding="utf-8")
    print(f"wrote {ROOT / 'requirements.lock'}: {len(lines) - 3} packages", file=sys.stderr)


if __name__ == "__main__":
    main()
