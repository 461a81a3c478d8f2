"""The number-source checker (tests/numbers.py) finds what it must: wrong values, unsourced numbers, bad keys."""

from __future__ import annotations

import json

from numbers_checker import problems, shows


def _doc(tmp_path, text):
    (tmp_path / "docs" / "results").mkdir(parents=True, exist_ok=True)
    (tmp_path / "docs" / "results" / "fig8.json").write_text(
        json.dumps({"claims": [{"measured": "10/10", "rate": 0.875, "time": 41.26, "rule": "held 300 s in 0.5 m"}]})
    )
    doc = tmp_path / "README.md"
    doc.write_text(text)
    return problems(tmp_path, doc)


def test_shows_rounds_as_the_text_does():
    assert shows("10/10", "10/10") and not shows("9/10", "10/10")
    assert shows("88%", 0.875) and shows("87.5%", 0.875) and not shows("87%", 0.875)
    assert shows("41 s", 41.26) and shows("41.3 s", 41.26) and not shows("42 s", 41.26)
    assert shows("300 s", "held 300 s in 0.5 m") and not shows("200 s", "held 300 s in 0.5 m")
    assert shows("2 min", 120.0) and not shows("3 min", 120.0)
    assert not shows("1", True)


def test_sourced_numbers_pass_and_others_are_named(tmp_path):
    good = (
        "# Results of Fig. 8 (2015)\n\nescaped [10/10](docs/results/fig8.json#claims/0/measured), "
        "[88%](docs/results/fig8.json#claims/0/rate) in [41 s](docs/results/fig8.json#claims/0/time); "
        "the 19-DOF robot, Table 2, §2.2, Python 3.11, version 1.2.3, `neurowalk run --steps 500`.\n"
    )
    assert _doc(tmp_path, good) == []
    bad = _doc(tmp_path, "escaped [9/10](docs/results/fig8.json#claims/0/measured) in 41 s\n")
    assert len(bad) == 2 and "differs" in bad[0] and "'41' has no source" in bad[1]
    missing = _doc(tmp_path, "see [10/10](docs/results/fig8.json#claims/3/measured)\n")
    assert len(missing) == 1 and "no such source" in missing[0]
    assert _doc(tmp_path, "```\nneurowalk figure fig8 --seeds 10\n```\n<!-- 12 -->\n") == []


def test_the_robots_19_joints_name_a_part_count(tmp_path):
    """AMOSII's 19 joints are a count of its parts, as "19-DOF" is; other counts of joints are not exempt."""
    assert _doc(tmp_path, "the 19 joint targets, AMOSII's 19 actuator names, its 19 joints\n") == []
    bad = _doc(tmp_path, "18 joint targets and 19 legs\n")
    assert len(bad) == 2 and "'18' has no source" in bad[0] and "'19' has no source" in bad[1]


def test_a_range_of_names_is_a_name(tmp_path):
    """A range of names ("Eq. 1-6") names each; a range after anything else is still two numbers to source."""
    assert _doc(tmp_path, "the network of Eq. 1-6 and of Fig. 3-5\n") == []
    bad = _doc(tmp_path, "after 1-6 runs\n")
    assert len(bad) == 2 and "'1' has no source" in bad[0] and "'6' has no source" in bad[1]
