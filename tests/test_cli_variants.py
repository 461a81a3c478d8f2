"""`--variant` and `--params` as a user gives them: good ones run and are recorded, bad ones exit 2 with one line."""

import json

import pytest

from neurowalk.cli import main


def _write(tmp_path, text: str):
    f = tmp_path / "p.json"
    f.write_text(text)
    return str(f)


@pytest.mark.parametrize(
    "extra,word",
    [
        (["--variant", "nope"], "unknown variant 'nope'"),
        (["--params", 'PARAMS:{"params": {"mu_z": 1}}'], "unknown field 'mu_z'"),
        (["--params", 'PARAMS:{"params": {"mu_b": NaN}}'], "mu_b must be a finite number"),
        (["--params", 'PARAMS:{"params": {"gamma_b": -0.001}}'], "gamma_b must be >= 0"),
        (["--params", 'PARAMS:{"params": {"mu_b": "fast"}}'], "mu_b must be a finite number"),
        (["--params", 'PARAMS:{"params": {"mu_b": 0.01}, "variant": "tuned"}'], "variant must be"),
        (["--params", "PARAMS:not json"], "is not JSON"),
        (["--params", "/no/such/file.json"], "cannot read params file"),
    ],
)
def test_bad_variant_or_params_exits_2_with_one_line(extra, word, tmp_path, capsys):
    extra = [_write(tmp_path, a.removeprefix("PARAMS:")) if a.startswith("PARAMS:") else a for a in extra]
    for cmd in (["run", "--body", "surrogate", "--steps", "10", "--out", str(tmp_path / "r")],
                ["sweep", "--body", "surrogate", "--steps", "10", "--out", str(tmp_path / "s")],
                ["figure", "table2", "--quick", "--out", str(tmp_path / "t")]):  # fmt: skip
        assert main([*cmd, *extra]) == 2, cmd
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and word in err[0], (cmd, err)
    assert not (tmp_path / "r").exists() and not (tmp_path / "s").exists()


def test_figure_without_variants_refuses_the_flag(capsys):
    assert main(["figure", "fig2", "--variant", "original", "--out", "/tmp/never"]) == 2
    assert "takes no --variant" in capsys.readouterr().err


def test_run_records_the_variant_and_params(tmp_path):
    f = _write(tmp_path, '{"params": {"mu_b": 0.01}, "variant": "original"}')
    out = tmp_path / "r"
    assert main(["run", "--arena", "box", "--body", "surrogate", "--steps", "300", "--params", f,
                 "--out", str(out), "--quiet"]) == 0  # fmt: skip
    s = json.loads((out / "summary.json").read_text())
    assert s["variant"] == "original" and s["params"] == {"mu_b": 0.01}
    assert s["start_weights"] == {"b0": 2.0, "q0": 3.0}


def test_sweep_runs_both_variants_as_separate_runs(tmp_path, capsys):
    out = tmp_path / "s"
    assert main(["sweep", "--arena", "box", "--body", "surrogate", "--steps", "200", "--variant", "paper,original",
                 "--out", str(out), "--quiet"]) == 0  # fmt: skip
    assert "2 runs" in capsys.readouterr().out
