"""Property: any JSON-like spec is either normalised to a valid run or refused with a ValueError naming it."""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from neurowalk.runners.specs import FIELDS, spec_key
from neurowalk.sim.config import EpisodeConfig

SCALARS = st.one_of(
    st.none(), st.booleans(), st.integers(-(10**12), 10**12), st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=6), st.sampled_from(["open", "box", "random", "plastic", "fixed", "surrogate", "original",
                                          "1e400", "nan", "-1", "0.3", "3"]),
)  # fmt: skip
VALUES = st.one_of(SCALARS, st.lists(SCALARS, max_size=3), st.dictionaries(st.text(max_size=8), SCALARS, max_size=3))
KEYS = st.sampled_from([*FIELDS, "junk"])
GOOD = {"arena": "box", "controller": "plastic", "body": "surrogate", "steps": 10}


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.dictionaries(KEYS, VALUES, max_size=4), st.booleans())
def test_a_spec_normalises_or_is_refused_by_name(extra, from_good):
    spec = {**GOOD, **extra} if from_good else extra
    try:
        s = EpisodeConfig.from_spec(spec).spec()
    except ValueError as e:
        assert str(e) and "\n" not in str(e)
        return
    cfg = EpisodeConfig.from_spec(s)  # a normalised spec is a valid run
    assert cfg.steps >= 1 and cfg.control_hz > 0 and cfg.noise >= 0
    assert spec_key(s) == spec_key(spec)  # and its key is the same as the original's
