"""EpisodeConfig: immutable and hashable, one canonical key in any process, replace() with dotted names, and the
one validator that run specs go through."""

from __future__ import annotations

import copy
import json
import os
import pickle
import subprocess
import sys

import pytest

from neurowalk.sim.config import EpisodeConfig
from neurowalk.sim.config_values import FrozenDict

CFG = dict(arena="narrow-passage", arena_opts={"gap": 0.5}, body_opts={}, params={"mu_b": 0.01}, seed=3, steps=500)

#: Keys of runs in stores written by earlier versions (computed by the spec normaliser before the config took it
#: over): a store's rows must stay findable.
STORED = {
    '{"arena": "box"}': "1eee66a004d522d422250f8db3e7c4de29dbc3625833b3e7c9553547a4241457",
    '{"arena": "narrow-passage", "arena_opts": {"gap": 0.5}, "controller": "static", "seed": 3, "steps": 500}':
        "4b9c678d0166af0945aa85f22128333cf6cce1ef98575545f3ba439df0e383db",
    '{"arena": "random", "body": "surrogate", "seed": 7, "variant": "original", "params": {"mu_b": 0.01}}':
        "b83214b12ee497185490c250066af26d5bb04f31b3d73ac227dc709103c6fd0b",
}  # fmt: skip


@pytest.mark.parametrize("spec", sorted(STORED))
def test_the_keys_of_stores_written_before_stay_valid(spec):
    assert EpisodeConfig.from_spec(json.loads(spec)).key() == STORED[spec]


def test_a_config_hashes_and_equal_configs_are_one_key_of_a_dict():
    a, b = EpisodeConfig(**CFG), EpisodeConfig(**copy.deepcopy(CFG))
    assert a == b and hash(a) == hash(b) and len({a: 1, b: 2}) == 1
    assert hash(a.replace(seed=4)) != hash(a)


@pytest.mark.parametrize("field", ["arena_opts", "params", "body_opts"])
def test_its_option_fields_cannot_change(field):
    cfg = EpisodeConfig(**CFG)
    opts = getattr(cfg, field)
    assert isinstance(opts, FrozenDict)
    for change in (lambda: opts.__setitem__("x", 1), lambda: opts.update(x=1), lambda: opts.pop("x", None),
                   opts.clear, lambda: opts.setdefault("x", 1), lambda: opts.__delitem__("x")):  # fmt: skip
        with pytest.raises(TypeError, match="cannot change"):
            change()
    with pytest.raises(AttributeError):
        cfg.seed = 5  # type: ignore[misc]


def test_nested_values_are_frozen_and_the_config_survives_pickle_and_copy():
    f = FrozenDict({"a": {"b": [1, 2]}})
    assert f == {"a": {"b": (1, 2)}} and isinstance(f["a"], FrozenDict) and hash(f) == hash(FrozenDict(f))
    cfg = EpisodeConfig(**CFG)
    for other in (pickle.loads(pickle.dumps(cfg)), copy.deepcopy(cfg), copy.copy(cfg)):
        assert other == cfg and other.key() == cfg.key() and isinstance(other.arena_opts, FrozenDict)
    assert json.loads(json.dumps(cfg.arena_opts)) == {"gap": 0.5}


def test_the_key_is_the_same_in_another_process_whatever_its_hash_seed():
    code = ("from neurowalk.sim.config import EpisodeConfig; import sys, json; "
            "print(EpisodeConfig(**json.loads(sys.argv[1])).key())")  # fmt: skip
    keys = {
        subprocess.run(
            [sys.executable, "-c", code, json.dumps(CFG)],
            env={**os.environ, "PYTHONHASHSEED": seed},
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
        for seed in ("1", "2")
    }
    assert keys == {EpisodeConfig(**CFG).key()}


def test_equal_runs_have_equal_keys_whatever_the_spelling_and_the_defaults():
    base = EpisodeConfig(arena="box", steps=300, control_hz=10)
    same = [
        EpisodeConfig(arena="box", steps=300.0, control_hz=10.0, params={}, body_opts={}),
        EpisodeConfig.from_spec({"arena": "box", "steps": "300", "arena_opts": {"distance": "1"}}),
        EpisodeConfig(arena="box", steps=300, arena_opts={"distance": 1}),  # its default, spelt out
    ]
    assert {c.key() for c in same} == {base.key()}
    assert base.replace(seed=1).key() != base.key() and base.replace(**{"arena_opts.distance": 2}).key() != base.key()


def test_replace_reaches_into_option_fields_by_dotted_name():
    cfg = EpisodeConfig(**CFG)
    new = cfg.replace(seed=9, **{"arena_opts.gap": 0.6, "params.mu_q": 0.02})
    assert new.seed == 9 and new.arena_opts == {"gap": 0.6} and new.params == {"mu_b": 0.01, "mu_q": 0.02}
    assert cfg.arena_opts == {"gap": 0.5} and cfg.seed == 3  # the original is as it was
    with pytest.raises(ValueError, match="no option 'nope'"):
        cfg.replace(**{"arena_opts.nope": 1})
    with pytest.raises(ValueError, match="only arena_opts, body_opts and params"):
        cfg.replace(**{"seed.x": 1})
    with pytest.raises(ValueError, match="unknown config field 'sede'"):
        cfg.replace(sede=1)


@pytest.mark.parametrize(
    ("fields", "words"),
    [
        ({"arena": "box", "arena_opts": {"distance": "far"}}, "must be a finite number"),
        ({"arena": "box", "arena_opts": {"gap": 1}}, "has no option 'gap'"),
        ({"arena": "random", "arena_opts": {"n_boxes": 2.5}}, "must be a whole number"),
        ({"arena_opts": [1]}, "arena_opts must be an object"),
        ({"reflexes": 1}, "reflexes must be true or false"),
        ({"params": {"nope": 1}}, "unknown field 'nope'"),
    ],
)
def test_a_bad_value_is_refused_when_the_config_is_made(fields, words):
    with pytest.raises(ValueError, match=words):
        EpisodeConfig(**fields)


def test_a_spec_file_reads_through_the_one_validator():
    with pytest.raises(ValueError, match="unknown spec field 'sede'"):
        EpisodeConfig.from_spec({"sede": 1})
    with pytest.raises(ValueError, match="steps must be a whole number"):
        EpisodeConfig.from_spec({"steps": "many"})
    spec = EpisodeConfig.from_spec({"arena": "corner", "controller": "static"}).spec()
    assert spec["arena_opts"] == {"angle": 60.0, "length": 2.0} and "variant" not in spec  # later fields at default
    assert EpisodeConfig.from_spec(spec).spec() == spec
