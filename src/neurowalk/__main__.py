"""``python -m neurowalk``: the ``neurowalk`` command."""

import sys

from neurowalk.cli import main

if __name__ == "__main__":
    sys.exit(main())
