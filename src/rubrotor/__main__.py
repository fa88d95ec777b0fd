"""``python -m rubrotor``: the command line (see :mod:`rubrotor.cli`)."""

import sys

from rubrotor import cli

if __name__ == "__main__":
    sys.exit(cli.main())
