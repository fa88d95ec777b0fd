"""``python -m rubrotor``: the command line (see :mod:`rubrotor.cli`)."""

import sys

from rubrotor.cli.app import main

if __name__ == "__main__":
    sys.exit(main())
