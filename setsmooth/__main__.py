"""``python -m setsmooth``: the command line of `setsmooth.runs.cli` (``python -m setsmooth figures ...``)."""

import sys

from .runs.cli import main

if __name__ == "__main__":
    sys.exit(main())
