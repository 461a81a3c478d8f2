"""The command-line reference page of the documentation site (``docs/cli.md``), made from the parser itself.

``python -m neurowalk.cli.reference docs/cli.md`` writes it; a test holds the committed page equal to
:func:`markdown`, so the page lists every command and option ``neurowalk --help`` shows, with the same words.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

HEADER = """# Command-line reference

Every command and option of `neurowalk`, as `neurowalk COMMAND --help` prints them (this page is made from the
parser: `python -m neurowalk.cli.reference docs/cli.md`). The guide to using them is [Using neurowalk](usage.md).
Bad input exits with status 2 and one line naming the value.
"""


def _subcommands(parser: argparse.ArgumentParser) -> dict[str, tuple[argparse.ArgumentParser, str]]:
    """The sub-parsers of ``parser`` and the one-line help of each, as the top-level ``--help`` shows it, by name, in
    the order ``--help`` lists them."""
    for action in parser._actions:  # argparse keeps them here; no public accessor
        if isinstance(action, argparse._SubParsersAction):
            helps = {a.dest: a.help or "" for a in action._choices_actions}
            return {name: (sub, helps.get(name, "")) for name, sub in action.choices.items()}
    return {}


def _option_rows(parser: argparse.ArgumentParser) -> list[str]:
    rows = []
    for action in parser._actions:
        if isinstance(action, argparse._HelpAction | argparse._SubParsersAction):
            continue
        if action.option_strings:
            flags = ", ".join(action.option_strings)
            metavar = action.metavar or (action.dest.upper() if action.nargs != 0 else "")
            name = f"`{flags} {metavar}`" if metavar else f"`{flags}`"
        else:
            name = f"`{action.metavar or action.dest}`"
        text = (action.help or "").replace("|", "\\|").replace("\n", " ")
        if action.choices and not isinstance(action.choices, dict):
            text += f" (one of: {', '.join(f'`{c}`' for c in action.choices)})"
        rows.append(f"| {name} | {text} |")
    return rows


def markdown(parser: argparse.ArgumentParser | None = None) -> str:
    """The reference page: each command's usage line, description, options and epilog, from ``parser`` (the
    ``neurowalk`` parser by default)."""
    if parser is None:
        from neurowalk.cli import build_parser  # here: this module is part of that package

        parser = build_parser()
    lines = [HEADER, "| command | what it does |\n|---|---|"]
    lines += [f"| [`{name}`](#{name}) | {help_} |" for name, (_, help_) in _subcommands(parser).items()]
    lines.append("")
    for name, (sub, help_) in _subcommands(parser).items():
        sub.format_help()  # fills in the registry names ({bodies}, ...) of the options' help
        tail = getattr(sub, "page_tail", None) or (sub.help_tail() if getattr(sub, "help_tail", None) else "")
        usage = " ".join(sub.format_usage().split())
        lines.append(f"## {name}\n")
        lines.append(f"{help_}\n")
        lines.append(f"```text\n{usage.removeprefix('usage: ')}\n```\n")
        if rows := _option_rows(sub):
            lines.append("| argument | meaning |\n|---|---|")
            lines += rows
            lines.append("")
        if more := (tail or sub.epilog or "").strip():
            lines.append(f"```text\n{more}\n```\n")
    return "\n".join(lines).rstrip() + "\n"


def main(argv: list[str] | None = None) -> int:
    """Write the page to the path given (or print it)."""
    argv = sys.argv[1:] if argv is None else argv
    text = markdown()
    if argv:
        Path(argv[0]).write_text(text, encoding="utf-8")
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
