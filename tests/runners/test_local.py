"""The local pool: a pool that breaks under a submit loses no job (the cause of a once-flaky sweep test)."""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool

import sweep_fns

from neurowalk.runners import local


class _BreaksOnThirdSubmit(ProcessPoolExecutor):
    """The first pool made refuses its third submit, as a pool whose worker just died does."""

    made = 0

    def __init__(self, *a, **kw):
        super().__init__(*a, **kw)
        type(self).made += 1
        self._first = type(self).made == 1
        self._submits = 0

    def submit(self, *a, **kw):
        self._submits += 1
        if self._first and self._submits == 3:
            raise BrokenProcessPool("a worker died")
        return super().submit(*a, **kw)


def test_a_submit_into_a_broken_pool_requeues_the_job(monkeypatch):
    monkeypatch.setattr(local, "ProcessPoolExecutor", _BreaksOnThirdSubmit)
    items = [{"seed": s, "steps": 1} for s in range(6)]
    done = list(local.run_unordered(sweep_fns.cheap, items, workers=2))
    assert sorted(d.index for d in done) == list(range(6))
    assert all(d.error is None for d in done)
    assert _BreaksOnThirdSubmit.made >= 2  # the rest ran on a fresh pool


def _run(tmp_path, retries: int, once: bool) -> tuple[list[local.Done], list[str]]:
    log = tmp_path / "log"
    items = [{"seed": s, "steps": 1, "log": str(log), "once": once} for s in range(6)]
    done = list(local.run_unordered(sweep_fns.die_counting, items, workers=2, retries=retries))
    assert sorted(d.index for d in done) == list(range(6))  # every job reported once
    return done, log.read_text().split()


def test_a_dead_workers_job_is_reported_not_rerun(tmp_path):
    done, starts = _run(tmp_path, retries=0, once=True)
    errors = {d.index: d.error for d in done if d.error is not None}
    assert list(errors) == [2] and isinstance(errors[2], local.WorkerDiedError)
    assert starts.count("2") == 1  # not rerun, though it would succeed now


def test_retries_run_a_dead_workers_job_again_at_most_that_often(tmp_path):
    (tmp_path / "flaky").mkdir()
    done, starts = _run(tmp_path / "flaky", retries=1, once=True)
    assert all(d.error is None for d in done) and starts.count("2") == 2  # died once, then ran
    (tmp_path / "always").mkdir()
    done, starts = _run(tmp_path / "always", retries=1, once=False)
    assert [d.index for d in done if d.error is not None] == [2] and starts.count("2") == 2
    assert "2 times" in str(next(d.error for d in done if d.error is not None))
