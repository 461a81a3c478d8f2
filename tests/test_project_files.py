"""The files every published research package has: a license, how to cite it, what changed."""

from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path

import jsonschema
import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
SCHEMA = Path(__file__).parent / "data" / "cff-1.2.0-schema.json"  # the Citation File Format's own schema


def _citation() -> dict:
    return yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))


def test_citation_is_valid_cff_and_names_this_version_and_the_paper():
    cff = _citation()
    jsonschema.validate(cff, json.loads(SCHEMA.read_text()))
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert cff["version"] == project["version"] and cff["license"] == project["license"]["text"]
    paper = cff["references"][0]
    assert paper["doi"] == "10.3389/fnbot.2015.00011" and paper["year"] == 2015
    assert [a["family-names"] for a in paper["authors"]] == ["Grinke", "Tetzlaff", "Wörgötter", "Manoonpong"]


def test_the_schema_check_refuses_a_broken_citation():
    cff = _citation()
    del cff["authors"]  # required
    with pytest.raises(jsonschema.ValidationError, match="authors"):
        jsonschema.validate(cff, json.loads(SCHEMA.read_text()))
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate({**_citation(), "doi": "not a doi"}, json.loads(SCHEMA.read_text()))


def test_license_is_the_one_the_package_declares():
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("MIT License") and 'THE SOFTWARE IS PROVIDED "AS IS"' in text


def test_changelog_has_this_version():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    versions = re.findall(r"^## \[([^\]]+)\]", (ROOT / "CHANGELOG.md").read_text(), re.M)
    assert versions and versions[0] == project["version"]
