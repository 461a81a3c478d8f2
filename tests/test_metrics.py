import numpy as np
import pytest

from neurowalk import metrics
from neurowalk.arenas import make_arena


def _pose(xy, yaw=None):
    xy = np.asarray(xy, dtype=float)
    return np.column_stack([xy, np.zeros(len(xy)) if yaw is None else yaw])


def test_trapped_escaped_coverage_path():
    arena = make_arena("simple-deadlock")
    still = _pose(np.full((4000, 2), 0.3))
    assert metrics.trapped(still) and not metrics.escaped(still, arena)
    out = _pose(np.column_stack([np.linspace(0, -2.0, 4000), np.zeros(4000)]))
    assert not metrics.trapped(out) and metrics.escaped(out, arena)
    assert not metrics.trapped(still[:100])  # too short to tell
    assert metrics.path_length(out) == pytest.approx(2.0)
    c1, c2 = metrics.coverage(still, arena), metrics.coverage(out, arena)
    assert 0 < c1 < c2 <= 1
    assert metrics.coverage(still, make_arena("open")) is None
    assert metrics.escaped(still, make_arena("open")) is None


def test_direction_switches_and_episodes():
    right, left, none = (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)
    outputs = np.array([none] * 5 + [right] * 10 + [none] * 3 + [right] * 4 + [left] * 6 + [none] * 5)
    assert metrics.direction_switches(outputs) == 1
    yaw = np.concatenate([np.zeros(5), -np.linspace(0, 1, 10), -np.ones(3), -1 - np.linspace(0, 0.2, 4),
                          -1.2 + np.linspace(0, 0.5, 6), np.full(5, -0.7)])  # fmt: skip
    eps = metrics.avoidance_episodes(outputs, _pose(np.zeros((len(yaw), 2)), yaw))
    assert [e["direction"] for e in eps] == [1, -1]  # the short gap is bridged
    assert eps[0]["turn_deg"] < 0 < eps[1]["turn_deg"]


def _walk(n, start=(0.0, 0.0), speed=0.0014, heading=0.0):
    """(n, 2) positions walking straight at ``speed`` m per control step (about full speed at 10 Hz)."""
    t = np.arange(n)[:, None]
    return np.asarray(start) + speed * t * [np.cos(heading), np.sin(heading)]


def _jitter(n, centre, radius, seed=0):
    """(n, 2) positions wandering inside a disc of ``radius`` around ``centre`` (turning on the spot, rocking)."""
    rng = np.random.default_rng(seed)
    ang, r = rng.uniform(0, 2 * np.pi, n), radius * np.sqrt(rng.uniform(0, 1, n))
    return np.asarray(centre) + np.column_stack([r * np.cos(ang), r * np.sin(ang)])


def test_wedged_periods_finds_each_stay_with_its_steps_and_duration():
    walk1 = _walk(800)
    stay1 = _jitter(1500, walk1[-1], 0.15)  # 150 s
    walk2 = _walk(900, stay1[-1], heading=1.0)
    stay2 = _jitter(3200, walk2[-1], 0.2, seed=1)  # 320 s
    walk3 = _walk(700, stay2[-1], heading=-2.0)
    xy = np.vstack([walk1, stay1, walk2, stay2, walk3])
    periods = metrics.wedged_periods(_pose(xy))
    assert len(periods) == 2
    a, b = periods
    # Each stay is found whole, with at most the walking steps that still fit the 0.3 m disc at either end
    # (0.3 m at 0.0014 m per step: about 210 steps, a little more as the walk pulls the mean).
    margin = 300
    assert 800 - margin <= a["start"] <= 800 and 2300 - 1 <= a["end"] <= 2300 + margin
    assert 3200 - margin <= b["start"] <= 3200 and 6400 - 1 <= b["end"] <= 6400 + margin
    assert 150 <= a["duration_s"] <= 150 + 2 * margin / 10 and 320 <= b["duration_s"] <= 320 + 2 * margin / 10
    assert a["end"] < b["start"]
    assert np.allclose(a["centre"], stay1.mean(axis=0), atol=0.05)
    assert a["duration_s"] == pytest.approx((a["end"] - a["start"] + 1) / 10)
    assert a["cause"] == "other" and a["blind_fraction"] is None and a["contact_fraction"] is None
    s = metrics.wedged_summary(periods)
    assert s["wedged_periods"] == 2 and s["longest_wedged_s"] == b["duration_s"]
    assert s["wedged_causes"] == {"other": 2}
    # yaw 0 throughout: every wedged step is held, each period one held run, none turning
    assert s["held_periods"] == 2 and s["longest_held_s"] == b["duration_s"] and s["turning_periods"] == 0


def test_wedged_periods_threshold_duration_radius_and_rate():
    still = _pose(_jitter(1000, (1.0, 2.0), 0.1))
    assert metrics.wedged_periods(still) == []  # exactly 100 s: not more than 100 s
    longer = _pose(_jitter(1001, (1.0, 2.0), 0.1))
    assert [p["duration_s"] for p in metrics.wedged_periods(longer)] == [100.1]
    assert metrics.wedged_periods(longer, control_hz=27.0) == []  # 37 s at 27 Hz
    assert len(metrics.wedged_periods(_pose(_jitter(2800, (0, 0), 0.1)), control_hz=27.0)) == 1
    wide = _pose(_jitter(3000, (0.0, 0.0), 0.45))  # wanders over 0.45 m: not within a 0.3 m disc
    assert metrics.wedged_periods(wide) == []
    assert len(metrics.wedged_periods(wide, radius=0.5)) == 1
    assert metrics.wedged_periods(_pose(_walk(20000))) == []  # walking at full speed never counts
    slow = _pose(_walk(20000, speed=0.0014 / 10))  # a tenth of the speed: 0.14 m per 100 s, wedged throughout
    assert [(p["start"], p["end"]) for p in metrics.wedged_periods(slow)] == [(0, 19999)]
    assert metrics.wedged_summary([]) == {
        "wedged_periods": 0,
        "longest_wedged_s": 0.0,
        "wedged_causes": {},
        "held_periods": 0,
        "longest_held_s": 0.0,
        "turning_periods": 0,
    }
    with pytest.raises(ValueError):
        metrics.wedged_periods(still, control_hz=0.0)


def test_wedged_periods_causes_from_rays_and_contact():
    xy = np.vstack([_walk(500), _jitter(2000, _walk(500)[-1], 0.1), _walk(500, _walk(500)[-1], heading=2.0)])
    pose, n = _pose(xy), len(xy)
    blind = np.full((n, 2), np.inf)
    seen = np.full((n, 2), 0.2)
    noisy_blind = np.column_stack([np.full(n, 0.39), np.full(n, np.inf)])  # noise echoes near 0.40 m are blind
    one_ray = np.column_stack([np.full(n, np.inf), np.full(n, 0.25)])  # one ray sees a box: not both blind
    touch, free = np.ones(n), np.zeros(n)

    def cause(**kw):
        (p,) = metrics.wedged_periods(pose, **kw)
        return p["cause"]

    assert cause(us_distance=blind) == cause(us_distance=noisy_blind) == "both rays blind"
    assert cause(us_distance=blind, contact=touch) == "both rays blind"  # blind rays explain it first
    assert cause(us_distance=seen, contact=touch) == cause(us_distance=one_ray, contact=touch) == "body contact"
    assert cause(us_distance=seen, contact=free) == cause(us_distance=seen) == cause(contact=free) == "other"
    # "most of the period": more than half of its steps
    (p,) = metrics.wedged_periods(pose)
    half = np.zeros(n)
    half[p["start"] : p["start"] + (p["end"] - p["start"] + 1) // 2] = 1
    assert cause(contact=half) == "other" and cause(contact=1 - half) == "body contact"
    # contact known only on some steps (NaN elsewhere): the share is taken over the known ones
    partial = np.full(n, np.nan)
    partial[p["start"] : p["start"] + 300] = 1.0
    (q,) = metrics.wedged_periods(pose, contact=partial)
    assert q["cause"] == "body contact" and q["contact_fraction"] == 1.0
    assert metrics.wedged_periods(pose, contact=np.full(n, np.nan))[0]["contact_fraction"] is None


HZ = 10.0  # control steps per second of the synthetic runs below


def _in_place(n: int, yaw: np.ndarray, seed: int = 0) -> np.ndarray:
    """(n, 3) poses of a robot whose trunk jitters 5 cm about (1, 2) with heading ``yaw`` (n,) rad."""
    return _pose(_jitter(n, (1.0, 2.0), 0.05, seed), yaw)


def _yaw_jitter(n: int, deg: float, seed: int = 0) -> np.ndarray:
    """(n,) headings (rad) jittering uniformly within +-``deg`` / 2 degrees about 0.3 rad."""
    return 0.3 + np.radians(np.random.default_rng(seed).uniform(-deg / 2, deg / 2, n))


def _held_steps(periods: list[dict]) -> np.ndarray:
    """The control steps of every held run of ``periods``."""
    return np.concatenate([np.arange(a, b + 1) for p in periods for a, b in p["held"]] or [np.zeros(0, int)])


def test_a_turn_in_place_is_wedged_but_not_held():
    n = 2000  # 200 s at 2 deg/s: 400 degrees, across the wrap of the yaw at +-pi
    yaw = np.angle(np.exp(1j * np.radians(2.0 * np.arange(n) / HZ)))  # wrapped into (-pi, pi]
    (p,) = metrics.wedged_periods(_in_place(n, yaw))
    assert (p["start"], p["end"]) == (0, n - 1)  # in the disc throughout
    assert p["held"] == [] and p["held_s"] == 0.0  # no 100 s stretch sweeps less than 200 degrees
    assert p["heading_range_deg"] == pytest.approx(2.0 * (n - 1) / HZ)  # unwrapped: the whole sweep
    s = metrics.wedged_summary([p])
    assert s["held_periods"] == 0 and s["longest_held_s"] == 0.0 and s["turning_periods"] == 1


def test_a_robot_sitting_still_with_small_yaw_jitter_is_held():
    n = 2000
    (p,) = metrics.wedged_periods(_in_place(n, _yaw_jitter(n, 10.0)))
    assert p["held"] == [[0, n - 1]] and p["held_s"] == p["duration_s"] == n / HZ
    assert p["heading_range_deg"] <= 10.0
    s = metrics.wedged_summary([p])
    assert s["held_periods"] == 1 and s["longest_held_s"] == n / HZ and s["turning_periods"] == 0


def test_sitting_then_turning_is_held_over_the_still_part_only():
    still, turn = 1500, 1500  # 150 s still, then 150 s turning at 2 deg/s, in the same disc
    rate = np.radians(2.0) / HZ  # rad per step
    yaw = np.concatenate([_yaw_jitter(still, 4.0), 0.3 + rate * np.arange(1, turn + 1)])
    (p,) = metrics.wedged_periods(_in_place(still + turn, yaw))
    assert (p["start"], p["end"]) == (0, still + turn - 1)  # one wedged period over both
    assert p["heading_range_deg"] > 250.0
    ((a, b),) = p["held"]
    assert a == 0 and b >= still - 1  # the whole still part is held ...
    # ... and at most the part of the turn a stretch of the band can reach: 30 degrees at 2 deg/s, 15 s
    assert b <= still - 1 + metrics.HELD_HEADING_DEG / 2.0 * HZ + 10  # (+ one stride of the stretch starts)
    assert metrics.wedged_summary([p])["turning_periods"] == 0  # it holds a held run: not a turning period


def test_held_threshold_boundary_and_argument():
    n = 1500
    for deg, held in ((29.0, True), (31.0, False)):  # the heading's range over the run, just inside / outside
        yaw = 0.3 + np.radians(deg) * (np.arange(n) % 2)  # alternates between two headings deg apart
        (p,) = metrics.wedged_periods(_in_place(n, yaw))
        assert bool(p["held"]) is held, deg
        assert p["heading_range_deg"] == pytest.approx(deg)
    (p,) = metrics.wedged_periods(_in_place(n, 0.3 + np.radians(31.0) * (np.arange(n) % 2)), heading_deg=35.0)
    assert p["held"] == [[0, n - 1]]  # the band is the argument's
    (p,) = metrics.wedged_periods(_in_place(n, np.full(n, 0.3)), heading_deg=0.0)
    assert p["held"] == [[0, n - 1]]  # a constant heading: range 0, inside even a band of 0
    yaw = np.full(n, 0.3)
    yaw[700] = np.nan  # an unknown heading: no stretch through it is held
    (p,) = metrics.wedged_periods(_in_place(n, yaw))
    assert 700 not in _held_steps([p])
    with pytest.raises(ValueError, match="heading_deg"):
        metrics.wedged_periods(_in_place(n, yaw), heading_deg=-1.0)


def test_held_steps_are_wedged_steps_and_the_band_is_monotone():
    rng = np.random.default_rng(5)
    n = 6000  # a slow random wander with a heading that sometimes drifts, sometimes holds
    xy = np.cumsum(rng.normal(0, 0.004, (n, 2)), axis=0)
    yaw = np.cumsum(rng.normal(0, 0.01, n) + np.where((np.arange(n) // 1000) % 2, 0.004, 0.0))
    pose = _pose(xy, yaw)
    wedged = metrics.wedged_periods(pose)
    steps = {band: set(_held_steps(metrics.wedged_periods(pose, heading_deg=band)).tolist()) for band in (10, 30, 90)}
    inside = {int(i) for p in wedged for i in range(p["start"], p["end"] + 1)}
    assert steps[10] <= steps[30] <= steps[90] <= inside
    for p in wedged:
        assert all(p["start"] <= a <= b <= p["end"] for a, b in p["held"])
        assert p["held_s"] == pytest.approx(sum(b - a + 1 for a, b in p["held"]) / HZ)
    held = metrics.held_periods(wedged)
    assert [(h["start"], h["end"]) for h in held] == [tuple(r) for p in wedged for r in p["held"]]
    assert all(h["cause"] in metrics.WEDGE_CAUSES for h in held)
