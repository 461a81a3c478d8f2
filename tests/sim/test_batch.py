"""Many runs in one mujoco.batch: copy i is bit for bit the single loop's run of config i."""

import mujoco
import numpy as np
import pytest

from neurowalk.body.obstacle_slots import PARK_Z, PARKING_BODY
from neurowalk.sim.batch import MujocoBatchWorlds, run_batch
from neurowalk.sim.episode import EngineOptions, EpisodeConfig, build, run_episode, seeds
from neurowalk.sim.throughput import measure_throughput

STEPS = 100
FIELDS = ("t", "qpos", "pose", "inputs", "outputs", "b", "q", "targets", "joint_angles", "us_distance",
          "foot_contact", "up_z")  # fmt: skip
MACHINE = ("wall_time_s", "real_time_factor")
# The robot walks into these boxes within STEPS (first box contact at control step 86 and 71).
INTO_BOX = EpisodeConfig(arena="box", arena_opts={"distance": 0.28}, controller="fixed", steer=(-1, -1), steps=STEPS)
INTO_TILTED_BOX = EpisodeConfig(arena="box", arena_opts={"distance": 0.37, "angle": 30.0}, controller="fixed",
                                steer=(-1, -1), steps=STEPS, seed=7)  # fmt: skip
RANDOM = {"arena": "random", "steps": STEPS}
CONFIGS = [  # different seeds, box counts and controllers; one without sensor noise
    EpisodeConfig(**RANDOM, arena_opts={"n_boxes": 12, "extent": 3.0}, controller="plastic", seed=1),
    EpisodeConfig(**RANDOM, arena_opts={"n_boxes": 3}, controller="static", seed=2),
    EpisodeConfig(**RANDOM, arena_opts={"n_boxes": 20, "extent": 2.5}, controller="braitenberg", seed=3, noise=0.0),
    INTO_TILTED_BOX,
    EpisodeConfig(
        **RANDOM, arena_opts={"n_boxes": 12, "extent": 3.0}, controller="plastic", seed=4, variant="original"
    ),
]


def assert_same_run(a, b):
    for f in FIELDS:
        np.testing.assert_array_equal(getattr(a.trajectory, f), getattr(b.trajectory, f), err_msg=f)
    strip = lambda s: {k: v for k, v in s.items() if k not in MACHINE}  # noqa: E731
    assert strip(a.summary) == strip(b.summary)


@pytest.fixture(scope="module")
def singles():
    return [run_episode(cfg) for cfg in CONFIGS]


@pytest.fixture(scope="module")
def batch():
    be = MujocoBatchWorlds(CONFIGS, nthread=2)
    return be, be.run()


@pytest.mark.parametrize("cfg", [INTO_BOX, INTO_TILTED_BOX, CONFIGS[0]], ids=["box", "tilted-box", "random"])
def test_padded_model_runs_bit_for_bit_like_the_plain_model(cfg):
    plain = run_episode(cfg)
    n = len(plain.arena.boxes)
    assert_same_run(plain, run_episode(cfg, options=EngineOptions(pad_boxes=n)))
    assert_same_run(plain, run_episode(cfg, options=EngineOptions(pad_boxes=n + 6)))


def first_box_contact(cfg):
    """Control step at which the robot first touches ``obstacle_0`` (None: never within cfg.steps)."""
    _, body, ctrl = build(cfg)
    body.reset(seeds(cfg)[0])
    ctrl.reset(seeds(cfg)[1])
    box = body.model.geom("obstacle_0").id
    for k in range(cfg.steps):
        body.apply(ctrl.act(body.observe()))
        for _ in range(body.n_substeps):
            mujoco.mj_step(body.model, body.data)
            if any(box in c.geom for c in body.data.contact[: body.data.ncon]):
                return k
    return None


def test_robot_touches_the_box_in_the_collision_runs():
    # the contact must really happen within the compared steps, or the collision checks prove nothing
    assert first_box_contact(INTO_BOX) < STEPS - 5
    assert first_box_contact(INTO_TILTED_BOX) < STEPS - 20


def test_each_copy_equals_the_single_loop_bit_for_bit(singles, batch):
    be, episodes = batch
    assert be.controllers.compiled
    assert be.max_boxes == max(len(s.arena.boxes) for s in singles)
    for single, ep in zip(singles, episodes, strict=True):
        assert ep.config == single.config and ep.arena == single.arena
        assert_same_run(single, ep)
        assert ep.summary["completed"] is True and ep.summary["steps_requested"] == STEPS


def test_copies_differ(batch):
    _, episodes = batch
    finals = {tuple(ep.trajectory.qpos[-1]) for ep in episodes}
    assert len(finals) == len(episodes)
    assert np.isnan(episodes[3].trajectory.b).all() and not np.isnan(episodes[0].trajectory.b).any()


@pytest.mark.parametrize("opts", [{"nthread": 1}, {"nthread": 2, "persistent": True}, {"compiled": False},
                                  {"max_boxes": 30}])  # fmt: skip
def test_threads_memory_controller_path_and_padding_do_not_change_a_bit(batch, opts):
    _, ref = batch
    configs = CONFIGS[:2]
    other = MujocoBatchWorlds(configs, **opts)
    for a, b in zip(ref[:2], other.run(), strict=True):
        assert_same_run(a, b)
    if "compiled" in opts:
        assert not other.controllers.compiled


def test_worlds_of_one_arena_share_its_model_and_run_as_alone():
    """A seed sweep in one arena builds one model for all its worlds (16,384 worlds need not build 16,384), and
    each world is still its single run, bit for bit (noise strengths and controllers of its own)."""
    configs = [
        INTO_BOX.replace(seed=0),
        INTO_BOX.replace(seed=1, controller="plastic", steer=None),
        INTO_BOX.replace(seed=2, noise=0.0),
        INTO_TILTED_BOX,
    ]
    be = MujocoBatchWorlds(configs, nthread=2)
    assert len({id(m) for m in be.models}) == 2 and be.models[0] is be.models[2]  # two arenas, two models
    for cfg, ep in zip(configs, be.run(), strict=True):
        assert_same_run(run_episode(cfg), ep)


def test_padded_models_share_sizes_and_park_out_of_reach(batch):
    be, _ = batch
    sizes = {(m.nbody, m.ngeom, m.nbvh, m.nbvhstatic, m.nq, m.nsensordata) for m in be.models}
    assert len(sizes) == 1  # what set_models needs: one MjData layout
    for m, arena in zip(be.models, be.arenas, strict=True):
        park = m.body(PARKING_BODY).id
        assert m.body_weldid[park] == 0 and m.body_pos[park][2] == PARK_Z  # welded to the world, far below
        geoms = np.flatnonzero(m.geom_bodyid == park)
        assert len(geoms) == be.max_boxes - len(arena.boxes) + 1
        assert np.all(m.geom_rgba[geoms, 3] == 0)
        assert park == m.nbody - 1 and geoms[0] == m.ngeom - len(geoms)  # after the robot: ids as in the plain model


def test_bad_batches_raise():
    with pytest.raises(ValueError, match="at least one"):
        MujocoBatchWorlds([])
    with pytest.raises(ValueError, match="steps"):
        MujocoBatchWorlds([CONFIGS[0], EpisodeConfig(steps=STEPS + 1)])
    with pytest.raises(ValueError, match="control_hz"):
        MujocoBatchWorlds([CONFIGS[0], EpisodeConfig(steps=STEPS, control_hz=20.0)])
    with pytest.raises(ValueError, match="obstacle slots"):
        MujocoBatchWorlds(CONFIGS[:1], max_boxes=3)
    with pytest.raises(ValueError, match="slots"):
        run_episode(CONFIGS[0], options=EngineOptions(pad_boxes=2))


def test_run_batch_and_throughput_report():
    episodes = run_batch([EpisodeConfig(steps=5, seed=s) for s in range(2)], nthread=2, progress=False)
    assert [len(ep.trajectory) for ep in episodes] == [5, 5]
    r = measure_throughput(n_copies=2, steps=5, nthread=2)
    assert r["physics_steps"] == 2 * 5 * r["n_substeps"]
    assert r["batch_physics_steps_per_s"] > 0 and r["single_physics_steps_per_s"] > 0 and r["speedup"] > 0


def test_a_stopped_batch_keeps_the_completed_steps(monkeypatch):
    """Ctrl-C part-way: every copy's episode holds the steps done, marked not completed; the same rows as a full run."""
    configs = [EpisodeConfig(arena="box", steps=12, seed=s) for s in (0, 1)]
    full = run_batch(configs, progress=False)
    runs = MujocoBatchWorlds(configs)
    advance, calls = runs.advance, []

    def stop_at_the_eighth():
        calls.append(1)
        if len(calls) == 8:
            raise KeyboardInterrupt
        advance()

    monkeypatch.setattr(runs, "advance", stop_at_the_eighth)
    eps = runs.run()
    for ep, whole in zip(eps, full, strict=True):
        assert ep.summary["completed"] is False and ep.summary["steps"] == 7 and ep.summary["steps_requested"] == 12
        np.testing.assert_array_equal(ep.trajectory.qpos, whole.trajectory.qpos[:7])
