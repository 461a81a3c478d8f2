"""``python -m neurowalk``: the ``neurowalk`` command."""

import sys

if __name__ == "__main__":
    try:
        from neurowalk.cli import main
    except KeyboardInterrupt:  # Ctrl-C while the command's modules load
        print("neurowalk: interrupted", file=sys.stderr)
        sys.exit(130)
    sys.exit(main())
