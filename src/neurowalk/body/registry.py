"""The one registry of bodies: what ``--body NAME`` can name, what each needs and offers, and how it is built.

Every per-step body follows one small protocol (:class:`~neurowalk.body.world.Body`, typed), which
:class:`~neurowalk.body.world.OneWorld` makes the one world the loop (:mod:`neurowalk.sim.loop`) steps; the planar
surrogate is a compiled world of its own (:class:`~neurowalk.body.surrogate.Surrogate`):

.. code-block:: text

    body = make_body(name, arena, options, control_hz=..., noise=...)
    body.reset(rng)                      # at the arena's start pose, at rest; sensor noise from rng
    obs = body.observe()                 # Observation: ultrasonic distances (2,) m, contacts, pose, time
    body.apply(action)                   # body.action == "targets": the 19 joint targets (rad, actuator order)
                                         # body.action == "steering": the steering pair (O1, O2) in [-1, 1]^2
    body.advance()                       # one control step of physics
    body.model, body.data                # MuJoCo (physics bodies): qpos[0:7] is the free joint of the trunk

``neurowalk bodies`` prints this registry. A body option (``--body-opt KEY=VALUE``) is a number checked against
its range here, before anything is built.
"""

from __future__ import annotations

import functools
import json
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, cast

import mujoco
import numpy as np

from neurowalk.arenas import ArenaSpec
from neurowalk.body.amosii import AmosII
from neurowalk.body.amosii_mjcf import amosii_xml
from neurowalk.body.amosii_params import CONES, INTEGRATORS, JACOBIANS, SOLVERS, BodyParams
from neurowalk.body.physics import n_substeps, obstacle_contacts
from neurowalk.body.surrogate import Surrogate, load_calibration
from neurowalk.body.user_mjcf import UserMjcf, check_opts
from neurowalk.body.wheeled import WheeledParams, wheeled_xml
from neurowalk.body.wheeled_body import Wheeled
from neurowalk.body.world import Body


@dataclass(frozen=True)
class BodyInfo:
    """What a body is: its sensors and actuators, what its ``apply`` takes, whether it climbs, its options.

    Attributes:
        name: the ``--body`` name. summary: one line. sensors, actuators: what it has, in words.
        action: ``"targets"`` (19 joint targets from the locomotion network) or ``"steering"`` (O1, O2).
        physics: a MuJoCo body (else a planar surrogate). climbs: it can take the climbing controls
            (``--reflexes``, ``--backbone``). options: name -> (default, low, high, meaning).
        choices: the options that take a name: name -> (default, the names allowed, meaning).
        surrogate: the planar body calibrated on this physics body (``neurowalk calibrate --body NAME``), if any.
        engines: the physics engines (a config's ``engine``) it runs on; a planar body runs its own compiled loop.
        climbs_on: those of its engines that run it with the climbing controls.
        viewer: ``neurowalk view`` shows it live in MuJoCo's viewer.
        lockstep: it runs as lock-step worlds (``mujoco.batch``, MuJoCo Warp): one model structure for every arena.
        gait_refusal: why it takes no gait but the wave gait (None: it takes every gait).
        build: ``build(name, arena, options, control_hz=, noise=, climbing=, pad_boxes=)`` -> the body (its
            options checked): :func:`make_body` calls it.
        check_opts: ``check_opts(name, options) -> options``: the options' own checks beyond their ranges (None:
            none).
        xml: ``xml(options, world) -> str``: the self-contained MJCF of a built-in physics body around ``world``
            (None: it has none to export).
        model: ``model(name, options) -> MjModel``: the model whose physics a run steps (None: a planar body).
        replay: ``replay(name, options, arena, qpos) -> contacts``: obstacle contact of recorded positions (None:
            replayed in the model :attr:`build` makes).
        prefix: the entry of every body named ``PREFIX...`` (``mjcf:``: a user's file); its options are checked
            as it builds (None: a built-in body of this name).
    """

    name: str
    summary: str
    sensors: str
    actuators: str
    action: str
    physics: bool
    climbs: bool
    options: dict[str, tuple[float, float, float, str]] = field(default_factory=dict)
    choices: dict[str, tuple[str, tuple[str, ...], str]] = field(default_factory=dict)
    surrogate: str | None = None
    engines: tuple[str, ...] = ("mujoco",)
    climbs_on: tuple[str, ...] = ("mujoco",)
    lockstep: bool = False
    viewer: bool = False
    gait_refusal: str | None = "takes the steering pair (no legs), no gait;"
    build: Callable[..., Body | Surrogate] = field(kw_only=True, compare=False, repr=False)
    check_opts: Callable[[str, dict[str, Any]], dict[str, Any]] | None = field(default=None, compare=False, repr=False)
    xml: Callable[[dict[str, Any], str], str] | None = field(default=None, compare=False, repr=False)
    model: Callable[[str, dict[str, Any]], mujoco.MjModel] | None = field(default=None, compare=False, repr=False)
    replay: Callable[..., np.ndarray] | None = field(default=None, compare=False, repr=False)
    prefix: str | None = None

    def check_gait(self, gait: str) -> None:
        """ValueError unless the body takes ``gait`` (a name of :data:`neurowalk.neural.cpg.GAITS`)."""
        if gait != "wave" and self.gait_refusal is not None:
            raise ValueError(f"body {self.name!r} {self.gait_refusal} got gait {gait!r}")


def amosii_params(opts: Mapping[str, Any] | None = None) -> BodyParams:
    """AMOSII's numbers with its body options (``timestep``, ``solver_iterations``, ``integrator``, ...; checked by
    :func:`check_body_opts`) set over the defaults."""
    options = dict(opts or {})
    if "solver_iterations" in options:
        n = options["solver_iterations"]
        if float(n) != int(n):
            raise ValueError(f"option 'solver_iterations' of body 'amosii' must be a whole number, got {n!r}")
        options["solver_iterations"] = int(n)
    return BodyParams(**options) if options else BodyParams()


def _check_amosii(name: str, options: dict[str, Any]) -> dict[str, Any]:
    amosii_params(options)  # a whole number of iterations, and BodyParams' own checks
    return options


def _build_amosii(name: str, arena: ArenaSpec, options: dict[str, Any], *, control_hz: float, noise: float,
                  climbing: bool, pad_boxes: int | None) -> AmosII:  # fmt: skip
    return AmosII(arena, amosii_params(options), control_hz=control_hz, noise=noise, scan_obstacles=climbing,
                  pad_boxes=pad_boxes)  # fmt: skip


def _build_planar(name: str, arena: ArenaSpec, options: dict[str, Any], *, control_hz: float, noise: float,
                  **_: Any) -> Surrogate:  # fmt: skip
    cal = load_calibration(body=name)  # each planar body reads its own calibration file
    body = Surrogate(arena, cal.scaled(**options) if options else cal, noise=noise, name=name)
    if control_hz != body.control_hz:
        raise ValueError(f"body {name!r} is calibrated at {body.control_hz} Hz, got control_hz {control_hz}")
    return body


def _build_wheeled(name: str, arena: ArenaSpec, options: dict[str, Any], *, control_hz: float, noise: float,
                   **_: Any) -> Wheeled:  # fmt: skip
    return Wheeled(arena, WheeledParams(**options), control_hz=control_hz, noise=noise)


def _build_mjcf(name: str, arena: ArenaSpec, options: dict[str, Any], *, control_hz: float, noise: float,
                **_: Any) -> UserMjcf:  # fmt: skip
    return UserMjcf(name, arena, options, control_hz=control_hz, noise=noise)


def _amosii_xml(options: dict[str, Any], world: str) -> str:
    return amosii_xml(amosii_params(options), world=world)


def _wheeled_xml(options: dict[str, Any], world: str) -> str:
    return wheeled_xml(WheeledParams(**options), world=world)


def _model_of(xml: Callable[[dict[str, Any], str], str]) -> Callable[[str, dict[str, Any]], mujoco.MjModel]:
    """The model of a built-in physics body, from its MJCF."""
    return lambda name, options: mujoco.MjModel.from_xml_string(xml(options, ""))


def _mjcf_model(name: str, options: dict[str, Any]) -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_path(name.removeprefix("mjcf:"))


def _replay_amosii(name: str, options: dict[str, Any], arena: ArenaSpec, qpos: np.ndarray) -> np.ndarray:
    return obstacle_contacts(arena, qpos, params=amosii_params(options))


#: Options of the planar (calibrated) bodies: the measured motion with its speeds or yaw rates scaled.
PLANAR_OPTIONS: dict[str, tuple[float, float, float, str]] = {
    "speed": (1.0, 0.25, 4.0, "forward and sideways speed x speed (the measured body's)"),
    "turn": (1.0, 0.25, 4.0, "yaw rate x turn (the measured body's)"),
}

BODIES: dict[str, BodyInfo] = {
    "amosii": BodyInfo(
        "amosii",
        "the hexapod AMOSII in MuJoCo (19 joints): the paper's robot",
        "2 ultrasonic rangefinders (±35°, 0.4 m), 6 foot contacts, 19 joint angles, obstacle-height scanner",
        "19 position servos (18 leg joints + backbone), driven by the locomotion network",
        "targets",
        True,
        True,
        surrogate="surrogate",
        engines=("mujoco", "mujoco.batch", "warp"),
        gait_refusal=None,
        lockstep=True,
        viewer=True,
        build=_build_amosii,
        check_opts=_check_amosii,
        xml=_amosii_xml,
        model=_model_of(_amosii_xml),
        replay=_replay_amosii,
        options={
            "timestep": (0.01, 0.001, 0.02, "physics step (s); a control step is a whole number of them"),
            "solver_iterations": (20, 1, 1000, "most solver iterations of a physics step (whole number)"),
            "solver_tolerance": (1e-6, 1e-12, 1e-3, "the solver stops when its cost improves by less"),
            "armature": (0.005, 1e-4, 0.5, "rotor inertia of every servo, reflected through its gears (kg m^2)"),
            "contact_timeconst": (0.02, 0.002, 0.2, "time constant of every contact (s); at least 2 physics steps"),
            "servo_timeconst": (0.03, 0.0, 0.5, "each servo follows its target with this lag (s; 0: none)"),
        },
        choices={
            "integrator": ("discrete", INTEGRATORS, "MuJoCo's integrator"),
            "solver": ("Newton", SOLVERS, "MuJoCo's constraint solver"),
            "cone": ("elliptic", CONES, "MuJoCo's friction cone"),
            "jacobian": ("sparse", JACOBIANS, "MuJoCo's constraint Jacobian"),
        },
    ),
    "surrogate": BodyInfo(
        "surrogate",
        "planar kinematic AMOSII calibrated on the physics robot (about 1000x faster)",
        "2 ultrasonic rangefinders (as AMOSII's)",
        "the steering pair through the calibrated motion of AMOSII",
        "steering",
        False,
        False,
        PLANAR_OPTIONS,
        gait_refusal="is calibrated on the wave gait,",
        build=_build_planar,
    ),
    "wheeled": BodyInfo(
        "wheeled",
        "a differential-drive robot with AMOSII's footprint, forward speed and rangefinders, in MuJoCo",
        "2 ultrasonic rangefinders (as AMOSII's)",
        "2 driven wheels (velocity motors: right from O1, left from O2) and casters; no locomotion network",
        "steering",
        True,
        False,
        {"scale": (1.0, 0.05, 4.0, "every length and the speed x scale (0.1: a Khepera-sized robot)")},
        surrogate="surrogate-wheeled",
        build=_build_wheeled,
        xml=_wheeled_xml,
        model=_model_of(_wheeled_xml),
    ),
    "surrogate-wheeled": BodyInfo(
        "surrogate-wheeled",
        "planar kinematic wheeled robot calibrated on the physics wheeled body (scale 1)",
        "2 ultrasonic rangefinders (as the wheeled robot's)",
        "the steering pair through the calibrated motion of the wheeled robot",
        "steering",
        False,
        False,
        PLANAR_OPTIONS,
        build=_build_planar,
    ),
}


MJCF = BodyInfo(
    "mjcf:FILE",
    "a user's MuJoCo robot (wheels or AMOSII's legs), by the convention of neurowalk.body.user_mjcf",
    "its 2 rangefinders (US_L, US_R, or --body-opt left=, right=)",
    "2 wheel velocity actuators (wheel_R, wheel_L, or by option) or AMOSII's 19 (drive=legs)",
    "steering",
    True,
    False,
    {},
    build=_build_mjcf,
    check_opts=check_opts,
    model=_mjcf_model,
    prefix="mjcf:",
)


def body_info(name: str) -> BodyInfo:
    """The registry entry of ``name`` (``mjcf:FILE``: the user-file entry); ValueError names an unknown body."""
    if MJCF.prefix and name.startswith(MJCF.prefix):
        return MJCF
    if name not in BODIES:
        raise ValueError(f"unknown body {name!r}; expected one of {', '.join(BODIES)}, or mjcf:FILE.xml")
    return BODIES[name]


def body_files(name: str) -> tuple[Path, ...]:
    """The user's files a body of this name reads (``mjcf:FILE``: the file; a built-in body: none): their contents
    are part of its runs' fingerprint (:func:`neurowalk.fingerprint.code`)."""
    info = body_info(name)
    return (Path(name[len(info.prefix) :]),) if info.prefix is not None else ()


def bodies_where(test: Callable[[BodyInfo], bool]) -> tuple[str, ...]:
    """The names of the registry's bodies whose :class:`BodyInfo` passes ``test`` (e.g. ``lambda b: b.climbs``)."""
    return tuple(name for name, info in BODIES.items() if test(info))


def check_body_opts(name: str, opts: dict[str, Any]) -> dict[str, Any]:
    """The body's options as numbers (a named option as its name), each checked against its range or its names,
    then by the body's own :attr:`BodyInfo.check_opts`; ValueError names a bad key or value."""
    info = body_info(name)
    if info.prefix is not None:  # a user's file: its own check reads the file
        return info.check_opts(name, dict(opts)) if info.check_opts is not None else dict(opts)
    out = {}
    for key, value in opts.items():
        if key in info.choices:
            _, allowed, _ = info.choices[key]
            if value not in allowed:
                raise ValueError(f"body option {key} must be one of {', '.join(allowed)}, got {value!r}")
            out[key] = value
            continue
        if key not in info.options:
            known = ", ".join([*info.options, *info.choices]) or "none"
            raise ValueError(f"unknown option {key!r} of body {name!r}; its options: {known}")
        _, low, high, _ = info.options[key]
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise ValueError(f"body option {key} must be a number, got {value!r}") from None
        if isinstance(value, bool) or not math.isfinite(number) or not low <= number <= high:
            raise ValueError(f"body option {key} must be a number in [{low}, {high}], got {value!r}")
        out[key] = number
    return info.check_opts(name, out) if info.check_opts is not None else out


def body_settings(name: str, opts: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Every option of body ``name`` with the value a run uses: given in ``opts`` (checked), else its default.

    One physics for every run: a climbing run takes the same defaults as any other. E.g.
    ``body_settings("amosii")["timestep"]`` is 0.01 (s). A user's MJCF body: its options as given.
    """
    info = body_info(name)
    defaults = {key: spec[0] for key, spec in (*info.options.items(), *info.choices.items())}
    return {**defaults, **check_body_opts(name, dict(opts or {}))}


def physics_settings(
    name: str, opts: Mapping[str, Any] | None = None, control_hz: float = 10.0
) -> dict[str, Any] | None:
    """The physics a run of body ``name`` steps, as it ran (None: a planar body).

    ``timestep_s`` is the step after fitting to the control rate (:func:`~neurowalk.body.physics.set_control_rate`:
    at 27 Hz a 0.01 s step runs as 4 steps of 9.26 ms), ``substeps`` the physics steps of a control step; then
    MuJoCo's integrator, solver, friction cone, Jacobian, most iterations and tolerance. E.g.
    ``physics_settings("amosii")["timestep_s"]`` is 0.01.
    """
    info = body_info(name)
    if info.model is None:
        return None
    options = check_body_opts(name, dict(opts or {})) if info.prefix is None else dict(opts or {})
    return dict(_physics_of(name, json.dumps(options, sort_keys=True), float(control_hz)))


@functools.lru_cache(maxsize=64)
def _physics_of(name: str, options: str, control_hz: float) -> tuple[tuple[str, Any], ...]:
    model = body_info(name).model(name, json.loads(options))  # type: ignore[misc]
    o = model.opt
    n = n_substeps(control_hz, o.timestep)
    return (
        ("timestep_s", 1.0 / (control_hz * n)),
        ("substeps", n),
        ("integrator", mujoco.mjtIntegrator(o.integrator).name.removeprefix("mjINT_").lower()),
        ("solver", mujoco.mjtSolver(o.solver).name.removeprefix("mjSOL_").lower()),
        ("cone", mujoco.mjtCone(o.cone).name.removeprefix("mjCONE_").lower()),
        ("jacobian", mujoco.mjtJacobian(o.jacobian).name.removeprefix("mjJAC_").lower()),
        ("iterations", int(o.iterations)),
        ("tolerance", float(o.tolerance)),
    )


def make_body(
    name: str,
    arena: ArenaSpec,
    opts: Mapping[str, Any] | None = None,
    *,
    control_hz: float = 10.0,
    noise: float = 0.02,
    climbing: bool = False,
    pad_boxes: int | None = None,
) -> Body | Surrogate:
    """Build body ``name`` in ``arena`` with its options (its registry entry's :attr:`BodyInfo.build`).

    ``climbing``: the controller climbs (a climbing body reads its obstacle-height scanner every step).
    ``pad_boxes``: AMOSII's model with room for that many obstacle slots (the model :mod:`neurowalk.sim.batch`
    steps, bit for bit the plain model's physics); other bodies have one model and ignore it. ValueError names an
    unknown body (and the known ones) or a bad option.
    """
    info = body_info(name)
    options = dict(opts or {}) if info.prefix is not None else check_body_opts(name, dict(opts or {}))
    return info.build(name, arena, options, control_hz=control_hz, noise=noise, climbing=climbing, pad_boxes=pad_boxes)


def body_model(name: str, arena: ArenaSpec, opts: dict[str, Any] | None = None) -> mujoco.MjModel:
    """The MuJoCo model of physics body ``name`` in ``arena`` (what a picture of its recorded positions renders);
    ValueError for a planar body."""
    if body_info(name).model is None:
        raise ValueError(f"body {name!r} is planar: it has no MuJoCo model")
    return cast("Body", make_body(name, arena, opts, noise=0.0)).model


def replay_contacts(name: str, opts: Mapping[str, Any], arena: ArenaSpec, qpos: np.ndarray) -> np.ndarray:
    """Per-row obstacle contact (1.0 / 0.0) of recorded positions ``qpos`` (T, nq) of a physics body, replayed in a
    fresh model of its arena (collision depends on positions only): the robot touching any geom of the world but
    a plane."""
    info = body_info(name)
    if info.replay is not None:
        return info.replay(name, dict(opts), arena, qpos)
    model = body_model(name, arena, dict(opts))
    if qpos.ndim != 2 or qpos.shape[1] != model.nq:
        raise ValueError(f"qpos must have shape (T, {model.nq}), got {qpos.shape}")
    data = mujoco.MjData(model)
    robot = model.geom_bodyid != 0
    obstacle = ~robot & (model.geom_type != mujoco.mjtGeom.mjGEOM_PLANE)
    out = np.zeros(len(qpos))
    for k in range(len(qpos)):
        data.qpos[:] = qpos[k]
        mujoco.mj_kinematics(model, data)
        mujoco.mj_collision(model, data)
        g = data.contact.geom[: data.ncon]
        out[k] = float(np.any((robot[g[:, 0]] & obstacle[g[:, 1]]) | (robot[g[:, 1]] & obstacle[g[:, 0]])))
    return out


def body_xml(name: str, opts: dict[str, Any] | None = None, world: str = "") -> str:
    """The self-contained MJCF of physics body ``name`` with its options, around ``world`` (an arena's
    ``to_mjcf()``); ValueError for a body without one (a planar body, a user's file)."""
    info = body_info(name)
    if info.xml is None:
        raise ValueError(f"body {name!r} has no built-in MuJoCo model to export")
    return info.xml(check_body_opts(name, opts or {}), world)


def body_listing() -> str:
    """The registry as text, one block per body (``neurowalk bodies``)."""
    lines = []
    for b in (*BODIES.values(), MJCF):
        opts = ", ".join(
            [f"{k}={d:g} ({lo:g} to {hi:g}: {what})" for k, (d, lo, hi, what) in b.options.items()]
            + [f"{k}={d} ({' | '.join(names)}: {what})" for k, (d, names, what) in b.choices.items()]
        )
        if b.prefix is not None:
            opts = "drive (wheels|legs), left, right, right_motor, left_motor (names), key, range (m), speed (rad/s)"
        lines += [
            f"{b.name:10s} {b.summary}",
            f"{'':10s} sensors: {b.sensors}",
            f"{'':10s} actuators: {b.actuators}",
            f"{'':10s} takes: {'joint targets' if b.action == 'targets' else 'the steering pair'}; "
            f"{'physics (MuJoCo)' if b.physics else 'planar'}; {'climbs' if b.climbs else 'does not climb'}",
            f"{'':10s} options: {opts or 'none'}",
        ]
    return "\n".join(lines)
