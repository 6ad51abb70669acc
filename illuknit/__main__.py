"""``python -m illuknit`` runs the command line."""

import sys

from illuknit.cli import main

if __name__ == "__main__":
    sys.exit(main())
