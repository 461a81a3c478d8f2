"""The ``neurowalk`` command's entry point: the console script and ``python -m neurowalk`` call :func:`main`.

It answers SIGINT (Ctrl-C) and SIGTERM from the moment it runs, before the command's modules load (a second or
more on a loaded machine): a stop at any moment of the command's start ends in one line on stderr and exit status
130 (SIGINT) or 143 (SIGTERM), 128 + the signal's number as a shell reports it, never in a traceback. Only the
interpreter's own start and ``import neurowalk`` (kept light, and changing no signal handler) come before.
"""

import os
import signal
import sys


def main() -> int:
    """Run the ``neurowalk`` command on ``sys.argv``; its exit status.

    A command a stop signal ended leaves the process at once, once its line is out (``os._exit``): the work it kept
    is closed and on disk by then, and the interpreter's shutdown, with a C extension's thread or compilation cut
    short by the signal, could otherwise end in a crash or in death by SIGINT instead of exit status 130 or 143.
    """
    from neurowalk.runners.stopping import stop_came

    status = _command()
    if stop_came():
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(status)
    return status


def _command() -> int:
    """The command's exit status, a stop at any moment of it answered in one line."""
    from neurowalk.runners.stopping import interrupted, stop_on_signals, stop_status  # light: nothing heavy yet

    try:
        # After the command a signal is ignored: its output and exit status stand (no traceback from the exit).
        with stop_on_signals(then=signal.SIG_IGN):
            try:
                from neurowalk.cli import main as command

                return command()
            except (KeyboardInterrupt, Exception) as e:  # while the command's modules load (a C extension's
                if not interrupted(e):  # import can turn the interrupt into an ImportError)
                    raise
    except KeyboardInterrupt:  # the instant the handlers were being set or put back
        pass
    print("neurowalk: interrupted", file=sys.stderr)  # (signals are ignored by now: this line is the only one)
    return stop_status()


if __name__ == "__main__":
    sys.exit(main())
