"""The README's set-up commands are the ones CI runs."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _commands() -> list[str]:
    text = (ROOT / "README.md").read_text()
    block = re.search(r"```bash\n(.*?)```", text, re.S)
    assert block, "README starts with a bash block holding the two set-up commands"
    return [line for line in block.group(1).splitlines() if line and not line.startswith("#")]


def test_readme_is_at_most_150_lines():
    assert len((ROOT / "README.md").read_text().splitlines()) <= 150


def test_readme_starts_with_two_commands_and_ci_runs_the_test_one():
    cmds = _commands()
    assert len(cmds) == 2
    main_job, tests = cmds
    assert "neurowalk" in main_job and "pytest" in tests
    assert tests in (ROOT / ".ci" / "run").read_text()


#: The pages whose code blocks hold the commands a reader copies: the README's tour and the full list in the manual.
COMMAND_PAGES = ("README.md", "docs/usage.md")


def _neurowalk_commands() -> list[str]:
    """Every `neurowalk ...` command in the code blocks of :data:`COMMAND_PAGES` (continuation lines joined, comments
    cut)."""
    text = "\n".join((ROOT / page).read_text() for page in COMMAND_PAGES)
    cmds = []
    for block in re.findall(r"```[a-z]*\n(.*?)```", text, re.S):
        joined = re.sub(r"\\\n\s*", " ", block)
        for line in joined.splitlines():
            line = line.split("  #")[0].strip()
            for part in line.split("&&"):
                part = part.strip()
                if part.startswith(("neurowalk ", ".venv/bin/neurowalk ")):
                    cmds.append(part)
    return cmds


def test_every_readme_command_parses():
    """The commands of the README and of docs/usage.md parse as written."""
    import shlex

    from neurowalk.cli import parse

    cmds = _neurowalk_commands()
    assert len(cmds) >= 20
    for cmd in cmds:
        parse(shlex.split(cmd)[1:])  # raises UsageError naming what no longer parses


def test_the_command_check_catches_a_bad_command():
    import shlex

    import pytest

    from neurowalk.cli import UsageError, parse

    with pytest.raises(UsageError):
        parse(shlex.split("neurowalk run --no-such-flag 3")[1:])


def test_each_readme_command_writes_to_its_own_folder():
    """Following the README and docs/usage.md overwrites nothing: every command that writes results has its own
    output path."""
    import shlex

    from neurowalk.cli import parse

    outs: dict[str, str] = {}
    argvs = dict.fromkeys(tuple(shlex.split(c)[1:]) for c in _neurowalk_commands())  # one shown twice: same work
    for argv in argvs:
        cmd = shlex.join(["neurowalk", *argv])
        args = parse(list(argv))
        out = getattr(args, "out", None)
        if args.command == "figure":
            if args.name == "list" or args.replot:  # writes nothing, or redraws what the command before wrote
                continue
            out = out or Path("out") / (f"{args.name}-climb" if args.climbing else args.name)  # the figure's default
        if out is None or getattr(args, "resume", False):  # nothing written (view, lists), or goes on in place
            continue
        assert str(out) not in outs, f"{cmd!r} writes to {out}, as {outs[str(out)]!r} does"
        outs[str(out)] = cmd
    assert len(outs) >= 20
