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
