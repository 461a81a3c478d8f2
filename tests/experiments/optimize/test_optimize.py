"""``neurowalk optimize``: a tiny CMA-ES search runs, resumes without recomputing, reproduces, and checks input."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from neurowalk.cli import main
from neurowalk.experiments.optimize import search
from neurowalk.experiments.optimize.report import Search
from neurowalk.experiments.optimize.space import DEFAULT_FIELDS, Dim, fitness, make_space, start_point
from neurowalk.neural.variants import get_variant, read_params_file
from neurowalk.runners.store import ResultStore

TINY = {"population": 4, "generations": 2, "environments": 3, "heldout": 3, "steps": 500, "deadend_seeds": 1}
RUNS_PER_CANDIDATE = 3 + 6  # training environments + dead ends (6 geometries x 1 seed)


def tiny(out: Path, **changes: Any) -> Search:
    """The tiny search of these tests in ``out`` (in this process: workers 1)."""
    return search.run(out=out, sizes={**TINY, **changes}, workers=1, progress=False)


def store_keys(folder: Path) -> set[str]:
    with ResultStore(folder / "results.sqlite") as store:
        return {row["key"] for row in store.rows()}


@pytest.fixture(scope="module")
def searched(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Search]:
    out = tmp_path_factory.mktemp("search")
    return out, tiny(out)


def test_tiny_search_writes_its_files_and_a_rerun_recomputes_nothing(searched: tuple[Path, Search]) -> None:
    out, s = searched
    for name in ("best.json", "heldout.json", "history.json", "convergence.png", "cmaes.json", "results.sqlite"):
        assert (out / name).is_file(), name
    assert len(s.history) == 2 and all(len(r["params"]) == 4 for r in s.history)
    assert s.runs_computed == (1 + 2 * 4) * RUNS_PER_CANDIDATE + 3 * 3  # base, 2 x 4 candidates, held-out x 3 rows
    best = json.loads((out / "best.json").read_text())
    assert set(best["params"]) == set(DEFAULT_FIELDS) and best["variant"] == "original"
    fb = best["found_by"]
    assert fb["generations"] == 2 and fb["population"] == 4 and fb["seed"] == 0
    assert fb["training"]["table_seed"] != fb["heldout"]["table_seed"]
    assert [h["generation"] for h in fb["history"]] == [1, 2]
    assert set(fb["heldout"]["rates"]) == {"best", "base", "paper"}
    for r in fb["heldout"]["rates"].values():
        lo, hi = r["success_rate_95ci"]
        assert lo <= r["success_rate"] <= hi
    held = json.loads((out / "heldout.json").read_text())
    assert held["environments"] == 3 and len(held["per_environment"]) == 3
    again = tiny(out)
    assert again.runs_computed == 0 and again.runs_skipped > 0
    assert json.loads((out / "best.json").read_text()) == best


def test_a_search_killed_mid_generation_resumes_and_ends_as_an_uninterrupted_one(
    searched: tuple[Path, Search], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    out, s = searched
    calls = {"n": 0}
    real = search.Runner.__call__

    def killed_after_storing_generation_2(self: search.Runner, specs: list[dict[str, Any]]) -> list[dict[str, Any]]:
        res = real(self, specs)
        calls["n"] += 1
        if calls["n"] == 3:  # base, generation 1, generation 2: its runs are stored, CMA-ES not yet told
            raise KeyboardInterrupt
        return res

    monkeypatch.setattr(search.Runner, "__call__", killed_after_storing_generation_2)
    with pytest.raises(KeyboardInterrupt):
        tiny(tmp_path)
    assert not (tmp_path / "best.json").exists()
    monkeypatch.setattr(search.Runner, "__call__", real)
    stored = store_keys(tmp_path)
    resumed = tiny(tmp_path)
    assert store_keys(tmp_path) - stored <= store_keys(out)  # only the held-out runs were new
    assert resumed.runs_computed == len(store_keys(tmp_path) - stored) <= 3 * 3
    assert json.loads((tmp_path / "best.json").read_text()) == json.loads((out / "best.json").read_text())
    assert resumed.history == s.history


def test_more_generations_continue_the_saved_state(searched: tuple[Path, Search], tmp_path: Path) -> None:
    out, _ = searched
    one = tiny(tmp_path, generations=1)
    assert len(one.history) == 1
    two = tiny(tmp_path)
    assert two.best == json.loads((out / "best.json").read_text())
    assert two.runs_computed <= 4 * RUNS_PER_CANDIDATE + 3  # generation 2 and the held-out runs of a new best


def test_best_json_is_a_params_file_that_run_accepts(searched: tuple[Path, Search], tmp_path: Path) -> None:
    out, s = searched
    data = read_params_file(out / "best.json")
    assert data["variant"] == "original" and data["params"] == s.best["params"]
    v = get_variant(data["variant"], data["params"])
    assert v.name == "original+params" and v.sensory.mu_b == data["params"]["mu_b"]
    assert v.sensory.b_start == 2.0  # the rest of the original variant stays
    args = ["run", "--params", str(out / "best.json"), "--body", "surrogate", "--steps", "50", "--quiet"]
    assert main([*args, "--out", str(tmp_path)]) == 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["variant"] == "original" and summary["params"] == data["params"]


def test_space_maps_rates_on_a_log_scale_and_starts_at_the_base_values() -> None:
    space = make_space("original")
    assert [d.name for d in space] == list(DEFAULT_FIELDS)
    mu_b = space[0]
    assert mu_b.scale == "log" and space[-1].scale == "linear"  # k is linear
    assert mu_b.decode(0.0) == mu_b.lo and mu_b.decode(1.0) == mu_b.hi
    assert mu_b.decode(0.5) == pytest.approx(math.sqrt(mu_b.lo * mu_b.hi), rel=1e-5)
    x0 = start_point(space, "original")
    sensory = get_variant("original").sensory
    for d, u in zip(space, x0, strict=True):
        assert 0 < u < 1 and d.decode(u) == pytest.approx(getattr(sensory, d.name), rel=1e-5)
    assert Dim("gamma_b", 0.0, 1e-3, "linear").decode(0.25) == pytest.approx(2.5e-4)
    assert make_space("paper", [], {"gamma_b": (0.0, 1e-3)})[0].scale == "linear"  # lo 0: no log scale


def test_fitness_ranks_every_infeasible_candidate_below_every_feasible_one() -> None:
    def runs(trapped: list[bool], escaped: list[bool]) -> tuple[list[dict], list[dict]]:
        return ([{"trapped": t, "coverage": 0.5} for t in trapped], [{"escaped": e} for e in escaped])

    worst_feasible = fitness(*runs([True] * 4, [True] * 6))
    best_infeasible = fitness(*runs([False] * 4, [True] * 5 + [False]))
    worse_infeasible = fitness(*runs([False] * 4, [True] * 4 + [False] * 2))
    assert worst_feasible["feasible"] and not best_infeasible["feasible"]
    assert worst_feasible["fitness"] == 0.0 > best_infeasible["fitness"] > worse_infeasible["fitness"] >= -2
    assert worst_feasible["score"] < best_infeasible["score"] < worse_infeasible["score"]
    more_cover = fitness([{"trapped": False, "coverage": 0.9}], [{"escaped": True}])
    less_cover = fitness([{"trapped": False, "coverage": 0.1}], [{"escaped": True}])
    one_fail = fitness([{"trapped": True, "coverage": 1.0}, {"trapped": False, "coverage": 1.0}], [{"escaped": True}])
    assert more_cover["score"] < less_cover["score"]  # coverage breaks the tie ...
    assert fitness([{"trapped": False, "coverage": 0.0}] * 2, [{"escaped": True}])["score"] < one_fail["score"]


@pytest.mark.parametrize(
    ("kwargs", "word"),
    [
        ({"fields": ["mu_x"]}, "mu_x"),
        ({"bounds": {"mu_b": (0.03, 0.001)}}, "lo < hi"),
        ({"bounds": {"mu_b": (float("nan"), 0.01)}}, "finite"),
        ({"bounds": {"gamma_q": (-0.001, 0.001)}}, "gamma_q"),
        ({"sizes": {"population": -1}}, "population"),
        ({"sizes": {"population": 1}}, "population"),
        ({"sizes": {"steps": 0}}, "steps"),
        ({"sizes": {"popsize": 4}}, "popsize"),
        ({"variant": "tuned"}, "tuned"),
        ({"train_seed": 0, "heldout_seed": 2}, "overlap"),
        ({"seed": -1}, "seed"),
        ({"sigma0": 0.0}, "sigma0"),
    ],
)
def test_bad_input_raises_naming_the_value(kwargs: dict[str, Any], word: str, tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=word):
        search.run(out=tmp_path, **{"sizes": TINY, **kwargs}, workers=1, progress=False)
    assert not (tmp_path / "results.sqlite").exists()


def test_an_output_folder_holding_another_search_is_refused(searched: tuple[Path, Search]) -> None:
    out, _ = searched
    with pytest.raises(ValueError, match="population"):
        tiny(out, population=5)


@pytest.mark.parametrize(
    ("args", "word"),
    [
        (["--param", "mu_b=0.03:0.001"], "mu_b"),
        (["--param", "mu_b=abc"], "mu_b=abc"),
        (["--fields", "mu_b,nope"], "nope"),
        (["--population", "-3"], "-3"),
        (["--variant", "nope"], "nope"),
    ],
)
def test_cli_bad_input_exits_2_with_one_line(args: list[str], word: str, tmp_path: Path, capsys: Any) -> None:
    assert main(["optimize", "--out", str(tmp_path), *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and word in err[0]


def test_cli_runs_a_tiny_search(tmp_path: Path, capsys: Any) -> None:
    sizes = ["--population", "3", "--generations", "1", "--environments", "2", "--heldout", "2", "--steps", "300",
             "--deadend-seeds", "1"]  # fmt: skip
    assert main(["optimize", "--out", str(tmp_path), "--workers", "1", "--quiet", "--fields", "mu_b", *sizes]) == 0
    out = capsys.readouterr().out
    assert "generation 1/1" in out and "held-out (2 environments" in out
    best = read_params_file(tmp_path / "best.json")
    assert list(best["params"]) == ["mu_b"] and "--fields mu_b" in best["found_by"]["command"]
    assert np.isfinite(best["params"]["mu_b"])


class _Evil:
    """Unpickling this creates a file: proof that a pickle was loaded."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def __reduce__(self) -> tuple:
        return (Path.touch, (self.path,))


def test_a_crafted_pickle_as_the_search_state_runs_nothing(tmp_path: Path, capsys: Any) -> None:
    import pickle

    proof = tmp_path / "pwned"
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "cmaes.pkl").write_bytes(pickle.dumps({"es": _Evil(proof)}))
    args = ["optimize", "--quick", "--generations", "1", "--population", "4", "--out", str(tmp_path / "out")]
    assert main([*args, "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cmaes.pkl" in err[0] and not proof.exists()


@pytest.mark.parametrize("content", [b"", b"{", b"\x00\xff" * 40, b"{}", b'{"format": 99, "settings": {}, '
                                     b'"records": [], "stopped": null}'], ids=["empty", "cut", "binary", "json",
                                                                              "newer"])  # fmt: skip
def test_a_damaged_search_record_is_named_in_one_line_and_left_as_it_was(
    searched: tuple[Path, Search], content: bytes, tmp_path: Path, capsys: Any
) -> None:
    (tmp_path / "cmaes.json").write_bytes(content)
    with pytest.raises(ValueError, match=r"cmaes\.json") as info:
        tiny(tmp_path)
    assert "\n" not in str(info.value)
    assert (tmp_path / "cmaes.json").read_bytes() == content


def test_a_search_record_whose_candidates_were_edited_is_refused(searched: tuple[Path, Search], tmp_path: Path) -> None:
    out, _ = searched
    record = json.loads((out / "cmaes.json").read_text())
    record["records"][0]["x"][0][0] += 0.01
    (tmp_path / "cmaes.json").write_text(json.dumps(record))
    with pytest.raises(ValueError, match="not those this seed draws"):
        tiny(tmp_path)
