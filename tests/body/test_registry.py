"""The body registry: every physics body passes the same contract (reset, observe, apply, advance, determinism)."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import mujoco
import numpy as np
import pytest

from neurowalk.arenas import make_arena
from neurowalk.body import registry
from neurowalk.body.registry import (
    BODIES,
    body_info,
    body_listing,
    body_settings,
    check_body_opts,
    make_body,
    replay_contacts,
)
from neurowalk.observation import Observation
from neurowalk.sim.episode import EpisodeConfig, run_episode

PHYSICS = [name for name, info in BODIES.items() if info.physics]
REGISTRY = Path(registry.__file__)


def test_an_unknown_body_fails_naming_the_known_ones(tmp_path):
    """From Python and from the command line: one line naming every body of the table."""
    with pytest.raises(ValueError, match="unknown body 'nosuchbody'; expected one of " + ", ".join(BODIES)):
        make_body("nosuchbody", make_arena("open"))
    run = subprocess.run(
        [sys.executable, "-m", "neurowalk", "run", "--body", "nosuchbody", "--steps", "5", "--out", str(tmp_path)],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 2 and all(name in run.stderr for name in BODIES), run.stderr


def test_the_registry_dispatches_on_its_table_not_on_names():
    """Each body is built by its entry's callables: registry.py compares no string with a body's name (a new body is
    an entry, not a branch), and each entry builds a body of its own kind."""
    tree = ast.parse(REGISTRY.read_text())
    compared = [
        c.value
        for node in ast.walk(tree)
        if isinstance(node, ast.Compare)
        for c in [node.left, *node.comparators]
        if isinstance(c, ast.Constant) and isinstance(c.value, str)
    ]
    assert not set(compared) & set(BODIES), compared
    arena = make_arena("open")
    kinds = {name: type(make_body(name, arena, noise=0.0)).__name__ for name in BODIES}
    assert kinds["amosii"] != kinds["wheeled"] != kinds["surrogate"]
    assert kinds["surrogate"] == kinds["surrogate-wheeled"]


def test_names_options_and_listing():
    assert {"amosii", "surrogate", "wheeled"} <= set(BODIES)
    assert EpisodeConfig(body="wheeled", body_opts={"scale": 0.5}).body_opts == {"scale": 0.5}
    listing = body_listing()
    for name, info in BODIES.items():
        assert body_info(name) is info and f"{name} " in listing
        for key, (default, low, high, _) in info.options.items():
            assert low <= default <= high and check_body_opts(name, {key: str(default)}) == {key: default}
    with pytest.raises(ValueError, match="'tank'"):
        body_info("tank")
    with pytest.raises(ValueError, match="'scale'"):
        check_body_opts("amosii", {"scale": 1})
    with pytest.raises(ValueError, match="scale"):
        check_body_opts("wheeled", {"scale": "inf"})


def _action(body, steer: tuple[float, float]) -> np.ndarray:
    if body.action == "steering":
        return np.array(steer)
    from neurowalk.controller import FixedController

    return FixedController(steer).act(body.observe())


@pytest.mark.parametrize("name", PHYSICS)
def test_contract_reset_observe_apply_advance_and_determinism(name):
    arena = make_arena("box")
    runs = []
    for _ in range(2):
        body = make_body(name, arena)
        assert body.action == body_info(name).action and body.n_substeps >= 1
        body.reset(np.random.default_rng(4))
        obs = body.observe()
        assert isinstance(obs, Observation) and obs.us_distance.shape == (2,) and obs.pose.shape == (3,)
        np.testing.assert_allclose(obs.pose, arena.start, atol=0.02)
        for _ in range(30):
            body.apply(_action(body, (-1.0, -1.0)))
            body.advance()
        runs.append((body.data.qpos.copy(), body.observe().us_distance))
        assert body.data.time == pytest.approx(30 / body.control_hz)
        assert body.warnings() == {}
    np.testing.assert_array_equal(runs[0][0], runs[1][0])
    np.testing.assert_array_equal(runs[0][1], runs[1][1])


@pytest.mark.parametrize("name", PHYSICS)
def test_the_control_loop_runs_each_body_and_replays_its_contacts(name):
    ep = run_episode(EpisodeConfig(body=name, arena="box", steps=40, controller="plastic"))
    assert ep.summary["body"] == name and ep.summary["completed"]
    assert ep.trajectory.qpos.shape == (40, make_body(name, ep.arena).model.nq)
    touch = replay_contacts(name, {}, ep.arena, ep.trajectory.qpos[:3])
    assert touch.shape == (3,) and set(np.unique(touch)) <= {0.0, 1.0}


def test_the_wheeled_robot_escapes_the_simple_deadlock_with_the_plastic_network_only():
    for seed in (0, 1):
        cfg = {"body": "wheeled", "arena": "simple-deadlock", "steps": 3000, "seed": seed}
        assert run_episode(EpisodeConfig(**cfg, controller="plastic")).summary["escaped"]
        assert not run_episode(EpisodeConfig(**cfg, controller="static")).summary["escaped"]


def test_the_wheeled_surrogate_is_a_planar_body_of_the_registry():
    from neurowalk.body.surrogate import Surrogate, load_calibration

    info = body_info("surrogate-wheeled")
    assert not info.physics and info.action == "steering" and not info.climbs and set(info.options) == {"speed", "turn"}
    assert BODIES["wheeled"].surrogate == "surrogate-wheeled" and BODIES["amosii"].surrogate == "surrogate"
    assert "surrogate-wheeled planar kinematic wheeled robot" in body_listing()
    body = make_body("surrogate-wheeled", make_arena("open"), {}, noise=0.0)
    assert isinstance(body, Surrogate) and body.name == "surrogate-wheeled"
    assert body.cal is load_calibration(body="surrogate-wheeled") and body.cal is not load_calibration()
    with pytest.raises(ValueError, match=r"'surrogate-wheeled' is calibrated at 10\.0 Hz"):
        make_body("surrogate-wheeled", make_arena("open"), {}, control_hz=20.0)
    with pytest.raises(ValueError, match=r"'surrogate-wheeled' is calibrated at 10\.0 Hz"):
        EpisodeConfig(body="surrogate-wheeled", control_hz=20.0)
    with pytest.raises(ValueError, match="'scale'"):
        check_body_opts("surrogate-wheeled", {"scale": 0.5})  # calibrated at scale 1 only


def test_one_physics_for_every_amosii_run_climbing_or_not():
    """A climbing run steps the same physics as any other (no climbing defaults), the registry's defaults are
    BodyParams', and a run's key names only the options it was given."""
    from neurowalk.body.amosii_params import BodyParams

    walk, climb = EpisodeConfig(arena="steps"), EpisodeConfig(arena="steps", reflexes=True, backbone=True)
    assert body_settings("amosii") == {k: getattr(BodyParams(), k) for k in body_settings("amosii")}
    arena = make_arena("steps")
    made = [make_body("amosii", arena, climbing=c).model.opt for c in (False, True)]
    assert made[0].timestep == made[1].timestep == 0.01 and made[0].integrator == made[1].integrator
    assert (
        run_episode(walk.replace(steps=2)).summary["physics"] == run_episode(climb.replace(steps=2)).summary["physics"]
    )
    assert "body_opts" not in climb.spec() and "climbing (" not in body_listing()
    assert climb.key() != climb.replace(body_opts={"timestep": 0.005}).key()


@pytest.mark.parametrize(
    ("name", "opts", "hz", "climbing"),
    [("amosii", {}, 10.0, False), ("amosii", {}, 27.0, False), ("amosii", {}, 27.0, True), ("wheeled", {}, 10.0, False),
     ("amosii", {"integrator": "implicitfast", "solver_iterations": 7}, 10.0, False)],
)  # fmt: skip
def test_the_physics_record_is_the_physics_the_body_steps(name, opts, hz, climbing):
    """summary.json's ``physics`` is the built body's model as it steps: the step fitted to the control rate (27 Hz:
    not the 10 or 5 ms asked for), the physics steps of a control step, and the solver's settings."""
    from neurowalk.body.registry import physics_settings

    body = make_body(name, make_arena("open"), opts, control_hz=hz, climbing=climbing)
    rec, o = physics_settings(name, opts, hz), body.model.opt
    assert rec["timestep_s"] == pytest.approx(o.timestep, rel=1e-12)
    assert rec["substeps"] * rec["timestep_s"] == pytest.approx(1.0 / hz, rel=1e-12)
    assert rec["integrator"] == mujoco.mjtIntegrator(o.integrator).name[len("mjINT_") :].lower()
    assert (rec["iterations"], rec["tolerance"]) == (o.iterations, o.tolerance)
    assert rec["cone"] == mujoco.mjtCone(o.cone).name[len("mjCONE_") :].lower()
    if hz == 27.0:
        assert rec["timestep_s"] != body_settings(name, opts)["timestep"]
    assert physics_settings("surrogate") is None


def test_a_runs_summary_records_its_physics():
    ep = run_episode(EpisodeConfig(steps=3, body_opts={"integrator": "implicitfast"}, control_hz=27.0))
    assert ep.summary["physics"]["integrator"] == "implicitfast" and ep.summary["physics"]["substeps"] == 4
    assert ep.result.physics["timestep_s"] == pytest.approx(1 / 108)
    with pytest.raises(ValueError, match="integrator must be one of implicitfast, discrete"):
        EpisodeConfig(body_opts={"integrator": "rk5"})
