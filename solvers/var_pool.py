"""Variable ids from readable keys, one pool per constraint model.

Every SAT variable of a :class:`~illuknit.solvers.model.Model` comes from its :class:`VarPool`: single
variables keyed by readable tuples (``("raised", r, c)``, like pysat's ``IDPool``) and regular
families allocated at once as numpy blocks that the same tuple keys resolve into.
"""

from __future__ import annotations

from collections.abc import Hashable, Sequence

import numpy as np
from numpy.typing import NDArray

from illuknit.core.errors import ModelError

__all__ = ["VarPool"]


class VarPool:
    """Variable ids from readable keys (like pysat's ``IDPool``), plus numpy blocks.

    Examples
    --------
    >>> pool = VarPool()
    >>> ids = pool.block("x", (2, 3))
    >>> int(ids[1, 2]) == pool.var(("x", 1, 2))
    True
    >>> pool.var("aux") == pool.top
    True
    """

    def __init__(self) -> None:
        self.top = 0
        self._keys: dict[Hashable, int] = {}
        self._blocks: dict[Hashable, tuple[int, tuple[int, ...]]] = {}

    def block(self, name: Hashable, shape: int | Sequence[int]) -> NDArray[np.int64]:
        """Allocate ``prod(shape)`` consecutive ids, addressable as ``(name, *index)``.

        Returns
        -------
        ndarray of shape ``shape``, int64
            The ids, in C order.
        """
        shp = (int(shape),) if isinstance(shape, int | np.integer) else tuple(int(s) for s in shape)
        if name in self._blocks:
            raise ModelError(f"variable block {name!r} already exists")
        if any(s < 0 for s in shp):
            raise ModelError(f"block shape must be non-negative, got {shp}")
        base = self.top + 1
        size = int(np.prod(shp, dtype=np.int64)) if shp else 1
        self.top += size
        self._blocks[name] = (base, shp)
        return np.arange(base, base + size, dtype=np.int64).reshape(shp)

    def block_ids(self, name: Hashable) -> NDArray[np.int64]:
        """The id array of an existing block."""
        try:
            base, shp = self._blocks[name]
        except KeyError:
            raise KeyError(f"no variable block {name!r}") from None
        size = int(np.prod(shp, dtype=np.int64)) if shp else 1
        return np.arange(base, base + size, dtype=np.int64).reshape(shp)

    @property
    def blocks(self) -> tuple[Hashable, ...]:
        return tuple(self._blocks)

    def _in_block(self, key: Hashable) -> int | None:
        if isinstance(key, tuple) and key and key[0] in self._blocks:
            base, shp = self._blocks[key[0]]
            idx = key[1:]
            if len(idx) == len(shp) and all(0 <= int(i) < s for i, s in zip(idx, shp, strict=True)):
                return (
                    base + int(np.ravel_multi_index(tuple(int(i) for i in idx), shp))
                    if shp
                    else base
                )
            raise KeyError(f"index {idx} out of range for block {key[0]!r} of shape {shp}")
        return None

    def var(self, key: Hashable) -> int:
        """The id of ``key``, allocating a new one on first use."""
        found = self._in_block(key)
        if found is not None:
            return found
        vid = self._keys.get(key)
        if vid is None:
            self.top += 1
            vid = self._keys[key] = self.top
        return vid

    def get(self, key: Hashable) -> int | None:
        """The id of ``key`` if it exists (never allocates)."""
        found = self._in_block(key)
        return found if found is not None else self._keys.get(key)

    def key_of(self, vid: int) -> Hashable | None:
        """Reverse lookup (slow; for messages and debugging)."""
        for name, (base, shp) in self._blocks.items():
            size = int(np.prod(shp, dtype=np.int64)) if shp else 1
            if base <= vid < base + size:
                return (name, *(int(i) for i in np.unravel_index(vid - base, shp)))
        for k, v in self._keys.items():
            if v == vid:
                return k
        return None
