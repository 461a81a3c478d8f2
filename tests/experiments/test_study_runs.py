"""The one run function and the one store of a study's runs (:mod:`neurowalk.experiments.study_runs`): terms kept with a
run, a run asked for twice made once, a run lacking a term made again keeping both, stores shared by figures
(``figure --shared-runs``)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from neurowalk.experiments.study_runs import Term, run_kept, run_store, store_path
from neurowalk.runners.store import ResultStore
from neurowalk.sim.config import EpisodeConfig
from neurowalk.sim.episode import Episode


def keep_start(ep: Episode) -> dict[str, Any]:
    """The first pose row (3,) and the number of rows."""
    return {"start": ep.trajectory.pose[0], "rows": len(ep.trajectory)}


def keep_end(ep: Episode) -> dict[str, Any]:
    """The last pose row (3,)."""
    return {"end": ep.trajectory.pose[-1]}


START = Term("test start", keep_start, arrays={"start": "float64"})
END = Term("test end", keep_end, arrays={"end": "float64"})
CONFIGS = [EpisodeConfig(arena="open", body="surrogate", steps=20, seed=s) for s in range(3)]


def finished(path: Path, code: str | None = None) -> dict[str, str]:
    """Each stored run's key and when it finished (of ``code``: a study's, whose file is part of it)."""
    with ResultStore(path, code) as store:
        return {r["key"]: r["finished_at"] for r in store.rows()}


def test_a_run_keeps_its_terms_beside_its_summary_arrays_read_back_as_arrays(tmp_path: Path) -> None:
    (r,) = run_store([(CONFIGS[0], (START,))], tmp_path, 1)
    assert r["seed"] == 0 and r["steps"] == 20  # the summary, as run_spec gives it
    assert r["kept"]["test start"]["rows"] == 20
    start = r["kept"]["test start"]["start"]
    assert isinstance(start, np.ndarray) and start.dtype == np.float64 and start.shape == (3,)
    assert (tmp_path / "results.sqlite").is_file()  # a study's one store, in its folder


def test_a_run_asked_twice_is_made_once_keeping_every_term(tmp_path: Path) -> None:
    a, b = run_store([(CONFIGS[0], (START,)), (CONFIGS[0], (END,))], tmp_path, 1)
    assert a is not b and set(a["kept"]) == set(b["kept"]) == {"test start", "test end"}
    np.testing.assert_array_equal(a["kept"]["test end"]["end"], b["kept"]["test end"]["end"])
    assert len(finished(tmp_path / "results.sqlite")) == 1


def test_a_stored_run_lacking_a_term_is_made_again_and_keeps_its_old_terms(tmp_path: Path) -> None:
    run_store([(c, (START,)) for c in CONFIGS], tmp_path, 1)
    before = finished(tmp_path / "results.sqlite")
    again = run_store([(c, (START,)) for c in CONFIGS], tmp_path, 1)  # nothing lacking: nothing run
    assert finished(tmp_path / "results.sqlite") == before
    (r,) = run_store([(CONFIGS[1], (END,))], tmp_path, 1)  # lacks END: made again, with START too
    after = finished(tmp_path / "results.sqlite")
    key = CONFIGS[1].key()
    assert after[key] != before[key] and {k: v for k, v in after.items() if k != key} == {
        k: v for k, v in before.items() if k != key
    }
    assert set(r["kept"]) == {"test start", "test end"}
    np.testing.assert_array_equal(r["kept"]["test start"]["start"], again[1]["kept"]["test start"]["start"])


def test_a_run_one_study_made_is_taken_by_another_with_shared_runs(tmp_path: Path) -> None:
    """Two studies with Settings.shared_runs: the second takes the runs the first made, nothing lands in their own
    folders, and the first's json names the store."""
    from neurowalk import Plan, Settings, Study
    from neurowalk.experiments.study import compute

    other = EpisodeConfig(arena="open", body="surrogate", steps=20, seed=9)

    def study(name: str, configs: list[EpisodeConfig]) -> Study:
        def measure(s: Settings, r: dict) -> dict:
            return {"paths": [k.path_length_m for k in r["a"]]}

        return Study(name, name, plot=lambda r: None, runs=lambda s: (Plan("a", c) for c in configs), measure=measure,
                     records_physics=True)  # fmt: skip

    shared = tmp_path / "runs"
    a = compute(study("first", CONFIGS), Settings(out=tmp_path / "a", shared_runs=shared, workers=1))
    before = finished(shared / "results.sqlite", a.code)
    b = compute(study("second", [*CONFIGS[:2], other]), Settings(out=tmp_path / "b", shared_runs=shared))
    after = finished(shared / "results.sqlite", b.code)
    assert a.code == b.code  # the same file's studies
    assert {k: after[k] for k in before} == before and len(after) == 4  # two taken, one made
    assert b.summary["paths"][:2] == a.summary["paths"][:2]
    assert not (tmp_path / "a" / "results.sqlite").exists() and not (tmp_path / "b" / "results.sqlite").exists()
    assert a.summary["store"] == str(store_path(shared))


def test_a_run_is_the_same_kept_in_memory_or_streamed_alone(tmp_path: Path) -> None:
    from neurowalk.experiments.suites.long_runs import LONG

    spec = EpisodeConfig(arena="cluttered", body="surrogate", steps=300, seed=1).spec()
    streamed = run_kept((LONG,), spec)["kept"]["long"]
    from neurowalk.experiments.study_runs import kept_of
    from neurowalk.runners.specs import episode_of

    held = kept_of((LONG,), episode_of(spec))["kept"]["long"]
    assert streamed.keys() == held.keys()
    for k in streamed:
        np.testing.assert_array_equal(streamed[k], held[k], err_msg=k)
    with pytest.raises(ValueError, match="streams its run"):
        run_kept((LONG, START), spec)
