"""Moved to :mod:`illuknit.knitout.floats` (the float measure lives with the program, below the
scheduler); this name keeps working for one release with a :class:`DeprecationWarning`."""

from __future__ import annotations

import warnings
from typing import Any

_MOVED = frozenset(
    {"LOOP_OPS", "Float", "FloatTracker", "long_floats", "needle_slot", "program_floats"}
)


def __getattr__(name: str) -> Any:
    if name in _MOVED:
        warnings.warn(
            f"illuknit.check.floats.{name} moved to illuknit.knitout.floats.{name}",
            DeprecationWarning,
            stacklevel=2,
        )
        from illuknit.knitout import floats

        return getattr(floats, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
