"""The site's command-line reference (docs/cli.md) is what the parser makes, and lists every command and option
that `neurowalk --help` and `neurowalk COMMAND --help` show."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

from neurowalk.cli.reference import markdown

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "cli.md"


def _help(*argv: str) -> str:
    done = subprocess.run(
        [sys.executable, "-m", "neurowalk", *argv, "--help"], capture_output=True, text=True, check=True
    )
    return done.stdout


def test_the_committed_page_is_what_the_parser_makes():
    assert PAGE.read_text(encoding="utf-8") == markdown(), "run: python -m neurowalk.cli.reference docs/cli.md"


def test_every_command_and_option_of_the_help_is_on_the_page():
    page = PAGE.read_text(encoding="utf-8")
    top = _help()
    commands = re.search(r"\{([\w,\-]+)\}", top).group(1).split(",")
    assert len(commands) >= 10
    seen = 0
    for command in commands:
        assert f"\n## {command}\n" in page, command
        section = page.split(f"\n## {command}\n", 1)[1].split("\n## ", 1)[0]
        options = set(re.findall(r"(?<![\w-])(--[a-z][\w-]*)", _help(command))) - {"--help"}
        seen += len(options)
        missing = sorted(o for o in options if f"`{o}" not in section)
        assert missing == [], f"{command}: {missing}"
    assert seen >= 50  # the options were found in the help at all
