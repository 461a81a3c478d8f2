"""The ``neurowalk`` command's entry point (``neurowalk/__main__.py``): a stop at any moment of its start.

SIGINT or SIGTERM sent at the command's readiness (its handlers in place, read from ``/proc``: ``readiness.py``) and
a few moments after, while its modules load, ends it with exit status 130 (SIGINT) or 143 (SIGTERM) and exactly one
line on stderr, never a traceback; through the console script and through ``python -m neurowalk``. ``import
neurowalk`` (a library) sets no signal handler.
"""

from __future__ import annotations

import signal
import subprocess
import sys
from pathlib import Path

import pytest

from readiness import catches_stop_signals, sleep_until, wait_ready

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")

SCRIPT = Path(sys.executable).parent / "neurowalk"  # the console script of this environment
COMMANDS = {
    "run": ["run", "--body", "surrogate", "--arena", "cluttered", "--steps", "3000000", "--quiet"],
    "figure": ["figure", "fig2", "--quick"],
}
OFFSETS = (0.0, 0.002, 0.02, 0.2, 0.4)  # s after readiness: the imports (a second or more), amid them, the work
ATTEMPTS = 3  # tries of an offset whose command had ended before its signal could be sent (a loaded machine)


def _launcher(k: int) -> list[str]:
    """The console script, or ``python -m neurowalk``, by turns."""
    if k % 2 == 0 and SCRIPT.is_file():
        return [str(SCRIPT)]
    return [sys.executable, "-m", "neurowalk"]


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_a_stop_at_start_up_ends_in_one_line_and_its_exit_status(command, sig, tmp_path):
    for k, offset in enumerate(OFFSETS):
        for attempt in range(ATTEMPTS):
            out = tmp_path / f"try{k}-{attempt}"
            cmd = [*_launcher(k), *COMMANDS[command], "--out", str(out)]
            proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            ready = wait_ready(proc)
            assert ready is not None, f"{cmd} ended before it was ready: {proc.communicate()}"
            sleep_until(ready + offset)
            if catches_stop_signals(proc.pid):
                break
            # Done before the signal could be sent: this test's process was not scheduled for the command's whole
            # run (a loaded machine; fig2 --quick lasts about 2 s). Once its command is done a process ignores stop
            # signals (its output and exit 0 stand) while the interpreter shuts down, so a process still alive is
            # not enough: it must still catch them. That try tells nothing: try again.
            proc.communicate()
        else:
            pytest.fail(f"{cmd}: ended before {offset} s after its readiness in {ATTEMPTS} tries")
        proc.send_signal(sig)
        try:
            _, err = proc.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.communicate()
            pytest.fail(f"{cmd}: {sig.name} {offset} s after its readiness: still running 60 s later")
        where = f"{' '.join(cmd[-len(COMMANDS[command]) - 2 :])}: {sig.name} {offset} s after its readiness"
        assert proc.returncode == 128 + sig, f"{where}: exit {proc.returncode}: {err}"
        lines = err.splitlines()
        assert len(lines) == 1 and lines[0].startswith("neurowalk: ") and "interrupted" in lines[0], f"{where}: {err}"
        assert "Traceback" not in err


def test_import_neurowalk_sets_no_signal_handler():
    code = (
        "import signal, neurowalk, neurowalk.__main__, neurowalk.runners.stopping\n"
        "print(signal.getsignal(signal.SIGTERM) is signal.SIG_DFL, signal.getsignal(signal.SIGINT) is "
        "signal.default_int_handler)"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert r.stdout.split() == ["True", "True"], r.stderr


def test_readiness_is_the_moment_the_handlers_are_set():
    code = "import signal, time; time.sleep(1); signal.signal(signal.SIGTERM, lambda *a: None); time.sleep(30)"
    proc = subprocess.Popen([sys.executable, "-c", code])
    try:
        assert not catches_stop_signals(proc.pid)  # a Python process catches SIGINT from its start, not SIGTERM
        assert wait_ready(proc, timeout=30) is not None
    finally:
        proc.kill()
        proc.wait()
