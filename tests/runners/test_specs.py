"""Run specs: canonical keys, the grid helper, the JSON-lines reader, up-front checks."""

import json

import pytest

from neurowalk.runners.specs import FIELDS, LATER, check_specs, describe, grid, read_jsonl, spec_key
from neurowalk.sim.config import EpisodeConfig


def test_key_ignores_dict_order_omitted_defaults_and_number_spelling():
    a = {"arena": "box", "controller": "static", "seed": 3, "arena_opts": {"distance": 0.5}}
    b = {"seed": 3.0, "arena_opts": {"distance": "0.5", "width": 1.0}, "controller": "static", "arena": "box"}
    c = {**a, "body": "amosii", "steps": 1000, "noise": 0.02, "control_hz": 10, "b0": None, "steer": None}
    assert spec_key(a) == spec_key(b) == spec_key(c)
    assert len(spec_key(a)) == 64 and int(spec_key(a), 16) >= 0


@pytest.mark.parametrize(
    "change", [{"seed": 4}, {"controller": "plastic"}, {"arena_opts": {"distance": 0.6}}, {"steps": 999}]
)
def test_key_changes_with_the_run(change):
    a = {"arena": "box", "controller": "static", "seed": 3, "arena_opts": {"distance": 0.5}}
    assert spec_key(a) != spec_key({**a, **change})


def test_normalize_fills_every_field_and_arena_default():
    s = EpisodeConfig.from_spec({"arena": "box"}).spec()
    assert tuple(s) == tuple(f for f in FIELDS if f not in LATER)  # later switches appear only when on
    on = EpisodeConfig.from_spec({"arena": "box", "reflexes": True, "backbone": True}).spec()
    assert on["reflexes"] is True and on["backbone"] is True and spec_key(on) != spec_key(s)
    assert spec_key({"arena": "box", "reflexes": False}) == spec_key(s)
    assert s["arena_opts"]["distance"] == 1.0 and s["steps"] == 1000 and s["controller"] == "plastic"
    assert json.loads(json.dumps(s)) == s  # JSON-able
    fixed = EpisodeConfig.from_spec({"controller": "fixed", "steer": (-1, -1)}).spec()
    assert fixed["steer"] == [-1.0, -1.0]


@pytest.mark.parametrize(
    "spec,word",
    [
        ({"arena": "maze"}, "maze"),
        ({"controller": "wheeled"}, "wheeled"),
        ({"body": "wheels"}, "wheels"),
        ({"seed": 1.5}, "seed"),
        ({"seed": -1}, "seed"),
        ({"steps": "many"}, "many"),
        ({"arena": "box", "arena_opts": {"gap": 1}}, "gap"),
        ({"arena": "box", "arena_opts": {"distance": "far"}}, "far"),
        ({"colour": "red"}, "colour"),
        ({"controller": "static", "b0": 1.0}, "b0"),
    ],
)
def test_bad_specs_raise_naming_the_value(spec, word):
    with pytest.raises(ValueError, match=word):
        check_specs([spec])


def test_check_specs_builds_the_arena():
    with pytest.raises(ValueError):
        check_specs([{"arena": "narrow-passage", "arena_opts": {"gap": -1.0}}])


def test_grid_is_the_cartesian_product_last_axis_fastest():
    g = grid({"arena": "box", "steps": 30}, controller=["plastic", "static"], **{"arena_opts.distance": [0.5, 1]})
    assert len(g) == 4
    assert [(s["controller"], s["arena_opts"]["distance"]) for s in g] == [
        ("plastic", 0.5), ("plastic", 1), ("static", 0.5), ("static", 1)
    ]  # fmt: skip
    assert all(s["arena"] == "box" and s["steps"] == 30 for s in g)
    assert grid({"seed": 1}) == [{"seed": 1, "arena_opts": {}}]


def test_a_grid_axis_of_a_body_option_sets_it_beside_the_base_options():
    g = grid({"body": "surrogate", "body_opts": {"speed": 1.5}}, **{"body_opts.turn": [0.5, 2]})
    assert [s["body_opts"] for s in g] == [{"speed": 1.5, "turn": 0.5}, {"speed": 1.5, "turn": 2}]
    check_specs(g)  # a valid option of that body
    assert EpisodeConfig.from_spec(g[0]).spec()["body_opts"] == {"speed": 1.5, "turn": 0.5}
    assert len({spec_key(s) for s in g}) == 2 and "body_opts" not in grid({"seed": 1})[0]


def test_read_jsonl(tmp_path):
    p = tmp_path / "specs.jsonl"
    p.write_text('{"seed": 1}\n\n# a comment\n{"seed": 2, "controller": "static"}\n')
    assert read_jsonl(p) == [{"seed": 1}, {"seed": 2, "controller": "static"}]
    p.write_text('{"seed": 1}\n{"seed": \n')
    with pytest.raises(ValueError, match=r"specs.jsonl:2"):
        read_jsonl(p)
    p.write_text("[1, 2]\n")
    with pytest.raises(ValueError, match="JSON object"):
        read_jsonl(p)
    with pytest.raises(ValueError, match="missing"):
        read_jsonl(tmp_path / "missing.jsonl")


def test_describe_names_what_differs():
    d = describe(
        EpisodeConfig.from_spec({"arena": "box", "arena_opts": {"distance": 0.5}, "seed": 3, "steps": 30}).spec()
    )
    assert d == "box distance=0.5 plastic amosii seed=3 steps=30"
