"""The compiled metrics give exactly the numpy reference's answers (tests/metrics_reference.py): same floats, same
booleans, on real surrogate and physics runs, on edge cases and on random walks."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from metrics_reference import _fitting_windows as ref_fitting_windows
from metrics_reference import avoidance_episodes as ref_avoidance_episodes
from metrics_reference import coverage as ref_coverage
from metrics_reference import direction_switches as ref_direction_switches
from metrics_reference import ever_trapped as ref_ever_trapped
from metrics_reference import heading_change as ref_heading_change
from metrics_reference import latched_turn_share as ref_latched_turn_share
from metrics_reference import path_length as ref_path_length
from metrics_reference import turn_state as ref_turn_state
from metrics_reference import wedged_periods as ref_wedged_periods
from neurowalk import metrics, metrics_kernel
from neurowalk.arenas import make_arena
from neurowalk.sim.episode import EpisodeConfig, run_episode
from neurowalk.sim.summarize import blind_readings

RANDOM = {"extent": 9.0, "size": 1.0}


def _same(pose: np.ndarray, outputs: np.ndarray, arena: object, blind: np.ndarray | None = None) -> None:
    """Every compiled metric equals its reference on this run (pose (T, 3), outputs (T, 2))."""
    for window, radius, stride in ((3000, 0.5, 100), (10000, 0.5, 100), (500, 0.2, 100), (700, 0.3, 33)):
        kw = {"window": window, "radius": radius, "stride": stride}
        assert metrics.ever_trapped(pose, **kw) is ref_ever_trapped(pose, **kw), kw
    for cell in (0.25, 0.4):
        assert metrics.coverage(pose, arena, cell) == ref_coverage(pose, arena, cell)  # type: ignore[arg-type]
    assert metrics.avoidance_episodes(outputs, pose) == ref_avoidance_episodes(outputs, pose)
    _same_turns(outputs)
    _same_path(pose)
    for radius in (0.3, 0.5, 1.0):
        for window, stride in ((1001, 10), (250, 7)):
            new = metrics._fitting_windows(pose[:, :2], window, radius, stride)
            assert np.array_equal(new, ref_fitting_windows(pose[:, :2], window, radius, stride))
        kw = {"control_hz": 10.0, "radius": radius, "blind": blind}
        assert _disc(metrics.wedged_periods(pose, **kw)) == ref_wedged_periods(pose, **kw)
        _same_held(pose, **kw)


#: Keys of a wedged period that the held rule added after the reference was copied (the heading band).
HELD_KEYS = ("heading_range_deg", "held", "held_s")


def _disc(periods: list[dict]) -> list[dict]:
    """``periods`` without :data:`HELD_KEYS`: what the reference (the disc rule only) computes."""
    return [{k: v for k, v in p.items() if k not in HELD_KEYS} for p in periods]


def _same_held(pose: np.ndarray, control_hz: float = 10.0, stride: int = 10, radius: float = 0.3, **_: object) -> None:
    """The held steps of :func:`metrics.wedged_periods` equal a plain numpy check of every stretch: rows in some
    stretch (every ``stride`` rows and the last) whose positions lie within ``radius`` of their mean and whose
    unwrapped yaw's range is within the band; each period's heading range is numpy's."""
    n = len(pose)
    window = int(np.floor(metrics.WEDGE_MIN_S * control_hz + 1e-9)) + 1
    starts = sorted({*range(0, n - window + 1, stride), n - window}) if n >= window else []
    yaw = np.unwrap(pose[:, 2])
    fits, ptp = [], []
    for s in starts:
        seg = pose[s : s + window, :2]
        fits.append(bool(np.max(np.sum((seg - seg.mean(axis=0)) ** 2, axis=1)) <= radius * radius))
        ptp.append(np.ptp(yaw[s : s + window]))
    for band in (5.0, metrics.HELD_HEADING_DEG, 120.0):
        want = np.zeros(n, dtype=bool)
        for s, fit, sweep in zip(starts, fits, ptp, strict=True):
            if fit and sweep <= np.radians(band):
                want[s : s + window] = True
        got = np.zeros(n, dtype=bool)
        periods = metrics.wedged_periods(pose, control_hz=control_hz, stride=stride, radius=radius, heading_deg=band)
        for p in periods:
            for a, b in p["held"]:
                got[a : b + 1] = True
            assert p["heading_range_deg"] == np.degrees(np.ptp(yaw[p["start"] : p["end"] + 1]))
        assert np.array_equal(got, want), band


@pytest.fixture(scope="module")
def surrogate_runs() -> list:
    """Surrogate runs of 20,000 steps: random arenas of every clutter, the three networks, other arenas."""
    cfgs = [
        EpisodeConfig(body="surrogate", arena="random", arena_opts={"n_boxes": n, **RANDOM}, controller=c, seed=s)
        for s, (n, c) in enumerate([(2, "plastic"), (8, "static"), (14, "braitenberg"), (20, "plastic")])
    ]
    cfgs += [
        EpisodeConfig(body="surrogate", arena=a, seed=3) for a in ("open", "box", "simple-deadlock", "narrow-passage")
    ]
    cfgs.append(EpisodeConfig(body="surrogate-wheeled", arena="cluttered", seed=5))
    return [run_episode(c.replace(steps=20_000)) for c in cfgs]


def test_surrogate_runs_give_the_reference_metrics(surrogate_runs: list) -> None:
    trapped = set()
    for ep in surrogate_runs:
        tr = ep.trajectory
        _same(tr.pose, tr.outputs, ep.arena, blind_readings(tr.us_distance))
        trapped.add(ep.summary["ever_trapped"])
    assert trapped == {True, False}  # both answers are checked


def test_physics_runs_give_the_reference_metrics() -> None:
    for cfg in (
        EpisodeConfig(body="wheeled", arena="cluttered", steps=3200, seed=2),
        EpisodeConfig(body="amosii", arena="box", steps=300, seed=1),  # shorter than every window
    ):
        ep = run_episode(cfg)
        _same(ep.trajectory.pose, ep.trajectory.outputs, ep.arena, blind_readings(ep.trajectory.us_distance))


def _same_turns(outputs: np.ndarray) -> None:
    """Turn states, switches and the latched share equal the reference's."""
    for threshold in (1.0, 0.3):
        got, want = metrics.turn_state(outputs, threshold), ref_turn_state(outputs, threshold)
        assert got.dtype == want.dtype and np.array_equal(got, want)
        assert metrics.direction_switches(outputs, threshold) == ref_direction_switches(outputs, threshold)
        assert metrics.latched_turn_share(outputs, threshold) == ref_latched_turn_share(outputs, threshold)


def _same_path(pose: np.ndarray) -> None:
    """Path length and heading change (from the first row's yaw and from others) equal the reference's."""
    assert metrics.path_length(pose) == ref_path_length(pose)
    for start in (None, 0.0, 3.0, -np.pi, np.pi):
        assert metrics.heading_change(pose, start) == ref_heading_change(pose, start)


def _agree(new: Callable[[], object], ref: Callable[[], object]) -> None:
    """``new()`` equals ``ref()``, or both refuse (ValueError: a window shorter than the stride)."""
    try:
        want = ref()
    except ValueError:
        with pytest.raises(ValueError, match="shorter than stride"):
            new()
        return
    got = new()
    assert np.array_equal(got, want) if isinstance(want, np.ndarray) else got == want


def _same_marks(pose: np.ndarray, window: int, radius: float, stride: int) -> None:
    """The wedged-stretch marks equal the reference's, or both refuse."""
    args = (pose[:, :2], window, radius, stride)
    _agree(lambda: metrics._fitting_windows(*args), lambda: ref_fitting_windows(*args))


def _still(n: int, radius: float = 0.1, seed: int = 0) -> np.ndarray:
    """(n, 3) poses jittering inside a disc of ``radius`` around (1, 2)."""
    rng = np.random.default_rng(seed)
    ang, r = rng.uniform(0, 2 * np.pi, n), radius * np.sqrt(rng.uniform(0, 1, n))
    return np.column_stack([1 + r * np.cos(ang), 2 + r * np.sin(ang), rng.uniform(-3, 3, n)])


@pytest.mark.parametrize("n", [1, 299, 300, 301, 399, 400, 401, 1000])
def test_lengths_around_the_window(n: int) -> None:
    arena = make_arena("random", rng=np.random.default_rng(0), n_boxes=5, **RANDOM)
    pose = _still(n)
    outputs = np.random.default_rng(n).uniform(-1, 1, (n, 2)) * [1.6, 0.8]
    for window in (299, 300, 301, 400):
        for stride in (1, 7, 100, 500):
            kw = {"window": window, "stride": stride, "radius": 0.1}
            assert metrics.ever_trapped(pose, **kw) is ref_ever_trapped(pose, **kw)
            _same_marks(pose, window, 0.1, stride)
    assert metrics.coverage(pose, arena) == ref_coverage(pose, arena)
    assert metrics.avoidance_episodes(outputs, pose) == ref_avoidance_episodes(outputs, pose)
    for hz in (1.0, 3.0, 10.0):  # windows of 101, 301, 1001 rows
        assert _disc(metrics.wedged_periods(pose, control_hz=hz)) == ref_wedged_periods(pose, control_hz=hz)


def test_ties_nan_and_inf_rows() -> None:
    n = 4000
    tie = np.zeros((n, 3))
    tie[:, 0] = np.where(np.arange(n) % 2, 0.5, -0.5)  # every point exactly at radius 0.5 from the mean 0
    for r in (0.5, np.nextafter(0.5, 0)):
        assert metrics.ever_trapped(tie, radius=r) is ref_ever_trapped(tie, radius=r)
        got = metrics._fitting_windows(tie[:, :2], 1001, r, 10)
        assert np.array_equal(got, ref_fitting_windows(tie[:, :2], 1001, r, 10))
    assert metrics.ever_trapped(tie, radius=0.5) and not metrics.ever_trapped(tie, radius=np.nextafter(0.5, 0))
    for bad in (np.nan, np.inf, -np.inf):
        for rows in ([0], [n - 1], [1500], list(range(0, n, 97))):
            pose = _still(n)
            pose[rows, 0] = bad
            for kw in ({}, {"window": 1000, "stride": 10}):
                assert metrics.ever_trapped(pose, **kw) is ref_ever_trapped(pose, **kw)
            got = metrics._fitting_windows(pose[:, :2], 1001, 0.3, 10)
            assert np.array_equal(got, ref_fitting_windows(pose[:, :2], 1001, 0.3, 10))
            arena = make_arena("random", rng=np.random.default_rng(0), n_boxes=3, **RANDOM)
            with np.errstate(invalid="ignore"):
                assert metrics.coverage(pose, arena) == ref_coverage(pose, arena)


def test_unbounded_and_empty() -> None:
    pose = _still(5000)
    assert metrics.coverage(pose, make_arena("open")) is None is ref_coverage(pose, make_arena("open"))
    assert metrics.avoidance_episodes(np.zeros((0, 2)), np.zeros((0, 3))) == []
    with pytest.raises(ValueError, match="stride"):
        metrics.ever_trapped(pose, stride=0)


def test_an_undecided_stretch_is_left_to_numpy() -> None:
    xy = np.zeros((400, 2))
    xy[::2, 0], xy[1::2, 0] = -0.5, 0.5
    found, undecided = metrics_kernel.ever_fits(xy, 300, 0.5, 100)
    assert not found and undecided.tolist() == [0, 100]  # exact ties: numpy decides them (they fit)
    found, undecided = metrics_kernel.ever_fits(xy, 300, 0.6, 100)
    assert found and undecided.size == 0


def test_a_stretch_with_no_whole_block_is_not_called_wide() -> None:
    # 732 rows, stretches of 11 every 10: the last, [721, 732), holds no whole block of 10 rows. The wide bound
    # over zero blocks once compared a stretch's first block with the run's last one (0.73 m of drift away), so
    # the early stretches, 1 cm long, were dropped as wide.
    xy = _walk(0, 732, 0.0, 0.001)[:, :2]
    want = [
        s
        for s in sorted({*range(0, 722, 10), 721})
        if np.max(np.sum((xy[s : s + 11] - xy[s : s + 11].mean(axis=0)) ** 2, axis=1)) <= 0.3**2
    ]
    assert want[:3] == [0, 10, 20]  # the early stretches fit
    assert metrics._fitting_starts(xy, 11, 0.3, 10).tolist() == want
    assert np.array_equal(metrics._fitting_windows(xy, 11, 0.3, 10), ref_fitting_windows(xy, 11, 0.3, 10))


def _walk(seed: int, n: int, step: float, drift: float) -> np.ndarray:
    """(n, 3) poses of a random walk (``step`` m per row, a ``drift`` m per row to +x)."""
    rng = np.random.default_rng(seed)
    moves = rng.normal(0, step, (n, 2)) + np.array([drift, 0.0])
    xy = np.cumsum(moves, axis=0) + rng.uniform(-4, 4, 2)
    return np.column_stack([xy, np.cumsum(rng.normal(0, 0.2, n))])


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    n=st.integers(1, 6000),
    step=st.sampled_from([0.0, 1e-4, 0.003, 0.01, 0.05]),
    drift=st.sampled_from([0.0, 1e-4, 0.001]),
    window=st.integers(1, 3000),
    stride=st.integers(1, 300),
    radius=st.sampled_from([0.05, 0.3, 0.5, 1.0]),
)
def test_random_walks_give_the_reference_metrics(
    seed: int, n: int, step: float, drift: float, window: int, stride: int, radius: float
) -> None:
    pose = _walk(seed, n, step, drift)
    kw = {"window": window, "radius": radius, "stride": stride}
    assert metrics.ever_trapped(pose, **kw) is ref_ever_trapped(pose, **kw)
    _same_marks(pose, window, radius, stride)
    arena = make_arena("random", rng=np.random.default_rng(seed), n_boxes=1 + seed % 20, **RANDOM)
    assert metrics.coverage(pose, arena) == ref_coverage(pose, arena)
    outputs = np.random.default_rng(seed).normal(0, 1.2, (n, 2))
    assert metrics.avoidance_episodes(outputs, pose) == ref_avoidance_episodes(outputs, pose)
    hz = window / 100.0  # windows of window + 1 rows
    _agree(lambda: _disc(metrics.wedged_periods(pose, control_hz=hz)), lambda: ref_wedged_periods(pose, control_hz=hz))
    if window >= 10:  # a stretch of more rows than the stride
        _same_held(pose, control_hz=hz)


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    n=st.integers(1, 3000),
    spread=st.sampled_from([0.1, 1.0, 3.0, 10.0]),
    grid=st.booleans(),
)
def test_unwrapped_headings_and_path_lengths(seed: int, n: int, spread: float, grid: bool) -> None:
    rng = np.random.default_rng(seed)
    yaw = rng.uniform(-spread, spread, n)
    if grid:  # multiples of pi / 4: jumps of exactly pi and 2 pi, the unwrap's ties
        yaw = np.round(yaw * 4 / np.pi) * np.pi / 4
    pose = np.column_stack([np.cumsum(rng.normal(0, 0.01, (n, 2)), axis=0), yaw])
    _same_path(pose)
    outputs = rng.normal(0, 1.2, (n, 2))
    if grid:
        outputs[:: 7 + seed % 5] = [[1.0, 0.0], [np.nan, 0.0], [0.0, 1.0]][seed % 3]  # at the threshold, NaN
    assert metrics.avoidance_episodes(outputs, pose) == ref_avoidance_episodes(outputs, pose)
    _same_turns(outputs)


def test_unwrap_and_steps_on_special_values() -> None:
    yaw = np.array([0.0, np.pi, 0.0, -np.pi, np.pi, -0.0, 2 * np.pi, np.nan, 1.0, np.inf, 0.5, -np.inf, 4.0])
    assert np.array_equal(metrics_kernel.unwrap(yaw), np.unwrap(yaw), equal_nan=True)
    with np.errstate(invalid="ignore"):
        xy = np.column_stack([yaw, yaw[::-1]])
        assert np.array_equal(
            metrics_kernel.step_lengths(xy), np.linalg.norm(np.diff(xy, axis=0), axis=1), equal_nan=True
        )
