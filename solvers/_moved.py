"""Old import paths of moved modules, kept working for one release with a DeprecationWarning.

A module whose contents moved keeps a stub that installs :func:`moved_module` as its PEP 562
``__getattr__``: every name read through the old path is looked up in the new module (imported
by name on first use) and warns once per read, naming the new path.
"""

from __future__ import annotations

import importlib
import warnings
from collections.abc import Callable
from typing import Any

__all__ = ["moved_module"]


def moved_module(old: str, new: str) -> Callable[[str], Any]:
    """A module ``__getattr__`` for the stub left at ``old`` when its contents moved to ``new``.

    Examples
    --------
    >>> import warnings
    >>> get = moved_module("illuknit.solvers.old", "illuknit.solvers.var_pool")
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     pool_class = get("VarPool")
    >>> pool_class.__module__, caught[0].category.__name__
    ('illuknit.solvers.var_pool', 'DeprecationWarning')
    """

    def __getattr__(name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(f"module {old!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(new), name, _MISSING)
        if value is _MISSING:
            raise AttributeError(f"module {old!r} has no attribute {name!r}")
        warnings.warn(
            f"{old}.{name} moved to {new}.{name}; the old path will be removed in the next release",
            DeprecationWarning,
            stacklevel=2,
        )
        return value

    return __getattr__


_MISSING = object()
