"""Edits of quantised pictures that simplify a double-view design (used by tiles.simplify).

Pure functions of index maps (and, for :func:`requantise_pair`, of the source pictures); what
each edit is for, and how edits are suggested and judged, is told in :mod:`illuknit.design.tiles.simplify`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.errors import ImageInputError, OptionError
from illuknit.design.tiles.assignment import Regions, regions_of

__all__ = [
    "drop_small_overlaps",
    "index_map",
    "merge_small_regions",
    "requantise_pair",
    "smooth_boundaries",
]


def index_map(a: ArrayLike, name: str) -> NDArray[np.int16]:
    """``a`` as an int16 index map, checked: non-empty, 2-D, integer (``name`` in the error)."""
    arr = np.asarray(a)
    if arr.ndim != 2 or not np.issubdtype(arr.dtype, np.integer) or arr.size == 0:
        raise ImageInputError(f"`{name}` must be a non-empty 2-D integer index map")
    return arr.astype(np.int16)


def merge_small_regions(indices: ArrayLike, *, min_region: int = 4) -> NDArray[np.int16]:
    """Repaint every 4-connected region of fewer than ``min_region`` units with the colour that
    borders it most; larger regions are untouched.

    Examples
    --------
    >>> merge_small_regions(np.array([[0, 0, 0], [0, 1, 0], [0, 0, 0]]), min_region=2)
    array([[0, 0, 0],
           [0, 0, 0],
           [0, 0, 0]], dtype=int16)
    """
    from scipy import ndimage

    idx = index_map(indices, "indices")
    out = idx.copy()
    for color in np.unique(idx):
        labels, n = ndimage.label(idx == color)
        if n == 0:
            continue
        sizes = np.bincount(labels.ravel())
        for lab in np.nonzero(sizes < min_region)[0]:
            if lab == 0:
                continue
            region = labels == lab
            ring = ndimage.binary_dilation(region) & ~region
            around = out[ring]
            if around.size:
                out[region] = np.bincount(around).argmax()
    return out


def smooth_boundaries(indices: ArrayLike, *, majority: int = 6) -> NDArray[np.int16]:
    """Each unit takes the most common colour of its 3 x 3 neighbourhood (itself included) when
    that colour has at least ``majority`` of the 9 votes (edges reflected)."""
    from scipy import ndimage

    idx = index_map(indices, "indices")
    k = int(idx.max()) + 1
    votes = np.stack(
        [
            ndimage.uniform_filter((idx == c).astype(np.float64), 3, mode="reflect") * 9
            for c in range(k)
        ]
    )
    best = votes.argmax(axis=0).astype(np.int16)
    strong = votes.max(axis=0) >= majority - 1e-9
    return np.where(strong, best, idx).astype(np.int16)


def drop_small_overlaps(a: ArrayLike, b: ArrayLike, *, min_overlap: int = 4) -> NDArray[np.int16]:
    """Picture ``b`` with every overlap pair of fewer than ``min_overlap`` units removed: those
    units of ``b`` take the colour of ``b`` that lies most often under the same colour of ``a``."""
    ia, ib = index_map(a, "a"), index_map(b, "b")
    if ia.shape != ib.shape:
        raise ImageInputError(f"the pictures differ in size: {ia.shape} and {ib.shape}")
    out = ib.copy()
    kb = int(ib.max()) + 1
    for ca in np.unique(ia):
        under = np.bincount(ib[ia == ca], minlength=kb)
        main = int(under.argmax())
        for cb in np.nonzero((under > 0) & (under < min_overlap))[0]:
            if cb != main:
                out[(ia == ca) & (ib == cb)] = main
    return out


def requantise_pair(
    sources: Sequence[ArrayLike], n_colors: int, *, yarns: Sequence[Any] | None = None
) -> tuple[Regions, Regions]:
    """Both source pictures re-read with ``n_colors`` colours.

    Parameters
    ----------
    sources : pair of ndarray of shape (N, M, 3)
        The pictures before quantisation, already on the design's grid.
    n_colors : int
        Colours per picture, at least 2.
    yarns : sequence of Yarn, optional
        Map each picture to these yarns (its colours are then yarn colours, as the bundled
        instances are quantised); by default the colours are the pictures' own cluster centres
        (as ``illuknit double`` quantises).
    """
    from illuknit.pictures.images import quantise_image

    if n_colors < 2:
        raise OptionError(f"`n_colors` must be at least 2, got {n_colors}")
    out = []
    for src in sources:
        q = quantise_image(src, n_colors=n_colors, yarns=yarns)
        colors = q.palette if yarns is not None else q.colors
        out.append(regions_of((q.indices, colors)))
    return out[0], out[1]
