"""The committed pictures are what their commands draw today (tools/pictures.py makes them again).

The README's picture, docs/run.png, is the first command's ``run.png``: the run's numbers are held to the committed
summary (docs/run.json) on any machine, the pixels where matplotlib is the version that drew the committed file
(another version may draw a line a pixel aside).
"""

from __future__ import annotations

import importlib.util
import json
import shlex
import sys
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from PIL import Image

from neurowalk.cli import main

ROOT = Path(__file__).parents[2]
_spec = importlib.util.spec_from_file_location("pictures", ROOT / "tools" / "pictures.py")
assert _spec is not None and _spec.loader is not None
pictures = sys.modules["pictures"] = importlib.util.module_from_spec(_spec)  # its dataclass looks itself up there
_spec.loader.exec_module(pictures)
#: Keys of a run's summary that say where and how fast it ran, not what the robot did.
MACHINE = {"wall_time_s", "real_time_factor", "neurowalk_version", "code"}


@pytest.fixture(scope="module")
def readme_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The README's first command, run as a user runs it, into a temporary folder."""
    out = tmp_path_factory.mktemp("readme") / "run"
    args = [a.replace("OUT", str(out)) for a in shlex.split(pictures.PICTURES["run"].command)]
    assert args[0] == "neurowalk" and main(args[1:]) == 0
    return out


def test_the_readme_pictures_command_is_the_readmes_first():
    readme = (ROOT / "README.md").read_text()
    command = pictures.PICTURES["run"].command.replace("--out OUT", "--out out/run")
    assert f".venv/bin/{command}\n" in readme and "![A run: path, inputs, steering and weights](docs/run.png)" in readme


def _flat(value: object, key: str = "") -> dict[str, object]:
    """A JSON value as ``{path: leaf}`` (nested objects and lists unfolded)."""
    if isinstance(value, dict):
        return {k: v for name, x in value.items() for k, v in _flat(x, f"{key}/{name}").items()}
    if isinstance(value, list):
        return {k: v for i, x in enumerate(value) for k, v in _flat(x, f"{key}/{i}").items()}
    return {key: value}


def _same_run(made: Path, committed_json: Path) -> None:
    """The run's summary ``made`` is the committed one: its outcome, path and weights (floats within 1e-9: the same
    on another CPU, usage.md)."""
    today, committed = (
        _flat({k: v for k, v in json.loads(p.read_text()).items() if k not in MACHINE}) for p in (made, committed_json)
    )
    assert today.keys() == committed.keys()
    floats = [k for k, v in committed.items() if isinstance(v, float)]
    assert {k: today[k] for k in floats} == pytest.approx({k: committed[k] for k in floats}, rel=1e-9, abs=1e-9)
    assert {k: v for k, v in today.items() if k not in floats} == {k: committed[k] for k in today if k not in floats}


def test_the_readme_run_is_the_committed_one(readme_run: Path):
    _same_run(readme_run / "summary.json", ROOT / "docs" / "run.json")


@pytest.mark.slow
def test_the_viewer_pictures_run_is_the_committed_one(tmp_path: Path):
    """docs/tutorials/view.png shows the run of the page's command (its screenshot needs a browser: the numbers of
    the run it shows are held here)."""
    pic = pictures.PICTURES["view"]
    args = [a.replace("OUT", str(tmp_path / "np")) for a in shlex.split(pic.command)]
    assert main([*args[1:], "--quiet"]) == 0
    assert pic.command.replace("--out OUT", "--out out/np") in (ROOT / pic.page).read_text()
    _same_run(tmp_path / "np" / "summary.json", ROOT / pic.files["summary.json"])


def test_docs_run_png_is_what_the_readme_command_draws(readme_run: Path):
    committed = Image.open(ROOT / "docs" / "run.png")
    drawn_by = committed.info.get("Software", "")
    if f"version{matplotlib.__version__}," not in drawn_by:
        pytest.skip(f"docs/run.png was drawn by {drawn_by!r}; this is matplotlib {matplotlib.__version__}")
    today = np.asarray(Image.open(readme_run / "run.png").convert("RGB"), dtype=np.int16)
    old = np.asarray(committed.convert("RGB"), dtype=np.int16)
    assert today.shape == old.shape
    differ = np.mean(np.any(np.abs(today - old) > 8, axis=-1))
    assert differ <= 0.001, f"{differ:.2%} of the pixels differ: run python tools/pictures.py run"
