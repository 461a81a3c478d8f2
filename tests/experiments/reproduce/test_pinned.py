"""The lock file of the committed reproduction (requirements.lock): it exists, it pins the versions the committed
records name, and `neurowalk reproduce` says in one line when the installed versions differ from it."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from neurowalk.experiments.reproduce import pinned
from neurowalk.experiments.reproduce.plan import PLAN

ROOT = Path(__file__).parents[3]


def test_the_lock_pins_what_the_committed_reproduction_ran_on() -> None:
    pins = pinned.read_lock(ROOT / "requirements.lock")
    assert pins is not None and pinned.LOCK == ROOT / "requirements.lock"
    for item in PLAN:
        made = json.loads((ROOT / "docs" / "results" / f"{item.name}.json").read_text())["versions"]
        for name in ("numpy", "mujoco", "numba", "matplotlib"):
            assert pins[name] == made[name], (item.name, name)
    assert {"numpy", "numba", "llvmlite", "mujoco", "matplotlib", "tqdm", "imageio-ffmpeg"} <= set(pins)


def test_other_versions_are_said_in_one_line(tmp_path: Path) -> None:
    lock = tmp_path / "requirements.lock"
    lock.write_text("# a comment\nnumpy==0.0.1\nno-such-package==1.0\n\n")
    line = pinned.versions_line(lock)
    assert line is not None and "\n" not in line
    assert "2 installed package versions differ" in line and "numpy" in line and "no-such-package" in line
    assert "(locked 0.0.1)" in line and "not installed" in line
    here = __import__("numpy").__version__
    lock.write_text(f"numpy=={here}\n")
    assert pinned.versions_line(lock) is None  # the same versions: nothing to say
    assert pinned.versions_line(tmp_path / "none.lock") is None  # no lock file (an installed wheel): nothing


def test_a_broken_lock_names_its_line(tmp_path: Path) -> None:
    lock = tmp_path / "requirements.lock"
    lock.write_text("numpy==2.4.6\nnumpy>=2\n")
    with pytest.raises(ValueError, match=r"requirements.lock:2: not name==version"):
        pinned.read_lock(lock)
