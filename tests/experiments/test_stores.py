"""Result stores shared by figures (``figure --shared-runs``, :func:`neurowalk.experiments.stores.shared_stores`)."""

from __future__ import annotations

from pathlib import Path

from neurowalk.experiments.stores import run_store, shared_stores, store_path
from neurowalk.runners.specs import run_spec


def cheap(spec: dict) -> dict:
    """A result that depends on the spec alone (as a seeded run's does), without a simulation."""
    return {"seed": spec["seed"], "x": spec["seed"] * 0.5}


SPECS = [{"arena": "open", "steps": 10, "seed": s} for s in range(3)]


def test_without_sharing_a_figure_keeps_its_runs_in_its_own_folder(tmp_path: Path) -> None:
    assert store_path(tmp_path / "fig", "results.sqlite", cheap) == tmp_path / "fig" / "results.sqlite"
    run_store(SPECS, tmp_path / "fig", 1, fn=cheap)
    assert (tmp_path / "fig" / "results.sqlite").is_file()


def test_a_run_one_figure_made_is_taken_by_another(tmp_path: Path) -> None:
    shared = tmp_path / "runs"
    with shared_stores(shared):
        first, report1 = run_store(SPECS, tmp_path / "a", 1, fn=cheap)
        second, report2 = run_store([*SPECS[:2], {**SPECS[0], "seed": 9}], tmp_path / "b", 1, fn=cheap)
        default = store_path(tmp_path / "a", "results.sqlite", None)
    assert default == shared / "neurowalk.runners.specs.run_spec.sqlite"  # run_spec's, by default
    assert (report1.skipped, report1.ok) == (0, 3)
    assert (report2.skipped, report2.ok) == (2, 1)  # two taken from the first figure's runs, one made
    assert [second[k] for k in list(second)[:2]] == [first[k] for k in list(first)[:2]]
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()  # nothing in the figures' own folders
    assert (shared / f"{cheap.__module__}.cheap.sqlite").is_file()


def test_each_run_function_has_its_own_shared_store(tmp_path: Path) -> None:
    with shared_stores(tmp_path):
        assert store_path(Path("x"), "results.sqlite", cheap) != store_path(Path("x"), "results.sqlite", run_spec)
    assert store_path(Path("x"), "results.sqlite", cheap) == Path("x") / "results.sqlite"  # the block ended
