"""Runs are keyed by the code that made them: in a copy of the package, an edit of the learning rule, of a metric or
of a study's keep term makes the same command in the same folder run its runs again (the new code's numbers, and one
line saying how many stored runs other code made); an edit of the command line's help reuses every stored run; two
checkouts sharing one store keep their runs side by side."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import neurowalk

pytestmark = pytest.mark.slow  # each edit of compiled code compiles the kernels again (a copy of the package)

STUDY = """
from neurowalk import EpisodeConfig, Plan, Study, Term


def ends(ep):
    return {"end": [float(x) for x in ep.trajectory.pose[-1]]}


END = Term("end", ends)


def runs(s):
    for seed in range(3):
        yield Plan("plastic", EpisodeConfig(arena="narrow-passage", body="surrogate", steps=400, seed=seed), (END,))


def measure(s, runs):
    kept = runs["plastic"]
    return {"ends": [k.kept["end"]["end"] for k in kept], "paths": [k.path_length_m for k in kept]}


def plot(result):
    from neurowalk.plotting import pyplot

    fig, ax = pyplot().subplots()
    ax.plot([p for p in result.summary["paths"]])
    return fig


study = Study("ends", "where the runs end", plot=plot, runs=runs, measure=measure)
"""
OTHER = "made by other code"


class Checkout:
    """A copy of the package (``root/pkg/neurowalk``) that a test edits, and the commands run from it."""

    def __init__(self, root: Path, cache: Path) -> None:
        self.root = root
        self.pkg = root / "pkg" / "neurowalk"
        shutil.copytree(Path(neurowalk.__file__).parent, self.pkg, ignore=shutil.ignore_patterns("__pycache__"))
        self.env = {**os.environ, "PYTHONPATH": str(root / "pkg"), "NUMBA_CACHE_DIR": str(cache),
                    "NEUROWALK_COMPILE_NOTE": "0"}  # fmt: skip

    def edit(self, rel: str, old: str, new: str) -> None:
        path = self.pkg / rel
        text = path.read_text()
        assert text.count(old) >= 1, (rel, old)
        path.write_text(text.replace(old, new))

    def run(self, *args: str | Path, cwd: Path) -> str:
        cmd = [sys.executable, "-m", "neurowalk", *map(str, args)]
        done = subprocess.run(cmd, cwd=cwd, env=self.env, capture_output=True, text=True, timeout=900)
        assert done.returncode == 0, done.stderr[-3000:]
        assert str(self.pkg) in self.where(cwd)  # the copy ran, not the installed package
        return done.stdout

    def where(self, cwd: Path) -> str:
        code = "import neurowalk; print(neurowalk.__file__)"
        return subprocess.run(
            [sys.executable, "-c", code], cwd=cwd, env=self.env, capture_output=True, text=True
        ).stdout


def _numbers(path: Path) -> dict:
    """A figure's json without its code and the store its runs are in."""
    return {k: v for k, v in json.loads(path.read_text()).items() if k not in ("code", "store")}


def _other(stdout: str) -> int:
    """How many stored runs the command said other code made (0: it said none)."""
    found = re.findall(r"(\d[\d,]*) stored runs? in \S+ made by other code", stdout)
    assert len(found) <= 1, stdout
    return int(found[0].replace(",", "")) if found else 0


@pytest.fixture
def checkout(tmp_path: Path) -> Checkout:
    return Checkout(tmp_path, tmp_path / "cache")


def test_an_edited_learning_rule_runs_a_figure_again_an_edited_help_does_not_and_checkouts_share_a_store(
    checkout: Checkout, tmp_path: Path
):
    out, shared = tmp_path / "table2", tmp_path / "shared"
    figure = ("figure", "table2", "--quick", "--out", out, "--shared-runs", shared)
    first = checkout.run(*figure, cwd=tmp_path)
    assert _other(first) == 0
    before = _numbers(out / "table2.json")
    code = json.loads((out / "table2.json").read_text())["code"]

    checkout.edit("cli/figure.py", "redraw from DIR/NAME.json", "redraw (an edited help) from DIR/NAME.json")
    again = checkout.run(*figure, cwd=tmp_path)
    assert "going on from" in again and _other(again) == 0  # every stored run reused
    assert _numbers(out / "table2.json") == before and json.loads((out / "table2.json").read_text())["code"] == code

    # the learning rule (the compiled sensory_step): self weights learn three times as fast
    checkout.edit("neural/sensory.py", "s[4] = b1 + correlation", "s[4] = b1 + 3.0 * correlation")
    checkout.edit("neural/sensory.py", "s[5] = b2 + correlation", "s[5] = b2 + 3.0 * correlation")
    edited = checkout.run(*figure, cwd=tmp_path)
    assert _other(edited) > 0 and json.loads((out / "table2.json").read_text())["code"] != code  # it said so
    new = _numbers(out / "table2.json")
    fresh = tmp_path / "fresh"
    checkout.run("figure", "table2", "--quick", "--out", fresh, cwd=tmp_path)
    assert new == _numbers(fresh / "table2.json") != before  # the new rule's numbers

    # a second checkout, the package as it came, on the same shared store: the first runs are kept beside the new
    second = Checkout(tmp_path / "second", tmp_path / "cache")
    said = second.run("figure", "table2", "--quick", "--out", tmp_path / "second-out", "--shared-runs", shared,
                      cwd=tmp_path)  # fmt: skip
    assert "going on from" in said and _other(said) == 0 and _numbers(tmp_path / "second-out" / "table2.json") == before
    said = checkout.run(*figure, cwd=tmp_path)  # and the edited checkout's runs stayed too
    assert "going on from" in said and _other(said) == 0 and _numbers(out / "table2.json") == new


def test_an_edited_metric_or_keep_term_runs_a_study_again(checkout: Checkout, tmp_path: Path):
    study = tmp_path / "ends.py"
    study.write_text(STUDY)
    out = tmp_path / "out"
    checkout.run("study", study, "--out", out, cwd=tmp_path)
    before = _numbers(out / "ends.json")
    assert _other(checkout.run("study", study, "--out", out, cwd=tmp_path)) == 0

    checkout.edit("metrics.py", "def path_length(", "def _path_length(")  # a metric: path length counted twice
    checkout.edit("metrics.py", "\ndef _path_length(", "\ndef path_length(pose):\n    return 2.0 * _path_length(pose)"
                  "\n\n\ndef _path_length(")  # fmt: skip
    said = checkout.run("study", study, "--out", out, cwd=tmp_path)
    after = _numbers(out / "ends.json")
    assert (
        _other(said) == 3 and after["paths"] == [2.0 * p for p in before["paths"]] and after["ends"] == before["ends"]
    )

    study.write_text(STUDY.replace('"end": [float(x) for x in ep.trajectory.pose[-1]]',
                                   '"end": [float(x) for x in ep.trajectory.pose[-2]]'))  # fmt: skip
    said = checkout.run("study", study, "--out", out, cwd=tmp_path)
    assert _other(said) == 3 and _numbers(out / "ends.json")["ends"] != before["ends"]
