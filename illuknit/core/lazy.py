"""Lazily imported public names for a package (PEP 562), so ``import illuknit`` stays fast.

A package lists ``{public name: defining module}`` and installs the two hooks::

    __getattr__, __dir__ = lazy_api(__name__, _API)
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping
from typing import Any

__all__ = ["lazy_api"]


def lazy_api(
    package: str, api: Mapping[str, str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """Module ``__getattr__`` and ``__dir__`` that import each name of ``api`` on first use."""

    def __getattr__(name: str) -> Any:
        module = api.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module), name)
        setattr(sys.modules[package], name, value)  # cache: later lookups skip this hook
        return value

    def __dir__() -> list[str]:
        return sorted(getattr(sys.modules[package], "__all__", api))

    return __getattr__, __dir__
