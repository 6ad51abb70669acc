"""Suggested edits to a double-view design's pictures (the paper's designer loop, Fig. 11-12).

When two pictures are over-constrained, a designer edits them -- erases a detail, smooths an
outline -- until the illusion reads. This module proposes such edits automatically, on the
quantised pictures (yarn index maps), and measures each one by what it does to the *original*
pictures' readability (an edit is judged by the picture the designer wanted, never by its own
simplified version):

* ``merge-small-regions`` -- connected regions smaller than ``min_region`` units take the colour
  that surrounds them most (specks a tile cannot show anyway);
* ``smooth-boundaries`` -- each unit takes the most common colour of its 3 x 3 neighbourhood when
  that colour holds a clear majority (ragged, one-unit steps in an outline become straight);
* ``drop-small-overlaps`` -- an overlap pair (colour of A over colour of B) covering fewer than
  ``min_overlap`` units is removed by repainting those units of B in the colour of B that most
  often lies under that colour of A (a pair that is never seen need not constrain the tiles).

:func:`suggest_edits` builds the suggestions from a pair of index maps; :func:`apply_edits`
measures each with a caller-given function (normally: assign tiles, compile, rank by perception)
and keeps, one after the other, those that raise the worse view's readability.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "EDIT_NAMES",
    "EditResult",
    "Suggestion",
    "apply_edits",
    "best_reading",
    "drop_small_overlaps",
    "merge_small_regions",
    "smooth_boundaries",
    "suggest_edits",
]

#: The edits, in the order they are tried.
EDIT_NAMES = ("merge-small-regions", "smooth-boundaries", "drop-small-overlaps")


def _index_map(a: ArrayLike, name: str) -> NDArray[np.int16]:
    from illuknit.errors import ImageInputError

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

    idx = _index_map(indices, "indices")
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

    idx = _index_map(indices, "indices")
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
    ia, ib = _index_map(a, "a"), _index_map(b, "b")
    if ia.shape != ib.shape:
        from illuknit.errors import ImageInputError

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


@dataclass(frozen=True)
class Suggestion:
    """One edit of the pair of pictures.

    Attributes
    ----------
    name : str
        One of :data:`EDIT_NAMES`.
    description : str
        What the edit does, for the designer.
    a, b : ndarray of shape (N, M), int16
        The edited index maps.
    changed : tuple of int
        Units changed in ``a`` and in ``b``.
    """

    name: str
    description: str
    a: NDArray[np.int16]
    b: NDArray[np.int16]
    changed: tuple[int, int]


def _suggestion(
    name: str, text: str, a0: NDArray[np.int16], b0: NDArray[np.int16], a1: NDArray[np.int16],
    b1: NDArray[np.int16],
) -> Suggestion | None:  # fmt: skip
    changed = (int((a0 != a1).sum()), int((b0 != b1).sum()))
    if changed == (0, 0):
        return None
    return Suggestion(name, text, a1, b1, changed)


def suggest_edits(
    a: ArrayLike,
    b: ArrayLike,
    *,
    min_region: int = 4,
    min_overlap: int = 4,
    names: Sequence[str] = EDIT_NAMES,
) -> list[Suggestion]:
    """The edits of :data:`EDIT_NAMES` that change something, each applied to ``a`` and ``b``."""
    from illuknit.errors import OptionError

    unknown = [n for n in names if n not in EDIT_NAMES]
    if unknown:
        raise OptionError(f"unknown edit {unknown[0]!r}; known: {', '.join(EDIT_NAMES)}")
    ia, ib = _index_map(a, "a"), _index_map(b, "b")
    out: list[Suggestion | None] = []
    for name in names:
        if name == "merge-small-regions":
            out.append(
                _suggestion(
                    name,
                    f"merge regions smaller than {min_region} units into their surroundings",
                    ia,
                    ib,
                    merge_small_regions(ia, min_region=min_region),
                    merge_small_regions(ib, min_region=min_region),
                )
            )
        elif name == "smooth-boundaries":
            out.append(
                _suggestion(
                    name,
                    "smooth ragged region boundaries (3 x 3 majority)",
                    ia,
                    ib,
                    smooth_boundaries(ia),
                    smooth_boundaries(ib),
                )
            )
        else:
            out.append(
                _suggestion(
                    name,
                    f"remove overlaps of fewer than {min_overlap} units (repainted in picture B)",
                    ia,
                    ib,
                    ia,
                    drop_small_overlaps(ia, ib, min_overlap=min_overlap),
                )
            )
    return [s for s in out if s is not None]


@dataclass(frozen=True)
class EditResult:
    """A suggestion measured: the worse view's readability and the worst ghosting before and
    after (against the original pictures), and whether :func:`apply_edits` kept it."""

    suggestion: Suggestion
    before: tuple[float, float]
    after: tuple[float, float]
    accepted: bool

    def to_json(self) -> dict[str, object]:
        return {
            "edit": self.suggestion.name,
            "description": self.suggestion.description,
            "units_changed": {"A": self.suggestion.changed[0], "B": self.suggestion.changed[1]},
            "readability_before": round(self.before[0], 4),
            "readability_after": round(self.after[0], 4),
            "ghosting_before": round(self.before[1], 4),
            "ghosting_after": round(self.after[1], 4),
            "accepted": self.accepted,
        }


def best_reading(
    a: ArrayLike,
    b: ArrayLike,
    *,
    colors: tuple[ArrayLike, ArrayLike],
    targets: Sequence[ArrayLike],
    candidates: int = 5,
    **assign: object,
) -> tuple[float, float]:
    """Worse-view readability and worst ghosting of the best-reading tile design for the index
    maps ``a``, ``b`` (picture colours ``colors``), judged against ``targets`` -- the original
    pictures. A pair with no tile design at all scores (-1, 1). ``assign`` goes to
    :func:`~illuknit.tiles.assign.assign_tiles` (bank, yarns, solver, brightness, ...)."""
    from illuknit.errors import TileAssignmentError
    from illuknit.tiles.assign import assign_tiles
    from illuknit.tiles.perception import rank_designs

    try:
        found = assign_tiles(
            (np.asarray(a), np.asarray(colors[0])),
            (np.asarray(b), np.asarray(colors[1])),
            candidates=candidates,
            explain=False,
            **assign,  # type: ignore[arg-type]
        )
    except TileAssignmentError:
        return (-1.0, 1.0)
    best = rank_designs(found, targets)[0].measures
    return (best.worse_readability, best.worst_ghosting)


def apply_edits(
    a: ArrayLike,
    b: ArrayLike,
    measure: Callable[[NDArray[np.int16], NDArray[np.int16]], tuple[float, float]],
    *,
    min_region: int = 4,
    min_overlap: int = 4,
) -> tuple[NDArray[np.int16], NDArray[np.int16], list[EditResult]]:
    """Try each edit on the pictures as edited so far; keep those that raise the worse view's
    readability.

    Parameters
    ----------
    a, b : ndarray of shape (N, M)
        Index maps of the two quantised pictures.
    measure : callable
        ``measure(a, b) -> (worse-view readability, worst ghosting)`` of the best design for the
        edited maps, judged against the ORIGINAL pictures.

    Returns
    -------
    (a, b, results)
        The edited maps (the inputs when nothing helped) and every edit tried, in order.
    """
    ia, ib = _index_map(a, "a"), _index_map(b, "b")
    current = measure(ia, ib)
    results = []
    for name in EDIT_NAMES:
        found = suggest_edits(ia, ib, min_region=min_region, min_overlap=min_overlap, names=[name])
        if not found:
            continue
        s = found[0]
        after = measure(s.a, s.b)
        keep = after[0] > current[0] + 1e-6
        results.append(EditResult(s, current, after, keep))
        if keep:
            ia, ib, current = s.a, s.b, after
    return ia, ib, results
