"""The local pool: each worker's job is known, so a death costs that job only, and an early stop leaves no worker."""

from __future__ import annotations

import os
import signal
import time
from pathlib import Path

import pytest
import sweep_fns

from neurowalk.runners import local


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def _kids() -> list[int]:
    me = str(os.getpid())
    out = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            if stat.read_text().rsplit(")", 1)[1].split()[1] == me:
                out.append(int(stat.parent.name))
        except OSError:
            continue
    return [p for p in out if _alive(p)]


def _no_new_children(before: set[int]) -> bool:
    deadline = time.monotonic() + 2  # a killed worker is reaped by its driver at once; allow the kernel a moment
    while set(_kids()) - before and time.monotonic() < deadline:
        time.sleep(0.02)
    return not set(_kids()) - before


@pytest.mark.skipif(not os.path.isdir("/proc"), reason="reads /proc")
def test_closing_early_kills_and_reaps_the_busy_workers_at_once():
    before = set(_kids())
    items = [{"seed": 0, "steps": 1, "sleep": 0}] + [{"seed": s, "steps": 1, "sleep": 60} for s in range(1, 4)]
    gen = local.run_unordered(sweep_fns.slow, items, workers=2)
    assert next(gen).index == 0  # the other worker sleeps in its job, and the first took the next one
    t0 = time.monotonic()
    gen.close()
    assert time.monotonic() - t0 < 5
    assert _no_new_children(before)


@pytest.mark.skipif(not os.path.isdir("/proc"), reason="reads /proc")
def test_an_interrupt_while_waiting_leaves_no_worker():
    before = set(_kids())
    items = [{"seed": s, "steps": 1, "sleep": 60} for s in range(4)]

    def interrupt(signum, frame):
        raise KeyboardInterrupt

    old = signal.signal(signal.SIGALRM, interrupt)
    signal.setitimer(signal.ITIMER_REAL, 0.5)
    t0 = time.monotonic()
    try:
        with pytest.raises(KeyboardInterrupt):
            list(local.run_unordered(sweep_fns.slow, items, workers=2))
    finally:
        signal.signal(signal.SIGALRM, old)
    assert time.monotonic() - t0 < 5
    assert _no_new_children(before)


def test_workers_ignore_sigint_and_sigterm():
    items = [{"seed": s, "steps": 1, "sleep": 0.5} for s in range(2)]
    before = set(_kids())
    gen = local.run_unordered(sweep_fns.slow, items, workers=2)
    sent = []

    def poke(signum, frame):  # the process group's Ctrl-C, as a terminal sends it, reaches the workers too
        for pid in set(_kids()) - before:
            os.kill(pid, signal.SIGINT)
            os.kill(pid, signal.SIGTERM)
            sent.append(pid)

    old = signal.signal(signal.SIGALRM, poke)
    signal.setitimer(signal.ITIMER_REAL, 0.25)
    try:
        done = list(gen)
    finally:
        signal.signal(signal.SIGALRM, old)
    assert sent and all(d.error is None for d in done) and sorted(d.index for d in done) == [0, 1]


def test_an_item_or_result_that_cannot_be_pickled_is_that_jobs_error():
    items = [{"seed": 0, "steps": 1}, {"seed": 1, "steps": 1, "bad": lambda: 0}, {"seed": 2, "steps": 1}]
    done = {d.index: d for d in local.run_unordered(sweep_fns.cheap, items, workers=2)}
    assert sorted(done) == [0, 1, 2] and done[1].error is not None
    assert done[0].error is None and done[2].error is None


def _run(tmp_path, retries: int, once: bool) -> tuple[list[local.JobResult], list[str]]:
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
