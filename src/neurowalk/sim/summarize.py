"""summary.json of a run (DESIGN §5) from the columns it needs (:class:`Record`)."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

import neurowalk
from neurowalk import fingerprint, metrics
from neurowalk.arenas import ArenaSpec
from neurowalk.arenas.climbing import CLIMB_WORDS
from neurowalk.body.registry import body_settings, physics_settings, replay_contacts
from neurowalk.neural.variants import get_variant
from neurowalk.sim.config import EpisodeConfig
from neurowalk.sim.trajectory import Trajectory


def _start_weights(cfg: EpisodeConfig) -> dict[str, float]:
    """The plastic network's start weights: the config's, else the variant's (b0, q0)."""
    p = get_variant(cfg.variant, cfg.params).sensory
    b = cfg.b0 if cfg.b0 is not None else (p.b_start if p.b_start is not None else 0.0)
    q = cfg.q0 if cfg.q0 is not None else (p.q_start if p.q_start is not None else 0.0)
    return {"b0": b, "q0": q}


@dataclass
class Record:
    """What a run's summary needs of its rows (a streamed run keeps only this in memory: 41 bytes a step).

    Attributes:
        pose: (T, 3) x m, y m, yaw rad. outputs: (T, 2) steering. blind: (T,) bool, both ultrasonic readings
        at or beyond :data:`~neurowalk.metrics.BLIND_M` (or no echo). final_z, max_z: trunk height after the
        last step and its highest, m (None for the planar surrogate). min_up_z: lowest trunk up-vector z.
        final_b, final_q: (2,) the sensory weights after the last step (NaN for a fixed controller).
    """

    pose: np.ndarray
    outputs: np.ndarray
    blind: np.ndarray
    final_z: float | None
    max_z: float | None
    min_up_z: float
    final_b: np.ndarray
    final_q: np.ndarray

    @classmethod
    def of(cls, tr: Trajectory) -> Record:
        """The record of a whole trajectory in memory."""
        z = tr.qpos[:, 2] if tr.qpos.shape[1] > 2 else None
        return cls(
            tr.pose,
            tr.outputs,
            blind_readings(tr.us_distance),
            None if z is None else float(z[-1]),
            None if z is None else float(np.max(z)),
            float(np.min(tr.up_z)),
            tr.b[-1],
            tr.q[-1],
        )


class RecordKeeper:
    """The summary's columns and a picture's rows of a streamed run, kept as its chunks go by (any body).

    :meth:`keep` takes the rows of steps [start, start + n); :meth:`record` and :meth:`picture` give those of the
    first ``done`` steps. Memory: 41 bytes a step, plus at most ``picture_rows`` rows (every ``stride``-th).
    """

    def __init__(
        self, steps: int, nq: int, picture_rows: int, state: Mapping[str, tuple[int, ...]] | None = None
    ) -> None:
        self.stride = max(1, math.ceil(steps / picture_rows))
        self.rec = Record(
            np.full((steps, 3), np.nan),
            np.full((steps, 2), np.nan),
            np.zeros(steps, dtype=bool),
            None,
            None,
            1.0,
            np.full(2, np.nan),
            np.full(2, np.nan),
        )
        self.pic = Trajectory.empty(math.ceil(steps / self.stride), nq, state)

    def keep(self, rows: Trajectory, start: int, stop: int) -> None:
        """Copy the columns and picture rows of steps [start, stop) (``rows`` from ``start``)."""
        r, n = self.rec, stop - start
        r.pose[start:stop], r.outputs[start:stop] = rows.pose[:n], rows.outputs[:n]
        r.blind[start:stop] = blind_readings(rows.us_distance[:n])
        if rows.qpos.shape[1] > 2:  # a MuJoCo body: trunk height
            z = rows.qpos[:n, 2]
            r.final_z, r.max_z = float(z[-1]), max(float(np.max(z)), -np.inf if r.max_z is None else r.max_z)
        r.min_up_z = min(r.min_up_z, float(np.min(rows.up_z[:n])))
        r.final_b, r.final_q = rows.b[n - 1].copy(), rows.q[n - 1].copy()
        first = -(-start // self.stride) * self.stride  # the first picture row at or after start
        take = np.arange(first, stop, self.stride)
        pic = self.pic.arrays()
        for k, src in rows.arrays().items():
            if src.shape[1:] == pic[k].shape[1:]:
                pic[k][take // self.stride] = src[take - start]

    def record(self, done: int) -> Record:
        """The record of the first ``done`` steps."""
        r = self.rec
        return Record(
            r.pose[:done], r.outputs[:done], r.blind[:done], r.final_z, r.max_z, r.min_up_z, r.final_b, r.final_q
        )

    def picture(self, done: int) -> Trajectory:
        """Every ``stride``-th row of the first ``done`` steps."""
        return self.pic.head(-(-done // self.stride))


def blind_readings(us_distance: np.ndarray) -> np.ndarray:
    """(T,) bool: both readings of ``us_distance`` (T, 2) at or beyond :data:`~neurowalk.metrics.BLIND_M` m."""
    us = np.asarray(us_distance)
    if us.ndim == 2 and us.shape[1] == 2:  # the same answer, without a reduction over rows of two
        return ~((us[:, 0] < metrics.BLIND_M) | (us[:, 1] < metrics.BLIND_M))
    return np.all(~(us < metrics.BLIND_M), axis=1)


STUCK_S = 300.0
"""Simulated time (s) of the stuck window of ``trapped``, ``ever_trapped`` and the end shares, at any control rate
(3000 control steps at 10 Hz)."""
PICTURE_ROWS = 10_000  # rows (at most) a streamed run keeps for its picture
REPLAY_BLOCK = 50_000  # rows of positions replayed at a time (about 10 MB)


def summarize(
    cfg: EpisodeConfig,
    arena: ArenaSpec,
    tr: Trajectory | Record,
    wall_time_s: float,
    warnings: dict[str, int],
    *,
    qpos_rows: Callable[[np.ndarray], np.ndarray] | None = None,
    steps: int | None = None,
) -> dict[str, Any]:
    """summary.json of DESIGN §5, plus steering-run figures.

    Args:
        tr: the run's trajectory, or the :class:`Record` of it.
        steps: the control steps the run made (default ``cfg.steps``: fewer for a run that stopped part-way).
        qpos_rows: physics runs given as a Record: ``qpos_rows(rows)`` returns those rows' (len(rows), nq)
            positions (to replay the obstacle contacts of wedged periods, :data:`REPLAY_BLOCK` rows at a time);
            with a Trajectory, its own qpos.
    """
    if isinstance(tr, Trajectory):
        rec = Record.of(tr)
        if qpos_rows is None and rec.final_z is not None:
            qpos_rows = tr.qpos.__getitem__
    else:
        rec = tr
    pose = rec.pose
    steps = cfg.steps if steps is None else steps
    sim_time = steps / cfg.control_hz
    stuck = round(STUCK_S * cfg.control_hz)  # the stuck window in control steps
    weights = None
    if not np.isnan(rec.final_b).any():
        c = -0.5 * float(rec.final_q.sum())
        weights = {"b": rec.final_b.tolist(), "q": rec.final_q.tolist(), "c": c}
    wedged = metrics.wedged_periods(pose, control_hz=cfg.control_hz, blind=rec.blind)
    if wedged and rec.final_z is not None and qpos_rows is not None:  # physics: replay the wedged steps' contacts
        rows = np.concatenate([np.arange(p["start"], p["end"] + 1) for p in wedged])
        touch = np.full(len(pose), np.nan)
        for block in np.array_split(rows, -(-len(rows) // REPLAY_BLOCK)):
            touch[block] = replay_contacts(cfg.body, cfg.body_opts, arena, qpos_rows(block))
        wedged = metrics.wedged_periods(pose, control_hz=cfg.control_hz, blind=rec.blind, contact=touch)
    return {
        "arena": cfg.arena,
        "arena_opts": arena.options,
        "controller": cfg.controller,
        "steer": list(cfg.steer) if cfg.steer is not None else None,
        "body": cfg.body,
        "steps": steps,
        "seed": cfg.seed,
        "control_hz": cfg.control_hz,
        "noise": cfg.noise,
        "start_weights": _start_weights(cfg) if cfg.controller == "plastic" else None,
        "reflexes": cfg.reflexes,
        "backbone": cfg.backbone,
        "variant": cfg.variant,
        "params": cfg.params,
        "gait": cfg.gait,
        "body_opts": cfg.body_opts,
        "body_settings": body_settings(cfg.body, cfg.body_opts),
        "physics": physics_settings(cfg.body, cfg.body_opts, cfg.control_hz),
        "final_z_m": rec.final_z,  # trunk height (None: planar body)
        "max_z_m": rec.max_z,
        "exit_step": (exit_step := metrics.exit_step(pose, arena)),
        "escaped": metrics.escaped(pose, arena),
        **_climb(arena, exit_step, cfg.control_hz),
        "trapped": metrics.trapped(pose, window=stuck),
        "ever_trapped": metrics.ever_trapped(pose, window=stuck),
        "ever_held_up_1000s": metrics.ever_trapped(pose, window=round(1000 * cfg.control_hz)),
        "end_turn_share": metrics.latched_turn_share(rec.outputs[-stuck:]),
        "end_blind_share": float(np.mean(rec.blind[-stuck:])),
        "coverage": metrics.coverage(pose, arena),
        "path_length_m": metrics.path_length(pose),
        "forward_displacement_m": metrics.forward_displacement(pose, arena.start),
        "net_displacement_m": float(np.linalg.norm(pose[-1, :2] - np.asarray(arena.start[:2]))),
        "heading_change_deg": float(np.degrees(metrics.heading_change(pose, arena.start[2]))),
        "min_up_z": rec.min_up_z,
        "direction_switches": metrics.direction_switches(rec.outputs),
        "turn_episodes": len(turns := metrics.avoidance_episodes(rec.outputs, pose)),
        "max_turn_deg": max((abs(e["turn_deg"]) for e in turns), default=0.0),
        # wedged_periods (count), longest_wedged_s, wedged_causes, held_periods (count), longest_held_s,
        # turning_periods (count)
        **metrics.wedged_summary(wedged, cfg.control_hz),
        # the periods: start, end (steps), duration_s, centre, extent_m, fractions, cause, heading_range_deg,
        # held (runs of held steps), held_s
        "wedged": wedged,
        "final_pose": pose[-1].tolist(),
        "final_weights": weights,
        "simulation_warnings": warnings,
        "wall_time_s": wall_time_s,
        "real_time_factor": sim_time / wall_time_s if wall_time_s > 0 else None,
        "neurowalk_version": neurowalk.__version__,
        "code": fingerprint.code(cfg.files()),
    }


def _climb(arena: ArenaSpec, exit_step: int | None, control_hz: float) -> dict[str, Any]:
    """On an arena whose exit region is a platform to climb onto (:data:`~neurowalk.arenas.climbing.CLIMB_WORDS`):
    ``climbed`` (the trunk centre got onto it) and ``climbed_at_s`` (when, s; None: it did not); nothing elsewhere."""
    if arena.exit_words != CLIMB_WORDS:
        return {}
    return {"climbed": exit_step is not None, "climbed_at_s": None if exit_step is None else exit_step / control_hz}
