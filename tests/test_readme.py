"""The README's set-up commands are the ones CI runs."""

import re
from pathlib import Path

import pytest

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


#: README commands too long for a test run (minutes to the better part of an hour: the committed reproduction ran
#: them), or that need a file or an extra the README only names: parsed, not run.
PARSE_ONLY = ("neurowalk reproduce", "neurowalk figure fig5", "neurowalk figure fig9", "neurowalk figure fig10",
              "neurowalk study", "neurowalk optimize", "neurowalk view", "neurowalk baseline")  # fmt: skip


def _readme_in_order() -> list[str]:
    """The README's `neurowalk` commands in the order a reader meets them: the first set-up command's, then every
    inline one (a table's rows, the climbing line, ...)."""
    text = (ROOT / "README.md").read_text()
    first = _commands()[0].split("&&")[-1].strip().removeprefix(".venv/bin/")
    return [first, *re.findall(r"`(neurowalk [^`]*)`", text)]


@pytest.mark.slow
def test_the_readmes_commands_run_in_order_in_a_fresh_folder(tmp_path):
    """Copied and pasted in order into an empty folder, each command runs (the long ones parse): one command's
    output folder never stops the next."""
    import os
    import shlex
    import subprocess
    import sys

    from neurowalk.cli import parse

    cmds = _readme_in_order()
    assert cmds[0].startswith("neurowalk run") and any("--climb" in c for c in cmds) and len(cmds) >= 15
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    ran = []
    for cmd in dict.fromkeys(cmds):  # a command named twice (prose, then the table) runs once
        argv = shlex.split(cmd)
        if cmd.startswith(PARSE_ONLY):
            parse(argv[1:])
            continue
        done = subprocess.run(argv, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600)
        assert done.returncode == 0, f"{cmd}:\n{done.stdout[-2000:]}\n{done.stderr[-2000:]}"
        ran.append(cmd)
    assert len(ran) >= 7 and (tmp_path / "out" / "climb" / "summary.json").is_file()
