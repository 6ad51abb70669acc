"""Reading the project's document files (patterns, tile banks, render parameters, manifests).

Each kind of document has its own error class; these helpers turn every way a file can fail to
read (missing, unreadable, not UTF-8, not JSON) into one such error with a clear message, so the
loaders only validate content.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from illuknit.core.errors import IlluknitError

__all__ = ["read_json_file", "read_text_file"]


def read_text_file(path: str | os.PathLike[str], *, error: type[IlluknitError], what: str) -> str:
    """The UTF-8 text of ``path``; ``error("<what> file not found: ...")`` and the like on failure."""
    p = Path(path)
    try:
        return p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error(f"{what} file not found: {p}") from None
    except (OSError, UnicodeDecodeError) as e:
        raise error(f"cannot read {what} file {p}: {e}") from None


def read_json_file(path: str | os.PathLike[str], *, error: type[IlluknitError], what: str) -> Any:
    """The parsed JSON of ``path``, raising ``error`` for a missing, unreadable or invalid file."""
    text = read_text_file(path, error=error, what=what)
    try:
        return json.loads(text)
    except json.JSONDecodeError as e:
        raise error(f"{Path(path)} is not valid JSON: {e}") from None
    except RecursionError:  # the decoder recurses once per level of nesting
        raise error(f"{Path(path)} is nested too deeply to be a {what} file") from None
