"""``python -m neurowalk.cli ...``: the ``neurowalk`` command (its entry point, :mod:`neurowalk.__main__`)."""

import sys

from neurowalk.__main__ import main

if __name__ == "__main__":
    sys.exit(main())
