"""MuJoCo Warp conformance on Warp's CPU device: the same model, sensors and loop as CPU MuJoCo, within float32.

Tolerances: Warp computes in float32, MuJoCo in float64. Over the first control steps (20 physics steps each) the
joint positions agree within 1e-4 rad / m; rangefinder readings at the same state within 1e-4 m, foot contact
the same on/off. After that two contact-rich runs drift apart, so longer runs are compared by outcome (README).
Marked ``warp``: CI runs them in a step of their own, with the warp extra installed.
"""

import os
import sys
from dataclasses import replace

import mujoco
import numpy as np
import pytest

from neurowalk.body.obstacle_slots import slot_rows, slot_world
from neurowalk.sim.episode import EngineOptions, EpisodeConfig, Streaming, build, run_episode

TILTED = EpisodeConfig(arena="box", arena_opts={"distance": 0.38, "angle": 30.0}, controller="fixed", steer=(-1, -1),
                       steps=25, seed=7, engine="warp", noise=0.0)  # fmt: skip
RANDOM = EpisodeConfig(arena="random", arena_opts={"n_boxes": 12, "extent": 3.0}, steps=25, seed=1, engine="warp")
QPOS_TOL = 1e-4  # rad / m over the first 25 control steps
US_TOL = 1e-4  # m, rangefinder at the same state


def test_slot_rows_are_the_compiled_obstacle_geoms():
    """Each world's obstacle rows (computed, not compiled) equal those MuJoCo compiles for that arena."""
    from neurowalk.arenas import make_arena
    from neurowalk.body.amosii_mjcf import amosii_xml
    from neurowalk.body.amosii_params import BodyParams

    for arena in (make_arena("difficult"), make_arena("random", rng=np.random.default_rng(3)), make_arena("box")):
        m = mujoco.MjModel.from_xml_string(amosii_xml(BodyParams(), world=slot_world(arena, 30)))
        ids = [m.geom(f"obstacle_{k}").id for k in range(30)]
        rows = slot_rows(arena, 30)
        for f in ("pos", "quat", "size", "aabb", "rbound"):
            np.testing.assert_allclose(getattr(m, f"geom_{f}")[ids], rows[f], atol=1e-12, err_msg=f)
        assert np.all(m.geom_bodyid[ids] == 0)  # all world geoms: one structure for every arena


def test_a_slot_differs_from_an_obstacle_only_in_what_warp_batches_per_world():
    """World 0's model gives every world its slots' other fields: a parked slot must be an obstacle like the
    others (seen by rays, the same friction and contact settings), or another world's box in it is not."""
    from neurowalk.arenas import make_arena
    from neurowalk.body.amosii_mjcf import amosii_xml
    from neurowalk.body.amosii_params import BodyParams

    m = mujoco.MjModel.from_xml_string(amosii_xml(BodyParams(), world=slot_world(make_arena("box"), 4)))
    ids = [m.geom(f"obstacle_{k}").id for k in range(4)]  # one box, three parked slots
    batched = {f"geom_{f}" for f in ("pos", "quat", "size", "aabb", "rbound")}
    fields = [f for f in dir(m) if f.startswith("geom_") and f not in batched and isinstance(getattr(m, f), np.ndarray)]
    assert {"geom_rgba", "geom_friction", "geom_contype", "geom_conaffinity", "geom_solref"} <= set(fields)
    for f in fields:
        rows = getattr(m, f)[ids]
        assert all(np.array_equal(r, rows[0]) for r in rows), f
    assert m.geom_rgba[ids[0], 3] > 0


def test_engine_is_a_config_field_checked_where_made():
    """A config names its engine; what bodies an engine runs is the body table's, checked when the config is made."""
    with pytest.raises(ValueError, match="unknown engine 'gpu'"):
        EpisodeConfig(engine="gpu")
    with pytest.raises(ValueError, match="engine 'warp' runs body 'amosii'"):
        EpisodeConfig(engine="warp", body="wheeled")
    with pytest.raises(ValueError, match="climbing"):
        EpisodeConfig(engine="warp", reflexes=True)


def test_a_missing_extra_names_what_to_install(monkeypatch):
    from neurowalk.sim import warp_engine

    monkeypatch.setitem(sys.modules, "mujoco_warp", None)  # import fails as if not installed
    with pytest.raises(ValueError, match=r"pip install -e '\.\[warp\]'"):
        warp_engine.import_warp()


def test_cli_without_the_extra_exits_2_with_one_line(monkeypatch, capsys, tmp_path):
    from neurowalk.cli import main

    monkeypatch.setitem(sys.modules, "mujoco_warp", None)
    assert main(["run", "--engine", "warp", "--steps", "2", "--out", str(tmp_path / "r")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "pip install -e '.[warp]'" in err[0]


warp = pytest.mark.warp


@pytest.fixture(scope="module")
def wp_device():
    """The Warp device the tests run on: ``NEUROWALK_TEST_DEVICE`` (``cpu``, the default, or ``cuda`` on a GPU
    machine: the same tests hold on both)."""
    pytest.importorskip("mujoco_warp")
    from neurowalk.sim.warp_engine import resolve_device

    return resolve_device(os.environ.get("NEUROWALK_TEST_DEVICE", "cpu"))


@warp
def test_worlds_follow_cpu_mujoco(wp_device):
    """Two worlds with different arenas and controllers: each within float32 of its CPU MuJoCo run."""
    from neurowalk.sim.warp_engine import run_warp

    eps = run_warp([TILTED, RANDOM], device=wp_device, progress=False)
    for cfg, ep in zip((TILTED, RANDOM), eps, strict=True):
        ref = run_episode(replace(cfg, engine="mujoco"))
        dq = np.abs(ep.trajectory.qpos - ref.trajectory.qpos).max()
        assert dq < QPOS_TOL, (cfg.arena, dq)
        np.testing.assert_allclose(ep.trajectory.t, ref.trajectory.t, atol=1e-9)
        assert ep.summary["engine"] == "warp" and ep.summary["device"] == wp_device
        assert ep.summary["steps"] == cfg.steps


@warp
def test_worlds_are_independent_and_runs_repeat(wp_device):
    """A world's run does not depend on the other worlds, and the same configs give the same numbers (a rerun, bit
    for bit): MuJoCo Warp's deterministic execution is on."""
    from neurowalk.sim.warp_engine import WarpWorlds, run_warp

    alone = run_warp([RANDOM], device=wp_device, progress=False)[0]
    again = run_warp([RANDOM], device=wp_device, progress=False)[0]
    pair = run_warp([TILTED, RANDOM], device=wp_device, progress=False)[1]
    for other in (again, pair):
        np.testing.assert_array_equal(alone.trajectory.qpos, other.trajectory.qpos)
        np.testing.assert_array_equal(alone.trajectory.outputs, other.trajectory.outputs)
    import mujoco_warp

    assert WarpWorlds([RANDOM], device=wp_device).wmodel.opt.deterministic == mujoco_warp.DeterminismType.ALL


@warp
def test_sensors_equal_at_the_same_states(wp_device):
    """Rangefinders and foot contacts of Warp and CPU MuJoCo at the same states (a robot walking into a tilted
    box, seen by both rays, feet on and off the ground)."""
    import mujoco_warp as mjw
    import warp as wp

    from neurowalk.body.amosii_sensors import sensor_layout
    from neurowalk.sim.warp_engine import WarpWorlds

    cfg = replace(TILTED, steps=100, engine="mujoco")
    ref = run_episode(cfg)
    rows = [20, 60, 80, 99]  # walking, nearing the box (rays on it), touching it (first contact at 71)
    runs = WarpWorlds([replace(cfg, engine="warp")], device=wp_device)
    runs.reset_physics()
    _, body, _ = build(cfg)
    lay = sensor_layout(body.model)
    for k in rows:
        qpos = ref.trajectory.qpos[k]
        body.data.qpos[:] = qpos
        body.data.ctrl[:] = ref.trajectory.targets[k]
        mujoco.mj_forward(body.model, body.data)
        with wp.ScopedDevice(wp_device):
            runs.wdata.qpos.assign(qpos[None].astype(np.float32))
            runs.wdata.qvel.zero_()
            runs.wdata.ctrl.assign(ref.trajectory.targets[k][None].astype(np.float32))
            mjw.forward(runs.wmodel, runs.wdata)
        sd = runs.wdata.sensordata.numpy()[0]
        us_cpu, us_warp = body.data.sensordata[lay.us], sd[lay.us]
        assert np.all((us_cpu < 0) == (us_warp < 0)), k  # no echo (-1) on the same rays
        seen = us_cpu >= 0
        np.testing.assert_allclose(us_warp[seen], us_cpu[seen], atol=US_TOL, err_msg=f"row {k}")
        touch_cpu, touch_warp = body.data.sensordata[lay.touch] > 0, sd[lay.touch] > 0
        np.testing.assert_array_equal(touch_warp, touch_cpu, err_msg=f"row {k}")
    assert any((ref.trajectory.us_distance[k] < 0.4).any() for k in rows)  # the rays did see the box


@warp
def test_a_world_sees_its_boxes_in_slots_another_world_leaves_empty(wp_device):
    """World 0 has no box, world 1 a box ahead in slot 0: world 1's rays read it as CPU MuJoCo does (a slot that
    world 0 parks once made it invisible to every world, and the robot walked into unseen walls)."""
    import mujoco_warp as mjw
    import warp as wp

    from neurowalk.body.amosii_sensors import sensor_layout
    from neurowalk.sim.warp_engine import WarpWorlds

    near = replace(TILTED, arena_opts={"distance": 0.3, "angle": 0.0}, engine="mujoco")
    _, body, _ = build(near)
    lay = sensor_layout(body.model)
    mujoco.mj_forward(body.model, body.data)
    body.reset(np.random.default_rng(0))
    us_cpu = body.data.sensordata[lay.us].copy()
    assert np.all((us_cpu >= 0) & (us_cpu < 0.4))  # both rays see the box from the start pose
    runs = WarpWorlds([replace(near, arena="open", arena_opts={}, engine="warp"), replace(near, engine="warp")],
                        device=wp_device)  # fmt: skip
    runs.reset_physics()
    with wp.ScopedDevice(wp_device):
        mjw.forward(runs.wmodel, runs.wdata)
    sd = runs.wdata.sensordata.numpy()
    np.testing.assert_allclose(sd[1, lay.us], us_cpu, atol=US_TOL)
    assert not np.any((sd[0, lay.us] >= 0) & (sd[0, lay.us] < 0.4))  # world 0's rays see nothing in range


@warp
def test_bad_devices_exit_2(wp_device, capsys, tmp_path):
    import warp as wp

    from neurowalk.cli import main

    assert main(["run", "--engine", "warp", "--device", "tpu", "--out", str(tmp_path / "a")]) == 2
    assert "unknown device 'tpu'" in capsys.readouterr().err
    if wp.get_cuda_device_count() == 0:
        assert main(["run", "--engine", "warp", "--device", "cuda", "--out", str(tmp_path / "b")]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "no CUDA GPU" in err[0]


@warp
def test_a_sweep_runs_warp_specs_as_worlds_of_one_model(wp_device, tmp_path, monkeypatch):
    """Specs on engine 'warp' go to one Warp model, the others to the pool; each stored result is its run's."""
    from neurowalk.runners.specs import result_of, spec_key
    from neurowalk.runners.store import ResultStore
    from neurowalk.runners.sweep import run_sweep

    specs = [{"arena": "box", "steps": 8, "seed": s, "engine": "warp"} for s in (0, 1)]
    specs.append({"arena": "box", "steps": 8, "seed": 0})
    with ResultStore(tmp_path / "r.sqlite") as store:
        report = run_sweep(specs, store, workers=1, progress=False, options=EngineOptions(device=wp_device))
        results = store.results()
    assert report.ok == 3 and report.error == 0
    for s in specs:
        cfg = EpisodeConfig(arena="box", steps=8, seed=s["seed"], engine=s.get("engine", "mujoco"))
        expect = result_of(run_episode(cfg))
        got = results[spec_key(EpisodeConfig.from_spec(s).spec())]
        assert got["final_pose"] == pytest.approx(expect["final_pose"], abs=1e-9)
    assert results[spec_key(EpisodeConfig.from_spec(specs[0]).spec())]["engine"] == "warp"
    assert "engine" not in results[spec_key(EpisodeConfig.from_spec(specs[2]).spec())]


@warp
def test_a_study_keeps_its_warp_runs_and_their_terms_in_its_store(wp_device, tmp_path, monkeypatch):
    """A study's runs on engine 'warp' are the worlds of shared calls and kept like the pool's, terms and all: its
    store holds them, and the same call again runs none (what fig3/fig5 with --engine warp resume and share)."""
    from neurowalk.experiments.study_runs import run_store
    from neurowalk.experiments.suites.long_runs import LONG
    from neurowalk.experiments.suites.real_robot import PATH
    from neurowalk.runners.store import ResultStore
    from neurowalk.sim import warp_engine

    runs = [(EpisodeConfig(arena="box", steps=8, seed=s, engine="warp"), (PATH,)) for s in (0, 1)]
    runs.append((EpisodeConfig(arena="box", steps=12, seed=0, engine="warp"), (LONG,)))
    first = run_store(runs, tmp_path, 1, options=EngineOptions(device=wp_device))
    assert [len(r["kept"]["path"]["path"]) for r in first[:2]] == [2, 2]  # rows 0 and the last (7)
    assert list(first[2]["kept"]["long"]["step"]) == [0, 10, 11] and first[0]["engine"] == "warp"
    with ResultStore(tmp_path / "results.sqlite") as store:
        assert len(store) == 3
    monkeypatch.setattr(warp_engine.WarpWorlds, "advance", lambda *a: pytest.fail("a stored run ran again"))
    again = run_store(runs, tmp_path, 1, options=EngineOptions(device=wp_device))
    assert [r["final_pose"] for r in again] == [r["final_pose"] for r in first]


@warp
def test_bench_measures_warp_beside_nothing_else_it_needs(wp_device):
    """`neurowalk bench --engine warp`'s measurement: one row per number of worlds, rates from the timed run."""
    from neurowalk.experiments.bench import warp_rates

    r = warp_rates((1, 3), steps=1, device=wp_device, progress=False)
    assert r["device"] == wp_device and r["device_name"].startswith("cpu") == (wp_device == "cpu")
    assert [row["worlds"] for row in r["rows"]] == [1, 3]
    for row in r["rows"]:
        assert row["control_steps_per_s"] == pytest.approx(row["worlds"] * row["control_steps"] / row["wall_s"])
        assert row["physics_steps_per_s"] == pytest.approx(10 * row["control_steps_per_s"])  # 10 ms steps, 10 Hz


@warp
def test_the_runner_puts_warp_configs_into_one_model_and_keeps_the_order(wp_device, monkeypatch):
    from neurowalk.experiments.study_runs import run_all

    cfgs = [EpisodeConfig(arena="box", steps=6, seed=s, engine=e) for s, e in ((0, "warp"), (1, "mujoco"), (2, "warp"))]
    got = run_all(cfgs, workers=1, progress=False, options=EngineOptions(device=wp_device))
    for cfg, run in zip(cfgs, got, strict=True):
        assert list(run.final_pose) == run_episode(cfg).summary["final_pose"]
        assert run.config == cfg


@warp
def test_walking_and_turning_in_the_open_match_cpu_mujoco(wp_device):
    """No obstacles (no obstacle slots at all): Table 1's forward walk and left turn go as on CPU MuJoCo."""
    from neurowalk.sim.warp_engine import run_warp

    cfgs = [EpisodeConfig(arena="open", controller="fixed", steer=s, steps=150, engine="warp", noise=0.0)
            for s in ((-1.0, -1.0), (-1.0, 1.0))]  # fmt: skip
    for cfg, ep in zip(cfgs, run_warp(cfgs, device=wp_device, progress=False), strict=True):
        ref = run_episode(replace(cfg, engine="mujoco")).trajectory.pose
        np.testing.assert_allclose(ep.trajectory.pose, ref, atol=1e-3)


def test_figures_take_the_engine_where_they_can(capsys, tmp_path):
    from neurowalk.cli import main
    from neurowalk.experiments import FIGURES, Settings
    from neurowalk.experiments.study import resolve

    with pytest.raises(ValueError, match="--engine warp runs --body amosii, got --body 'surrogate'"):
        resolve(FIGURES["table2"], Settings(body="surrogate", engine="warp", out=tmp_path / "t"))
    assert main(["figure", "table2", "--engine", "warp", "--body", "surrogate", "--out", str(tmp_path / "a")]) == 2
    assert capsys.readouterr().err.strip().splitlines() == [
        "neurowalk: error: --engine warp runs --body amosii, got --body 'surrogate'"
    ]
    assert main(["figure", "fig6", "--engine", "warp", "--out", str(tmp_path / "b")]) == 2
    assert "takes no --engine" in capsys.readouterr().err


@warp
def test_a_stopped_warp_run_keeps_its_steps(wp_device, monkeypatch):
    from neurowalk.sim.config import RunInterruptedError
    from neurowalk.sim.warp_engine import WarpWorlds

    advance, calls = WarpWorlds.advance, []

    def stop_at_the_fourth(self):
        calls.append(1)
        if len(calls) == 4:
            raise KeyboardInterrupt
        advance(self)

    monkeypatch.setattr(WarpWorlds, "advance", stop_at_the_fourth)
    rows = []
    with pytest.raises(RunInterruptedError) as stop:
        run_episode(
            EpisodeConfig(arena="box", steps=10, engine="warp"),
            stream=Streaming(sink=lambda r, start: rows.append(len(r))),
            options=EngineOptions(device=wp_device),
        )
    assert stop.value.episode.summary["steps"] == 3 and stop.value.episode.summary["completed"] is False
    assert sum(rows) == 3  # the sink got every completed row


@warp
def test_warp_keeps_the_engine_contract(wp_device):
    from neurowalk.sim.check import check_engine
    from neurowalk.sim.engines import ENGINES

    check_engine(ENGINES["warp"], options=EngineOptions(device=wp_device), steps=6)
