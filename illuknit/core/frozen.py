"""Read-only mappings in the frozen IRs, and how they pickle.

Frozen IRs hold their tables as :class:`types.MappingProxyType`, so nobody changes them in place;
plain pickle refuses a mapping proxy. Importing :mod:`illuknit` registers (:mod:`copyreg`) that a
proxy pickles as its dict and comes back as a proxy, so IRs cross to worker processes (the app's
killable jobs) and into the app's session store like any other value.
"""

from __future__ import annotations

import copyreg
import types
from collections.abc import Mapping
from typing import Any

__all__ = ["frozen_mapping"]


def frozen_mapping(items: Mapping[Any, Any]) -> types.MappingProxyType[Any, Any]:
    """A read-only view of a copy of ``items``."""
    return types.MappingProxyType(dict(items))


def _reduce(proxy: types.MappingProxyType[Any, Any]) -> tuple[Any, ...]:
    return (frozen_mapping, (dict(proxy),))


copyreg.pickle(types.MappingProxyType, _reduce)
