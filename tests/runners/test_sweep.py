"""The sweep engine on the local backend: resume, dedup, errors, dead workers, same rows for any worker count."""

import pytest
import sweep_fns

from neurowalk.runners.local import WorkerDiedError, run_unordered
from neurowalk.runners.specs import grid, spec_key
from neurowalk.runners.store import ResultStore
from neurowalk.runners.sweep import run_sweep
from neurowalk.sim.episode import EpisodeConfig

SPECS = grid({"arena": "open", "steps": 30}, seed=list(range(6)))


def _sweep(store, specs=SPECS, **kw):
    return run_sweep(specs, store, progress=False, **{"fn": sweep_fns.cheap, **kw})


def test_resume_skips_done_runs_and_dedups(tmp_path):
    with ResultStore(tmp_path / "r.sqlite") as st:
        r = _sweep(st, [*SPECS[:4], dict(reversed(SPECS[0].items()))])  # a repeat in another key order
        assert (r.total, r.unique, r.duplicates, r.ok, r.error, r.skipped) == (5, 4, 1, 4, 0, 0)
        before = {row["key"]: row["finished_at"] for row in st.rows()}
        r = _sweep(st, workers=2)
        assert (r.skipped, r.ok, r.error) == (4, 2, 0)
        rows = st.rows()
        assert len(rows) == 6 and {row["key"] for row in rows} == {spec_key(s) for s in SPECS}
        assert all(before[row["key"]] == row["finished_at"] for row in rows if row["key"] in before)  # not rerun
        r = _sweep(st)
        assert (r.skipped, r.ok) == (6, 0)


def test_a_failing_run_is_an_error_row_and_the_rest_goes_on(tmp_path):
    with ResultStore(tmp_path / "r.sqlite") as st:
        r = _sweep(st, fn=sweep_fns.fail_on_seed_3, workers=2)
        assert (r.ok, r.error) == (5, 1)
        (f,) = r.failures
        assert f.error == "ValueError: seed 3 is cursed" and f.spec["seed"] == 3 and f.key == spec_key(SPECS[3])
        assert "seed=3" in f.line() and f.line().startswith(f.key[:12])
        (row,) = st.rows("error")
        assert row["result"] is None and row["error"] == "ValueError: seed 3 is cursed"
        r = _sweep(st)  # a rerun retries only the failed run, and replaces its row
        assert (r.skipped, r.ok, r.error) == (5, 1, 0) and len(st) == 6 and st.counts()["error"] == 0


def test_a_dead_worker_costs_only_its_own_run(tmp_path):
    with ResultStore(tmp_path / "r.sqlite") as st:
        r = _sweep(st, fn=sweep_fns.die_on_seed_2, workers=2)
        assert (r.ok, r.error) == (5, 1)
        assert r.failures[0].spec["seed"] == 2 and r.failures[0].error.startswith("WorkerDiedError")
        assert {k: v["seed"] for k, v in st.results().items()} == {
            spec_key(s): s["seed"] for s in SPECS if s["seed"] != 2
        }


def test_a_result_that_is_not_a_dict_is_an_error(tmp_path):
    with ResultStore(tmp_path / "r.sqlite") as st:
        r = _sweep(st, SPECS[:2], fn=sweep_fns.not_a_dict, workers=1)
        assert r.error == 2 and "must be a dict" in r.failures[0].error


def test_bad_arguments_raise_before_any_run(tmp_path):
    with ResultStore(tmp_path / "r.sqlite") as st:
        for kw in ({"backend": "dask"}, {"workers": 0}, {"address": "auto"}):
            with pytest.raises(ValueError):
                _sweep(st, **kw)
        with pytest.raises(ValueError, match="maze"):
            _sweep(st, [*SPECS, {"arena": "maze"}])
        assert len(st) == 0


def test_physics_rows_are_the_same_for_one_and_two_workers(tmp_path):
    specs = grid({"arena": "open", "steps": 30}, controller=["plastic", "static"], seed=[0, 1])
    rows = []
    for workers in (1, 2):
        with ResultStore(tmp_path / f"w{workers}.sqlite") as st:
            r = run_sweep(specs, st, workers=workers, progress=False)
            assert (r.ok, r.error) == (4, 0)
            rows.append(st.results())
            assert all(row["wall_time_s"] > 0 for row in st.rows())
    assert rows[0] == rows[1] and len(rows[0]) == 4
    one = next(iter(rows[0].values()))
    assert "wall_time_s" not in one and "real_time_factor" not in one and one["steps"] == 30
    assert len({tuple(v["final_pose"]) for v in rows[0].values()}) == 4  # the runs differ from each other


def test_run_unordered_reports_exceptions_and_deaths():
    items = [EpisodeConfig.from_spec({"seed": s, "steps": 1}).spec() for s in range(5)]
    done = sorted(run_unordered(sweep_fns.die_on_seed_2, items, workers=2), key=lambda d: d.index)
    assert [d.index for d in done] == list(range(5))
    assert isinstance(done[2].error, WorkerDiedError) and done[2].wall_time_s is None
    assert all(d.error is None and d.value["seed"] == d.index and d.wall_time_s >= 0 for d in done if d.index != 2)


def test_a_batch_keeps_input_order_and_names_its_first_failure(tmp_path):
    """run_all, the one runner on a store: results in the configs' order; a failed run named in one line, the
    finished ones kept in the folder's store (none where the store was a temporary one)."""
    from neurowalk.experiments.study_runs import RunsFailedError, run_all, store_path

    cfgs = [EpisodeConfig(steps=20, seed=s) for s in (2, 0, 1)]
    out = run_all(cfgs, workers=2, progress=False)
    assert [r.seed for r in out] == [2, 0, 1] and [r.config for r in out] == cfgs
    bad = [EpisodeConfig(steps=20), EpisodeConfig(steps=20, arena="box", arena_opts={"distance": -5.0})]
    with pytest.raises(RunsFailedError, match="1 runs failed, the first with ValueError: arena 'box': distance") as e:
        run_all(bad, workers=2, progress=False)
    assert e.value.store is None and "kept" not in str(e.value)
    with pytest.raises(RunsFailedError, match="finished runs are kept in") as e:
        run_all(bad, workers=2, progress=False, folder=tmp_path)
    assert e.value.store == store_path(tmp_path) and len(ResultStore(store_path(tmp_path)).done_keys()) == 1


def test_retries_are_a_whole_number_at_least_0(tmp_path):
    with ResultStore(tmp_path / "r.sqlite") as st:
        for bad in (-1, 0.5):
            with pytest.raises(ValueError, match="retries"):
                _sweep(st, retries=bad)
