"""``neurowalk bench``: every figure is a measured rate or a ratio to a baseline of the same run."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

from neurowalk.cli import main


def test_bench_writes_rates_and_ratios(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["bench", "--quick", "--workers", "2", "--out", str(tmp_path)]) == 0
    b = json.loads((tmp_path / "bench.json").read_text())
    phys, sur = b["physics"], b["surrogate"]
    assert phys["control_steps_per_s"] > 0 and phys["bare_mj_step_per_s"] > phys["control_steps_per_s"]
    ratio = b["surrogate_vs_physics"]["one_process"]
    assert ratio == pytest.approx(sur["env_steps_per_s_one_process"] / phys["control_steps_per_s"])
    assert ratio > 10  # a planar body with a compiled loop must be far faster than physics
    for k in ("nthread_1", "nthread_2"):
        assert b["batch_physics"][k]["batch_physics_steps_per_s"] > 0 and b["batch_physics"][k]["speedup"] > 0
    loop = b["closed_loop_vs_bare"]
    ratio = loop["closed_loop_wall_s"] / loop["bare_mj_step_wall_s"]
    assert loop["ratio_closed_loop_over_bare"] == pytest.approx(ratio) and ratio > 0
    ps = b["physics_settings"]  # the adopted physics against the former, on the same run
    assert ps["adopted_over_former"] == pytest.approx(
        ps["control_steps_per_s_adopted"] / ps["control_steps_per_s_former"]
    )
    assert ps["former_body_opts"]["integrator"] == "implicitfast" and ps["control_steps_per_s_former"] > 0
    e2e = b["surrogate_end_to_end"]
    assert 0 < e2e["env_steps_per_s_end_to_end"] < e2e["env_steps_per_s_in_loop"]  # the loop is part of the whole
    assert e2e["end_to_end_over_in_loop"] == pytest.approx(e2e["ms_per_run_in_loop"] / e2e["ms_per_run_end_to_end"])
    pool = b["surrogate_pool"]
    assert pool["workers"] == 2 and pool["speedup"] == pytest.approx(pool["one_process_wall_s"] / pool["pool_wall_s"])
    busy = b["busy_core"]  # the same parallel figures with one core held by another process
    rates = [busy["batch_physics"][k]["batch_physics_steps_per_s"] for k in ("nthread_1", "nthread_2")]
    assert min(rates) > 0 and busy["batch_physics"]["nthread_2_over_1"] == pytest.approx(rates[1] / rates[0])
    assert busy["surrogate_pool"]["workers"] == 2 and busy["surrogate_pool"]["speedup"] > 0
    assert "bench.json" in capsys.readouterr().out


def test_busy_core_holds_a_core_while_the_block_runs() -> None:
    import os
    import time

    from neurowalk.experiments.bench import busy_core

    # The child spins while the block runs: its CPU time is there once it is reaped. On a loaded machine (the
    # suite's other worker) it gets a share of a core only, so the blocks repeat until 0.3 s of CPU is seen.
    c0, used = os.times(), 0.0
    for _ in range(8):
        t0 = time.perf_counter()
        with busy_core():
            time.sleep(0.5)
        assert time.perf_counter() - t0 < 5  # the block ends with its body: the child is stopped and reaped
        c1 = os.times()
        used = c1.children_user + c1.children_system - c0.children_user - c0.children_system
        if used > 0.3:
            break
    assert used > 0.3


@pytest.mark.parametrize("bad", ["0,4", "1,x", ""])
def test_bench_rejects_bad_worlds(bad: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["bench", "--engine", "warp", "--worlds", bad, "--out", "/tmp/never"]) == 2
    assert "--worlds" in capsys.readouterr().err


def test_bench_rejects_zero_workers(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["bench", "--workers", "0", "--out", "/tmp/never"]) == 2
    assert capsys.readouterr().err.count("\n") == 1


def test_run_on_the_surrogate_writes_the_same_files(tmp_path: Path) -> None:
    args = ["run", "--arena", "narrow-passage", "--body", "surrogate", "--steps", "5000", "--quiet", "--out"]
    assert main([*args, str(tmp_path)]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["body"] == "surrogate" and s["escaped"] is True
    assert (tmp_path / "run.png").is_file() and (tmp_path / "trajectory.npz").is_file()


def test_surrogate_has_no_video_and_calibrate_needs_a_worker(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", "--body", "surrogate", "--video", "--out", "/tmp/never"]) == 2
    assert main(["calibrate", "--workers", "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and "--video needs a MuJoCo body" in err[0] and "--workers" in err[1]


@pytest.mark.parametrize("script", sorted(p.name for p in (Path(__file__).parents[2] / "benchmarks").glob("*.py")))
def test_benchmark_scripts_import(script: str) -> None:
    """Every script in benchmarks/ imports against today's package (a renamed or removed name breaks it here,
    not months later when someone measures)."""
    path = Path(__file__).parents[2] / "benchmarks" / script
    spec = importlib.util.spec_from_file_location(f"bench_{path.stem}", path)
    assert spec is not None and spec.loader is not None
    spec.loader.exec_module(importlib.util.module_from_spec(spec))


def test_lockstep_rates_split_a_world_step_into_host_and_physics():
    """The lock-step benchmark's rows (mujoco.batch, one shared arena): rates from the timed run, and the host's
    microseconds per world-step the sum of its parts."""
    from neurowalk.experiments.bench import lockstep_rates

    r = lockstep_rates((1, 3), steps=2, engine="mujoco.batch", arena="box", progress=False)
    assert r["engine"] == "mujoco.batch" and r["device_name"].startswith("cpu")
    assert [row["worlds"] for row in r["rows"]] == [1, 3]
    for row in r["rows"]:
        assert row["control_steps_per_s"] == pytest.approx(row["worlds"] * row["control_steps"] / row["wall_s"])
        parts = row["sense_us"] + row["controllers_us"] + row["record_us"]
        assert row["host_us"] == pytest.approx(parts) and min(row["physics_us"], parts) > 0
        assert 0 < row["noise_draw_us"] < row["sense_us"]  # a block's draw shared by its 256 steps
        assert row["host_us_this_run"] > row["host_us"]  # a 2-step run paid a whole block
        assert row["physics_share"] == pytest.approx(row["physics_us"] / (row["physics_us"] + row["host_us_this_run"]))


def test_the_convergence_benchmark_judges_its_committed_result_as_committed() -> None:
    """docs/benchmarks/convergence.json is what bench_convergence.py's rules say of its numbers: the adopted physics
    converges, the former does not (its 60 s walk is too far at 10 ms), and a count agrees with another where the
    share of either lies inside the other's 95% interval (20/20 against 19/20 does; 20/20 against 12/20 does not)."""
    from neurowalk.body.registry import body_settings

    path = Path(__file__).parents[2] / "benchmarks" / "bench_convergence.py"
    spec = importlib.util.spec_from_file_location("bench_convergence", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)  # type: ignore[union-attr]
    done = json.loads((path.parents[1] / "docs" / "benchmarks" / "convergence.json").read_text())
    for p in done["physics"].values():
        assert mod.verdict(p["measured"], p["reference"]) == {"checks": p["checks"], "converged": p["converged"]}
    assert done["physics"]["adopted"]["converged"] and not done["physics"]["before"]["converged"]
    assert not done["physics"]["before"]["checks"]["forward_60s"]["holds"]
    assert done["physics"]["adopted"]["body_opts"] == mod.PHYSICS["adopted"] == body_settings("amosii")  # the defaults

    def count(k: int) -> dict:
        return {"runs": 20, "n": k, "95ci": list(mod.wilson(k, 20))}

    assert mod.compatible(count(20), count(19), "n") and mod.compatible(count(19), count(20), "n")
    assert not mod.compatible(count(20), count(12), "n")
