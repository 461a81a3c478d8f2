"""The one control loop: observe → controller → joint targets → physics, at ``control_hz``.

.. code-block:: text

    body.reset(rng); controller.reset(rng)
    for each control step:
        obs = body.observe()              # copies; sensor noise from the run's Generator
        targets = controller.act(obs)     # 19 joint targets (rad)
        body.apply(targets); body.advance()   # n_substeps physics steps
        record

Every random draw comes from Generators spawned from one seed (``SeedSequence(seed).spawn``), so
the same seed gives the same trajectory, bit for bit.
"""

from __future__ import annotations

import math
import pickle
import time
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np

import neurowalk
from neurowalk import metrics
from neurowalk.arenas import ArenaSpec, make_arena
from neurowalk.body.physics import AmosII, obstacle_contacts
from neurowalk.body.surrogate import Surrogate
from neurowalk.controller import CONTROLLERS, Controller, make_controller
from neurowalk.neural.cpg import GAITS, CpgParams
from neurowalk.neural.motor import LocomotionParams
from neurowalk.neural.variants import get_variant
from neurowalk.sim.trajectory import Trajectory, poses_from_qpos, up_z_from_qpos

BODIES: tuple[str, ...] = ("amosii", "surrogate")


@dataclass(frozen=True, kw_only=True)
class EpisodeConfig:
    """One run: where, with which controller and body, how long, which seed."""

    arena: str = "open"
    arena_opts: dict[str, Any] = field(default_factory=dict)
    controller: str = "plastic"
    steer: tuple[float, float] | None = None  # for controller "fixed": (O1, O2)
    body: str = "amosii"
    steps: int = 1000  # control steps
    seed: int = 0
    control_hz: float = 10.0
    noise: float = 0.02  # strength of the coloured sensor noise
    b0: float | None = None  # plastic controller: start self weights (default 0)
    q0: float | None = None  # plastic controller: start inhibition magnitudes (default 0)
    reflexes: bool = False  # local leg control: forward models, searching and elevation reflexes
    backbone: bool = False  # backbone joint control and the climbable-step decision (obstacle-height sensor)
    variant: str = "paper"  # the network: paper (Eq. 1-6 as printed), original (the authors' code), tuned
    params: dict[str, float] | None = None  # SensoryParams fields set on top of the variant (a params file)
    gait: str = "wave"  # the CPG's modulatory input by name (neurowalk.neural.cpg.GAITS)

    def __post_init__(self) -> None:
        if self.controller not in CONTROLLERS:
            raise ValueError(f"unknown controller {self.controller!r}; expected one of {', '.join(CONTROLLERS)}")
        if self.body not in BODIES:
            raise ValueError(f"unknown body {self.body!r}; expected one of {', '.join(BODIES)}")
        if not _whole(self.steps) or not 1 <= self.steps <= MAX_STEPS:
            raise ValueError(f"steps must be a whole number from 1 to {MAX_STEPS:,}, got {self.steps!r}")
        if not _whole(self.seed) or not 0 <= self.seed < 2**63:
            raise ValueError(f"seed must be a whole number from 0 to 2**63 - 1, got {self.seed!r}")
        if not _number(self.control_hz) or not 0 < self.control_hz <= 1000:
            raise ValueError(f"control_hz must be a number in (0, 1000] Hz, got {self.control_hz!r}")
        if not _number(self.noise) or not 0 <= self.noise <= 1:
            raise ValueError(f"noise must be a number in [0, 1] (strength of the sensor noise), got {self.noise!r}")
        for name in ("b0", "q0"):
            v = getattr(self, name)
            if v is not None and (not _number(v) or v < 0):
                raise ValueError(f"{name} must be a number >= 0 (a start weight), got {v!r}")
        if self.steer is not None and (
            len(self.steer) != 2 or not all(_number(v) and -1 <= v <= 1 for v in self.steer)
        ):
            raise ValueError(f"steer must be two numbers O1, O2 in [-1, 1], got {list(self.steer)!r}")
        if (self.b0 is not None or self.q0 is not None) and self.controller != "plastic":
            raise ValueError("start weights b0/q0 go with controller 'plastic' only")
        if (self.controller == "fixed") != (self.steer is not None):
            raise ValueError("--steer O1,O2 goes with controller 'fixed' (and only with it)")
        if (self.reflexes or self.backbone) and self.body != "amosii":
            raise ValueError(f"reflexes and backbone control need body 'amosii' (legs and terrain), got {self.body!r}")
        get_variant(self.variant, self.params)  # raises on an unknown variant or a bad parameter
        if self.gait not in GAITS:
            raise ValueError(f"unknown gait {self.gait!r}; expected one of {', '.join(GAITS)}")
        if self.gait != "wave" and self.body == "surrogate":
            raise ValueError(f"body 'surrogate' is calibrated on the wave gait, got gait {self.gait!r}")


MAX_STEPS = 100_000_000  # control steps of one run (about 116 days simulated at 10 Hz)


def _number(v: object) -> bool:
    """A finite real number (not a bool)."""
    return isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)


def _whole(v: object) -> bool:
    """A finite whole number (not a bool)."""
    return _number(v) and float(v) == int(v)  # type: ignore[arg-type]


@dataclass
class Episode:
    """A finished run: its config, arena, trajectory and summary (DESIGN §5 keys)."""

    config: EpisodeConfig
    arena: ArenaSpec
    trajectory: Trajectory
    summary: dict[str, Any]


def seeds(cfg: EpisodeConfig) -> tuple[np.random.Generator, np.random.Generator, np.random.Generator]:
    """Generators of the body (sensor noise), the controller and the arena layout, from the run's seed."""
    body, ctrl, arena = (np.random.default_rng(s) for s in np.random.SeedSequence(cfg.seed).spawn(3))
    return body, ctrl, arena


def build(cfg: EpisodeConfig, *, pad_boxes: int | None = None) -> tuple[ArenaSpec, AmosII | Surrogate, Controller]:
    """Arena, body and controller of a config (raises ValueError on bad input).

    ``pad_boxes``: build AMOSII's model with that many obstacle slots (``AmosII(pad_boxes=...)``), the model
    :mod:`neurowalk.sim.batch` runs; None (default) for the plain model.
    """
    arena = make_arena(cfg.arena, rng=seeds(cfg)[2], **cfg.arena_opts)
    body: AmosII | Surrogate
    if cfg.body == "surrogate":
        body = Surrogate(arena, noise=cfg.noise)
        if cfg.control_hz != body.control_hz:
            raise ValueError(f"body 'surrogate' is calibrated at {body.control_hz} Hz, got control_hz {cfg.control_hz}")
    else:
        body = AmosII(arena, control_hz=cfg.control_hz, noise=cfg.noise, pad_boxes=pad_boxes,
                      scan_obstacles=cfg.backbone or cfg.reflexes)  # fmt: skip
    weights = {k: v for k, v in (("b0", cfg.b0), ("q0", cfg.q0)) if v is not None}
    climbing = {k: True for k in ("reflexes", "backbone") if getattr(cfg, k)}
    v = get_variant(cfg.variant, cfg.params)
    gait = LocomotionParams(cpg=CpgParams.for_gait(cfg.gait))
    kwargs: dict[str, Any] = {**weights, **climbing, "locomotion": v.locomotion(gait)}
    if cfg.controller != "fixed":
        kwargs["sensory"] = v.sensory
    controller = make_controller(cfg.controller, steer=cfg.steer, **kwargs)
    return arena, body, controller


@dataclass(frozen=True)
class Resume:
    """Where a stopped physics run goes on: the step, the pickled (body, controller), the rows before it."""

    step: int
    state: bytes
    head: Trajectory


class RunInterruptedError(Exception):
    """A run stopped part-way (e.g. Ctrl-C); ``episode`` holds the steps it completed."""

    def __init__(self, episode: Episode) -> None:
        super().__init__(f"run stopped after {episode.summary['steps']} of {episode.config.steps} steps")
        self.episode = episode


def run_episode(cfg: EpisodeConfig, *, progress: bool = False, sink: Any = None, chunk: int = 10_000,
                pad_boxes: int | None = None, checkpoint: Any = None,
                resume: Resume | None = None) -> Episode:  # fmt: skip
    """Run one episode and summarise it.

    Args:
        cfg: the run.
        progress: show a progress bar (rate, time left).
        sink: if given, called as ``sink(trajectory, start, stop)`` after every ``chunk`` steps and at
            the end, so that a long run can write its rows as it goes.
        chunk: rows per sink call.
        pad_boxes: run AMOSII on the model with that many obstacle slots, as :mod:`neurowalk.sim.batch` does.
        checkpoint: physics only: called as ``checkpoint(step, state)`` after each ``chunk`` steps' sink call,
            ``state`` the whole body and controller (MuJoCo state, noise generators, networks) as bytes.
        resume: physics only: go on from such a checkpoint (:class:`Resume`); the continuation is bit for bit
            the run that was not stopped.

    Raises:
        RunInterruptedError: on KeyboardInterrupt; it carries the episode of the completed steps (the sink
            has received all of them).
    """
    if cfg.body == "surrogate":
        from neurowalk.sim.surrogate_episode import run_surrogate_episode

        return run_surrogate_episode(cfg, progress=progress, sink=sink, chunk=chunk)
    arena, body, ctrl = build(cfg, pad_boxes=pad_boxes)
    assert isinstance(body, AmosII)
    body_rng, ctrl_rng, _ = seeds(cfg)
    body.reset(body_rng)
    ctrl.reset(ctrl_rng)
    tr = Trajectory.empty(cfg.steps, body.model.nq)
    start = 0
    if resume is not None:
        start = resume.step
        body, ctrl = pickle.loads(resume.state)
        for f in fields(Trajectory):
            getattr(tr, f.name)[:start] = getattr(resume.head, f.name)[:start]
    has_weights = hasattr(ctrl, "b")
    bar = _progress(cfg.steps, progress)
    if bar is not None:
        bar.update(start)
    t0 = time.perf_counter()
    done = start
    try:
        done = _loop(cfg, body, ctrl, tr, has_weights, bar, sink, chunk, start, checkpoint)
    except KeyboardInterrupt:
        done = int(np.count_nonzero(~np.isnan(tr.t)))
    wall = time.perf_counter() - t0
    if bar is not None:
        bar.close()
    if sink is not None and done % chunk:
        sink(_finish(tr, body, done - done % chunk, done), done - done % chunk, done)
    ep = _episode(cfg, arena, body, tr, done, wall)
    if done < cfg.steps:
        raise RunInterruptedError(ep)
    return ep


def _loop(cfg: EpisodeConfig, body: AmosII, ctrl: Controller, tr: Trajectory, has_weights: bool, bar: Any,
          sink: Any, chunk: int, start: int = 0, checkpoint: Any = None) -> int:  # fmt: skip
    """The control loop proper, from step ``start``; returns the number of completed steps."""
    d = body.data
    for k in range(start, cfg.steps):
        obs = body.observe()
        targets = ctrl.act(obs)
        body.apply(targets)
        body.advance()
        tr.inputs[k] = ctrl.inputs
        tr.outputs[k] = ctrl.steering
        if has_weights:
            tr.b[k] = ctrl.b  # type: ignore[attr-defined]
            tr.q[k] = ctrl.q  # type: ignore[attr-defined]
        tr.targets[k] = targets
        tr.us_distance[k] = obs.us_distance
        tr.foot_contact[k] = obs.foot_contact
        tr.qpos[k] = d.qpos
        tr.t[k] = d.time  # last: a row with a time is complete
        if bar is not None and k % 100 == 99:
            bar.update(100)
        if sink is not None and (k + 1) % chunk == 0:
            sink(_finish(tr, body, k + 1 - chunk, k + 1), k + 1 - chunk, k + 1)
            if checkpoint is not None and k + 1 < cfg.steps:
                checkpoint(k + 1, pickle.dumps((body, ctrl)))
    return cfg.steps


def _finish(tr: Trajectory, body: AmosII, start: int, stop: int) -> Trajectory:
    """Fill the derived arrays (pose, joint angles, up_z) of rows [start, stop) from qpos; return ``tr``."""
    q = tr.qpos[start:stop]
    tr.pose[start:stop] = poses_from_qpos(q)
    tr.joint_angles[start:stop] = q[:, 7:][:, _joint_order(body)]
    tr.up_z[start:stop] = up_z_from_qpos(q)
    return tr


def _episode(cfg: EpisodeConfig, arena: ArenaSpec, body: AmosII, tr: Trajectory, done: int, wall: float) -> Episode:
    tr = _finish(tr, body, 0, done).head(done)
    run_cfg = cfg if done == cfg.steps else replace(cfg, steps=max(done, 1))
    summary = summarize(run_cfg, arena, tr, wall, body.warnings()) if done else {"steps": 0}
    summary["completed"] = done == cfg.steps
    summary["steps_requested"] = cfg.steps
    return Episode(cfg, arena, tr, summary)


def _progress(total: int, on: bool) -> Any:
    if not on:
        return None
    from tqdm import tqdm

    return tqdm(total=total, unit="step", desc="episode", mininterval=0.5, smoothing=0.1)


def _joint_order(body: AmosII) -> np.ndarray:
    return body._qidx - 7


def _start_weights(cfg: EpisodeConfig) -> dict[str, float]:
    """The plastic network's start weights: the config's, else the variant's (b0, q0)."""
    p = get_variant(cfg.variant, cfg.params).sensory
    b = cfg.b0 if cfg.b0 is not None else (p.b_start if p.b_start is not None else 0.0)
    q = cfg.q0 if cfg.q0 is not None else (p.q_start if p.q_start is not None else 0.0)
    return {"b0": b, "q0": q}


def summarize(cfg: EpisodeConfig, arena: ArenaSpec, tr: Trajectory, wall_time_s: float,
              warnings: dict[str, int]) -> dict[str, Any]:  # fmt: skip
    """summary.json of DESIGN §5, plus steering-run figures."""
    pose = tr.pose
    has_z = tr.qpos.shape[1] > 2
    sim_time = cfg.steps / cfg.control_hz
    weights = None
    if not np.isnan(tr.b[-1]).any():
        c = -0.5 * float(tr.q[-1].sum())
        weights = {"b": tr.b[-1].tolist(), "q": tr.q[-1].tolist(), "c": c}
    wedged = metrics.wedged_periods(pose, control_hz=cfg.control_hz, us_distance=tr.us_distance)
    if wedged and has_z:  # physics: replay the wedged steps' obstacle contacts from the recorded positions
        rows = np.concatenate([np.arange(p["start"], p["end"] + 1) for p in wedged])
        touch = obstacle_contacts(arena, tr.qpos, rows)
        wedged = metrics.wedged_periods(pose, control_hz=cfg.control_hz, us_distance=tr.us_distance, contact=touch)
    return {
        "arena": cfg.arena,
        "arena_opts": arena.options,
        "controller": cfg.controller,
        "steer": list(cfg.steer) if cfg.steer is not None else None,
        "body": cfg.body,
        "steps": cfg.steps,
        "seed": cfg.seed,
        "control_hz": cfg.control_hz,
        "noise": cfg.noise,
        "start_weights": _start_weights(cfg) if cfg.controller == "plastic" else None,
        "reflexes": cfg.reflexes,
        "backbone": cfg.backbone,
        "variant": cfg.variant,
        "params": cfg.params,
        "gait": cfg.gait,
        "final_z_m": float(tr.qpos[-1, 2]) if has_z else None,  # trunk height (None: planar body)
        "max_z_m": float(np.max(tr.qpos[:, 2])) if has_z else None,
        "exit_step": metrics.exit_step(pose, arena),
        "escaped": metrics.escaped(pose, arena),
        "trapped": metrics.trapped(pose),
        "ever_trapped": metrics.ever_trapped(pose),
        "ever_held_up_1000s": metrics.ever_trapped(pose, window=round(1000 * cfg.control_hz)),
        "end_turn_share": metrics.latched_turn_share(tr.outputs[-3000:]),
        "end_blind_share": float(np.mean(np.all(~(tr.us_distance[-3000:] < metrics.BLIND_M), axis=1))),
        "coverage": metrics.coverage(pose, arena),
        "path_length_m": metrics.path_length(pose),
        "forward_displacement_m": metrics.forward_displacement(pose, arena.start),
        "net_displacement_m": float(np.linalg.norm(pose[-1, :2] - np.asarray(arena.start[:2]))),
        "heading_change_deg": float(np.degrees(metrics.heading_change(pose, arena.start[2]))),
        "min_up_z": float(np.min(tr.up_z)),
        "direction_switches": metrics.direction_switches(tr.outputs),
        "turn_episodes": len(turns := metrics.avoidance_episodes(tr.outputs, pose)),
        "max_turn_deg": max((abs(e["turn_deg"]) for e in turns), default=0.0),
        **metrics.wedged_summary(wedged),  # wedged_periods (count), longest_wedged_s, wedged_causes
        "wedged": wedged,  # the periods: start, end (steps), duration_s, centre, extent_m, fractions, cause
        "final_pose": pose[-1].tolist(),
        "final_weights": weights,
        "simulation_warnings": warnings,
        "wall_time_s": wall_time_s,
        "real_time_factor": sim_time / wall_time_s if wall_time_s > 0 else None,
        "neurowalk_version": neurowalk.__version__,
    }
