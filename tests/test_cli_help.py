"""Help text offers what the checks accept: every list of names in an option's help is a registry's names."""

from __future__ import annotations

import re

import pytest

from neurowalk.cli import main
from neurowalk.cli.common import REGISTRIES, registry_names

COMMANDS = ("run", "view", "figure", "sweep", "optimize", "calibrate", "export-model")
#: A list of names as help shows it: ``a | b | c``.
NAME_LIST = re.compile(r"[\w:.-]+(?: \| [\w:.-]+)+")


def _help(command: str, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> str:
    monkeypatch.setenv("COLUMNS", "1000")  # one line per option: no list wrapped
    with pytest.raises(SystemExit) as exit_:
        main([command, "--help"])
    assert exit_.value.code == 0
    return capsys.readouterr().out


@pytest.mark.parametrize("command", COMMANDS)
def test_every_list_of_names_in_help_is_a_registry(command, capsys, monkeypatch):
    text = _help(command, capsys, monkeypatch)
    lists = NAME_LIST.findall(text)
    assert lists, text
    known = {tuple(registry_names(r)) for r in REGISTRIES}
    for found in lists:
        names = tuple(found.split(" | "))
        assert names in known or (names[:-1] in known and names[-1] == "mjcf:FILE.xml"), found


@pytest.mark.parametrize("command", ["run", "figure", "sweep"])
def test_help_offers_only_the_variants_there_are(command, capsys, monkeypatch):
    from neurowalk.neural import variants

    there = variants.variant_names()
    text = _help(command, capsys, monkeypatch)
    assert f"the network: {' | '.join(there)} (default" in text
    assert ("tuned" in text) == ("tuned" in there)  # the data file of 'tuned' is shipped only after a search
    monkeypatch.setattr(variants, "variant_names", lambda: ("paper", "original", "tuned"))
    assert "the network: paper | original | tuned (default" in _help(command, capsys, monkeypatch)


def test_each_name_the_registries_show_is_accepted_by_its_check():
    from neurowalk.arenas import make_arena
    from neurowalk.body.registry import body_info
    from neurowalk.experiments.calibration.subjects import subject
    from neurowalk.neural.variants import get_variant
    from neurowalk.sim.episode import EpisodeConfig

    for name in registry_names("variants"):
        get_variant(name)
    for name in registry_names("arenas"):
        make_arena(name)
    for name in registry_names("bodies"):
        body_info(name)
    assert all(body_info(b).physics for b in registry_names("physics_bodies"))
    for name in registry_names("calibrated_bodies"):
        subject(name)
    for name in registry_names("controllers"):
        EpisodeConfig(controller=name, steer=(0.0, 0.0) if name == "fixed" else None)
    for name in registry_names("gaits"):
        EpisodeConfig(gait=name)
    for name in registry_names("engines"):
        EpisodeConfig(engine=name)
    with pytest.raises(ValueError, match="registry"):
        registry_names("colours")


def test_every_option_with_a_default_says_it():
    """An option that has a default value states it in its help (`default ...`), so `--help` answers it."""
    import argparse

    from neurowalk.cli import build_parser

    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    silent = [
        f"{name} {a.option_strings[0]}"
        for name, p in sub.choices.items()
        for a in p._actions
        if a.option_strings
        and a.help not in (None, argparse.SUPPRESS)
        and a.nargs != 0  # flags (store_true, --help) have no value to default
        and a.default not in (None, False, [])
        and "default" not in a.help
    ]
    assert silent == []


def test_a_sweep_writes_to_out_sweep_by_default_as_the_other_commands_to_out_name():
    from pathlib import Path

    from neurowalk.cli import parse

    assert parse(["sweep", "--arena", "box"]).out == Path("out/sweep")
    assert parse(["sweep", "--arena", "box", "--out", "elsewhere"]).out == Path("elsewhere")


def test_quick_means_the_same_for_a_figure_and_a_study():
    import contextlib
    import io

    from neurowalk.cli import main

    helps = []
    for argv in (["figure", "fig3", "--help"], ["study", "--help"]):
        out = io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.suppress(SystemExit):
            main(argv)
        helps.append(" ".join(out.getvalue().split()))
    assert all("--quick a first look: the study's quick version (fewer seeds or environments" in h for h in helps)
