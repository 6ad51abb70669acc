import subprocess
import sys

import illuknit


def test_version_matches_cli():
    out = subprocess.run(
        [sys.executable, "-m", "illuknit", "--version"], capture_output=True, text=True, check=True
    )
    assert illuknit.__version__ in out.stdout
