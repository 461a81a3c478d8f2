"""The Ray backend: the same rows as the local pool, errors and dead workers recorded, the CLI path.

One local Ray instance (2 CPUs) serves the module: starting Ray takes seconds. Skipped only where ray is not
installed (the test extra installs it, so CI runs these).
"""

import json
import os
from pathlib import Path

import pytest

pytest.importorskip("ray")

import sweep_fns

from neurowalk.cli import main
from neurowalk.runners import ray_backend
from neurowalk.runners.specs import grid, spec_key
from neurowalk.runners.store import ResultStore
from neurowalk.runners.sweep import run_sweep

SPECS = grid({"arena": "open", "steps": 30}, seed=list(range(6)))


@pytest.fixture(scope="module")
def ray_2cpu():
    """A local Ray instance of 2 CPUs whose workers can import this folder's ``sweep_fns``."""
    here = str(Path(__file__).parent)
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("PYTHONPATH", os.pathsep.join(p for p in (here, os.environ.get("PYTHONPATH")) if p))
        started = ray_backend.start(workers=2)
    yield
    if started:
        ray_backend.stop()


def test_cli_ray_rows_equal_local_rows(ray_2cpu, tmp_path, capsys):
    import ray

    argv = ["sweep", "--controller", "plastic,static", "--seeds", "2", "--steps", "30", "--quiet"]
    assert main([*argv, "--backend", "ray", "--workers", "2", "--out", str(tmp_path / "ray")]) == 0
    assert main([*argv, "--workers", "1", "--out", str(tmp_path / "local")]) == 0
    with ResultStore(tmp_path / "ray" / "results.sqlite") as a, ResultStore(tmp_path / "local" / "results.sqlite") as b:
        assert a.results() == b.results() and len(a) == 4
    info = json.loads((tmp_path / "ray" / "sweep.json").read_text())
    assert info["settings"]["backend"] == "ray" and info["counts"]["ok"] == 4
    assert ray.is_initialized()  # the sweep did not start Ray, so it left it running


def test_ray_records_errors_and_dead_workers_and_goes_on(ray_2cpu, tmp_path):
    with ResultStore(tmp_path / "r.sqlite") as st:
        r = run_sweep(SPECS, st, backend="ray", fn=sweep_fns.fail_on_seed_3, progress=False)
        assert (r.ok, r.error) == (5, 1) and r.failures[0].error == "ValueError: seed 3 is cursed"
    with ResultStore(tmp_path / "d.sqlite") as st:
        r = run_sweep(SPECS, st, backend="ray", fn=sweep_fns.die_on_seed_2, progress=False)
        assert (r.ok, r.error) == (5, 1)
        assert r.failures[0].spec["seed"] == 2 and r.failures[0].error.startswith("WorkerDiedError")
        assert set(st.done_keys()) == {spec_key(s) for s in SPECS if s["seed"] != 2}
        r = run_sweep(SPECS, st, backend="ray", fn=sweep_fns.cheap, progress=False)  # resume: only the dead run
        assert (r.skipped, r.ok, r.error) == (5, 1, 0) and len(st) == 6
