"""The number-source checker (tests/numbers_checker.py) finds what it must: wrong values, unsourced numbers, bad
keys."""

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
    assert shows("4.8e-7", 4.768e-07) and shows("4.77e-7", 4.768e-07) and not shows("4.7e-7", 4.768e-07)
    assert not shows("4.8e-6", 4.768e-07)  # the power of ten counts
    assert shows("3.3 min", 197.8) and shows("7.0 min", 417.3) and not shows("3.2 min", 197.8)
    assert not shows("1", True)


def test_a_string_backs_its_whole_numbers_only():
    assert shows("10/10", "10/10") and shows("44/50", "plastic 44/50, static 25/50")
    assert not shows("10/10", "9/10")  # "10" is in "9/10" once, and not as the text's first number
    assert not shows("48/50", "8/50") and not shows("27/30", "plastic 28/30, static 10/30")
    assert shows("close to the number of cores", "close to the number of cores (2)")
    assert not shows("reproduced", "partly")


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


def test_a_year_before_punctuation_is_a_year(tmp_path):
    """ "2014," or "2015;" is a year, as "2014" is; a number before a comma is still a number to source."""
    assert _doc(tmp_path, "(Manoonpong et al. 2013, Grinke et al. 2015; in 2014.)\n") == []
    bad = _doc(tmp_path, "after 300, 500 runs\n")
    assert len(bad) == 2 and "'300' has no source" in bad[0] and "'500' has no source" in bad[1]


def test_a_link_to_a_whole_source_file_names_it(tmp_path):
    """A link with no #key names a result file: no claim, so its text may hold no result, only names."""
    text = "see [the Fig. 8 run](docs/results/fig8.json) and [`fig8.json`](docs/results/fig8.json)\n"
    assert _doc(tmp_path, text) == []
    bad = _doc(tmp_path, "escaped [10/10](docs/results/fig8.json)\n")
    assert len(bad) == 2 and all("has no source (a link to a whole file: a value needs its #key)" in b for b in bad)


def test_the_studies_are_sources_and_spaces_in_keys_are_escaped(tmp_path):
    """docs/baselines/ and docs/optimize/ hold results; a key with a space is linked with %20."""
    for study in ("baselines", "optimize"):
        (tmp_path / "docs" / study).mkdir(parents=True)
        (tmp_path / "docs" / study / "out.json").write_text(json.dumps({"failure classes": {"latched spin": 7}}))
    text = (
        "[7](docs/baselines/out.json#failure%20classes/latched%20spin) and "
        "[7 spins](docs/optimize/out.json#failure%20classes/latched%20spin)\n"
    )
    assert _doc(tmp_path, text) == []
    bad = _doc(tmp_path, "[8](docs/optimize/out.json#failure%20classes/latched%20spin)\n")
    assert len(bad) == 1 and "differs" in bad[0] and "latched%20spin = 7" in bad[0]
    (tmp_path / "docs" / "other").mkdir()
    (tmp_path / "docs" / "other" / "out.json").write_text(json.dumps({"n": 7}))
    bad = _doc(tmp_path, "[7](docs/other/out.json#n)\n")
    assert len(bad) == 1 and "'7' has no source" in bad[0]


def test_a_name_broken_over_two_lines_is_a_name(tmp_path):
    """ "Fig." or "Table" ending one line and its number starting the next is a name; a bare number there is not."""
    assert _doc(tmp_path, "as in Fig.\n8 and Table\n2, and §\n2.2\n") == []
    bad = _doc(tmp_path, "as in the runs\n8 of them\n")
    assert len(bad) == 1 and "'8' has no source" in bad[0]


def test_inline_code_that_wraps_onto_the_next_line_is_code(tmp_path):
    assert _doc(tmp_path, "the paper's length (`LONG_STEPS =\n100,000` control steps)\n") == []
    bad = _doc(tmp_path, "a `setting` here\n\nand 42 there\n")  # a blank line ends a paragraph: 42 is prose
    assert len(bad) == 1 and "'42'" in bad[0] and ":3:" in bad[0]
