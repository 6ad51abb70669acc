"""The head-on variant (paper Fig. 17): a picture seen head-on that disappears at an angle.

Looking straight at the fabric every unit is visible; from either side a bump hides the unit
beyond it. A tile such as ``0^/1`` (bump of yarn 0, then flat yarn 1) shows a 0/1 stripe head-on
but solid 0 from both sides, while ``0`` shows solid 0 everywhere. Laying the first kind of tile
where the *front* picture is and the second elsewhere, the front picture is there head-on and
gone at an angle, where only the *side* picture (here: a plain field) is seen.

This is the double-view assignment of :mod:`illuknit.design.tiles.assign` with the views
``("headon", "side")``: every colour of the front picture gets a head-on fill, every colour of
the side picture gets a fill seen identically from A and from B, and every overlap pair needs a
tile of the bank :func:`headon_bank` with that head-on fill and that side fill. When no side
picture is given, the side is one uniform region, so the front picture vanishes completely.
"""

from __future__ import annotations

import inspect
from collections.abc import Sequence
from dataclasses import fields
from typing import Any

import numpy as np

from illuknit.core.arguments import check_instance, check_int
from illuknit.core.errors import TileAssignmentError, TileBankError, UnknownNameError
from illuknit.core.pattern import Yarn, check_yarns
from illuknit.design.tiles.assign import MAX_ASSIGNMENTS, AssignOptions, _yarns_of, assign_tiles
from illuknit.design.tiles.assignment import TileAssignment, regions_of
from illuknit.design.tiles.bank import TileBank, ViewPair, canonical_bank

__all__ = ["HEADON_VIEWS", "assign_headon", "headon_bank", "uniform_side"]

HEADON_VIEWS: ViewPair = ("headon", "side")


def headon_bank(yarns: Sequence[Yarn], *, max_height: int = 4) -> TileBank:
    """The canonical bank deduplicated by (head-on fill, side fill), for tiles whose two side
    views show the same fill."""
    return canonical_bank(yarns, max_height=max_height, views=HEADON_VIEWS)


def uniform_side(
    front: Any, *, color: Sequence[int] | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """A one-region side picture the size of ``front``: ``(indices, colors)``.

    Its colour defaults to the colour of the front picture's largest region, so the side view
    reads as the background.
    """
    r = regions_of(front, name="front")
    if color is None:
        counts = np.bincount(r.indices.ravel(), minlength=len(r.colors))
        color = r.colors[int(counts.argmax())]
    cols = np.array([list(color)], dtype=np.uint8)
    return np.zeros(r.indices.shape, dtype=np.int16), cols


def assign_headon(
    front: Any,
    side: Any | None = None,
    *,
    bank: TileBank | None = None,
    yarns: Sequence[Yarn] | None = None,
    candidates: int = 5,
    **options: Any,
) -> list[TileAssignment]:
    """Tile assignments that show ``front`` head-on and ``side`` (or nothing) at an angle.

    Parameters
    ----------
    front, side : QuantisedImage or (indices, colors)
        ``side`` None means a uniform side view (see :func:`uniform_side`).
    bank : TileBank, optional
        Defaults to :func:`headon_bank` of ``yarns`` (or of the pictures' yarns).
    **options
        Passed on to :func:`~illuknit.design.tiles.assign.assign_tiles` (``brightness``, ``solver``, ...).

    Returns
    -------
    list of TileAssignment
        With ``views == ("headon", "side")``; compile them with
        :func:`~illuknit.design.tiles.compile.compile_tiles`.
    """
    if bank is not None:
        check_instance(bank, TileBank, "bank", error=TileBankError)
    if yarns is not None:
        check_yarns(yarns)
    check_int(candidates, "candidates", min=1, max=MAX_ASSIGNMENTS, error=TileAssignmentError)
    regions_of(front, name="front")
    if side is not None:
        regions_of(side, name="side")
    if "views" in options:
        raise TileAssignmentError("assign_headon fixes `views` to ('headon', 'side')")
    known = set(inspect.signature(assign_tiles).parameters) - {"qa", "qb", "views", "knobs"}
    known |= {f.name for f in fields(AssignOptions)}
    for name in options:
        if name not in known:
            raise UnknownNameError("assign_tiles option", name, sorted(known))
    if side is None:
        side = uniform_side(front)
    if bank is None:
        ys = yarns if yarns is not None else _yarns_of(front, side)
        if not ys:
            raise TileAssignmentError("pass `bank` or `yarns` (the pictures carry no yarns)")
        bank = headon_bank(ys)
    return assign_tiles(
        front, side, bank=bank, candidates=candidates, views=HEADON_VIEWS, **options
    )
