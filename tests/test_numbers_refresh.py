"""The link refresher (tests/numbers_refresh.py) rewrites stale result numbers in the old text's format, and only
those: synthetic pages and JSON sources in a temporary checkout."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from numbers_checker import problems
from numbers_refresh import UnfixableError, main, refresh_link, refresh_text, render, shows_strictly

SOURCE = {
    "time_s": 1.2134,
    "steps_per_s": 12345.6,
    "small": 2100,
    "rate": 0.8834,
    "wall_s": 417.3,
    "long_s": 7560.0,
    "speedup": 1.234,
    "delta": -0.0412,
    "seed": 1000000002,
    "escaped": "9/10",
    "rule": "plastic 28/30, static 11/30",
    "twice": "plastic 28/30, static 11/30, paper 29/30",
    "claim": "held 250 s in 0.5 m",
    "flag": True,
}


def _resolve(target: str) -> tuple[object, str] | None:
    """A lookup over :data:`SOURCE` for targets ``r.json#key``; other targets are not sources."""
    file, _, key = target.partition("#")
    if file != "r.json":
        return None
    return (SOURCE[key] if key else SOURCE), f"docs/results/r.json#{key}"


@pytest.mark.parametrize(
    ("old", "value", "new"),
    [
        ("1.46 s", 1.2134, "1.21 s"),  # the decimals kept
        ("1 s", 1.2134, "1 s"),
        ("1.090x", 1.234, "1.234x"),
        ("1.09x faster", 1.234, "1.23x faster"),
        ("9,876 steps/s", 12345.6, "12,346 steps/s"),  # commas kept
        ("9876 steps/s", 12345.6, "12,346 steps/s"),  # grown to 10,000 or more: commas
        ("1,888 steps/s", 2100, "2,100 steps/s"),
        ("1888 steps/s", 2100, "2100 steps/s"),
        ("1000000000", 1000000002, "1000000002"),  # a long number written without commas stays so
        ("88%", 0.75, "75%"),  # a share, times 100
        ("88.3%", 0.7512, "75.1%"),
        ("3.3 min", 417.3, "7.0 min"),  # seconds as minutes
        ("3 min", 417.3, "7 min"),
        ("2.0 h", 7560.0, "2.1 h"),
        ("-0.031", -0.0412, "-0.041"),
        ("−0.03", -0.0412, "−0.04"),
        ("+0.03", 0.0412, "+0.04"),
        ("0.03", -0.0412, "-0.04"),
        ("10/10", "9/10", "9/10"),  # a string value: the fraction
        ("44/50 runs", "44/50 runs, 9/10 seeds", "44/50 runs"),
        ("plastic 27/30", "plastic 28/30, static 11/30", "plastic 28/30"),
        ("static 10/30", "plastic 28/30, static 11/30", "static 11/30"),
        ("plastic 27/30, static 10/30", "plastic 28/30, static 11/30", "plastic 28/30, static 11/30"),
        ("plastic\n27/30", "plastic 28/30, static 11/30", "plastic\n28/30"),  # the text's line break kept
        ("300 s", "held 250 s in 0.5 m", "250 s"),
    ],
)
def test_a_stale_text_is_rewritten_in_its_format(old, value, new):
    assert refresh_link(old, value) == new


def test_render_keeps_sign_commas_and_decimals():
    assert render("1.46", 1.2134) == "1.21"
    assert render("-1.0", -0.04) == "0.0"  # no "-0.0"
    assert render("12,000", 9999.6) == "10,000"


@pytest.mark.parametrize(
    ("old", "value", "why"),
    [
        ("27/30", "plastic 28/30, static 11/30", "ambiguous"),  # two parts read as "N/N"
        ("27 of 30", "plastic 28/30, static 11/30", "matches no part"),
        ("fast", 1.5, "no number"),
        ("1", True, "not a number or a string"),
        ("1.5 s", float("nan"), "not a finite number"),
    ],
)
def test_what_cannot_be_matched_is_unfixable(old, value, why):
    with pytest.raises(UnfixableError, match=why):
        refresh_link(old, value)


PAGE = """\
# Results 2

It ran [1.46 s](r.json#time_s) at [9,876 steps/s](r.json#steps_per_s), [88%](r.json#rate) escaped, in
[3.3 min](r.json#wall_s): [10/10](r.json#escaped) seeds ([plastic 27/30](r.json#rule)), 1.46 s outside a link.
Already right: [1.21 s](r.json#time_s) and [0.8834](r.json#rate). Not a source: [1.46 s](other.md#time),
[Fig. 3](https://example.org/1.46), the whole file [r.json](r.json). In code: `[1.46 s](r.json#time_s)`.

<!-- [1.46 s](r.json#time_s) -->
UnfixableError: [27/30](r.json#twice) and [a key](r.json#missing).
"""


def test_only_stale_link_texts_change():
    new, rewrites, unfixed = refresh_text(PAGE, _resolve)
    assert [r.line for r in rewrites] == [3, 3, 4, 4, 4]
    assert [(r.old, r.new) for r in rewrites] == [
        ("1.46 s", "1.21 s"),
        ("9,876 steps/s", "12,346 steps/s"),
        ("3.3 min", "7.0 min"),
        ("10/10", "9/10"),
        ("plastic 27/30", "plastic 28/30"),
    ]
    expected = (
        PAGE.replace("[1.46 s](r.json#time_s) at", "[1.21 s](r.json#time_s) at")
        .replace("[9,876", "[12,346")
        .replace("[3.3 min]", "[7.0 min]")
        .replace("[10/10]", "[9/10]")
        .replace("[plastic 27/30]", "[plastic 28/30]")
    )
    assert new == expected  # "88%" shows 0.8834 already; other links, code, comments and prose untouched
    assert [(u.line, u.text) for u in unfixed] == [(9, "27/30"), (9, "a key")]
    assert "ambiguous" in unfixed[0].why and "no such source" in unfixed[1].why
    assert refresh_text(new, _resolve)[1] == []  # a second pass finds nothing


def _checkout(tmp_path: Path, page: str) -> Path:
    (tmp_path / "docs" / "results").mkdir(parents=True)
    (tmp_path / "docs" / "results" / "r.json").write_text(json.dumps(SOURCE))
    doc = tmp_path / "docs" / "page.md"
    doc.write_text(page.replace("(r.json", "(results/r.json"), encoding="utf-8")
    return doc


def test_the_command_rewrites_and_the_checker_accepts(tmp_path, capsys):
    page = "Took [1.46 s](r.json#time_s), [88.0%](r.json#rate), [10/10](r.json#escaped), [1.2x](r.json#speedup).\n"
    doc = _checkout(tmp_path, page)
    assert problems(tmp_path, doc) != []
    assert main(["--root", str(tmp_path), str(doc)]) == 0
    out = capsys.readouterr().out
    assert "docs/page.md:1: [1.46 s] -> [1.21 s]" in out and "Reminder" in out and "docs/page.md" in out
    assert doc.read_text(encoding="utf-8") == (
        "Took [1.21 s](results/r.json#time_s), [88.3%](results/r.json#rate), [9/10](results/r.json#escaped), "
        "[1.2x](results/r.json#speedup).\n"
    )
    assert problems(tmp_path, doc) == []
    assert main(["--root", str(tmp_path), str(doc)]) == 0  # nothing left to do
    assert "0 link text(s) rewritten in 0 file(s)" in capsys.readouterr().out


def test_the_command_reports_what_it_left_and_dry_run_writes_nothing(tmp_path, capsys):
    page = "[1.46 s](r.json#time_s) and [27/30](r.json#twice)\n"
    doc = _checkout(tmp_path, page)
    before = doc.read_text(encoding="utf-8")
    assert main(["--root", str(tmp_path), "--dry-run", str(doc)]) == 1
    out = capsys.readouterr().out
    assert "[1.46 s] -> [1.21 s]" in out and "Not fixed:" in out and "docs/page.md:1: [27/30]" in out
    assert doc.read_text(encoding="utf-8") == before


def test_a_fraction_the_checker_still_passes_is_stale():
    """The checker takes "10/10" for "9/10" ("10" is a substring of it); the refresher does not."""
    new, rewrites, _ = refresh_text("[10/10](r.json#escaped), [27/30](r.json#rule)", _resolve)
    assert new == "[9/10](r.json#escaped), [27/30](r.json#rule)" and len(rewrites) == 1
    assert shows_strictly("plastic 28/30", SOURCE["rule"]) and not shows_strictly("plastic 28/31", SOURCE["rule"])
