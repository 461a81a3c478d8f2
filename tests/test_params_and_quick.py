"""Options as their help says: a params file keeps the variant it names (a --variant that says otherwise is refused)
and one that names none is set over --variant (default paper), Table 2's row saying which; a --quick run writes a
folder of its own and never overwrites a full result."""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib.pyplot as plt
import pytest

from neurowalk.cli import main
from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.figures.table2 import rows
from neurowalk.experiments.study import resolve

GAMMA = {"gamma_b": 0.004}

STUDY = """
from neurowalk import EpisodeConfig, Plan, Study
from neurowalk.plotting import pyplot


def runs(s):
    for seed in s.seed_range(full=3):
        yield Plan("a", EpisodeConfig(arena="open", body="surrogate", steps=100 if s.quick else 200, seed=seed))


def plot(result):
    fig, ax = pyplot().subplots()
    ax.plot(result.summary["paths"])
    return fig


def measure(s, r):
    return {"paths": [k.path_length_m for k in r["a"]]}


study = Study("walks", "how far", plot=plot, runs=runs, measure=measure)
"""


def _file(tmp_path: Path, **extra: str) -> Path:
    path = tmp_path / "params.json"
    path.write_text(json.dumps({"params": GAMMA, **extra}))
    return path


CASES = [
    (None, None, "paper"),
    (None, "original", "original"),
    ("original", None, "original"),
    ("paper", "paper", "paper"),
]


@pytest.mark.parametrize(("named", "flag", "row"), CASES)
def test_a_params_row_runs_on_the_files_variant_or_the_flags(tmp_path: Path, named, flag, row) -> None:
    path = _file(tmp_path, **({"variant": named} if named else {}))
    s = resolve(FIGURES["table2"], Settings(params=path, variant=flag))
    table = rows(s.variant, s.params)
    assert table[f"plastic-params ({row})"] == {"controller": "plastic", "variant": row, "params": GAMMA}


def test_a_variant_that_contradicts_the_files_is_refused_in_one_line(tmp_path: Path, capsys) -> None:
    path = _file(tmp_path, variant="original")
    status = main(["figure", "table2", "--params", str(path), "--variant", "paper", "--out", str(tmp_path / "t")])
    err = capsys.readouterr().err.strip().splitlines()
    assert (
        status == 2 and len(err) == 1 and "--variant paper contradicts params file" in err[0] and "original" in err[0]
    )
    assert not (tmp_path / "t" / "table2.json").exists()


def test_a_quick_study_leaves_the_full_result_untouched(tmp_path: Path, monkeypatch, capsys) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "walks.py").write_text(STUDY)
    assert main(["study", "walks.py", "--workers", "1"]) == 0
    full = (tmp_path / "out" / "walks" / "walks.json").read_bytes()
    assert json.loads(full)["quick"] is False and len(json.loads(full)["paths"]) == 3
    assert main(["study", "walks.py", "--quick", "--workers", "1"]) == 0
    quick = json.loads((tmp_path / "out" / "walks-quick" / "walks.json").read_text())
    assert quick["quick"] is True and (tmp_path / "out" / "walks" / "walks.json").read_bytes() == full
    capsys.readouterr()
    assert main(["study", "walks.py", "--quick", "--out", "out/walks"]) == 2  # a folder with the full result: refused
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "holds walks's full result" in err[0]
    assert (tmp_path / "out" / "walks" / "walks.json").read_bytes() == full
    plt.close("all")


def test_a_quick_figure_writes_its_own_default_folder(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(["figure", "fig2", "--quick"]) == 0
    assert (tmp_path / "out" / "fig2-quick" / "fig2.json").is_file() and not (tmp_path / "out" / "fig2").exists()
    plt.close("all")
