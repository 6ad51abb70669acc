"""Shared stripes: double views whose every row is knitted in one yarn (issue #37).

Classic shadow knitting (Høxbro, WoollyThoughts) works every row in one yarn: the piece is
striped, two rows of dark then two rows of light, and the picture lives only in which stitches
are purled into ridges. A hand knitter carries no float and changes colour only at the edge.

:func:`stripe_bank` is that technique as a tile bank. Every tile has the same yarns, unit row by
unit row, :data:`STRIPE` = dark, dark, light, light (a unit row is two hand rows), and the tiles
differ only in their bumps (all 16 patterns of a height-4 tile). The bank is ``phase_locked``:
the assignment does not shift a tile's rows to line up its stripes with its neighbours' (as
:func:`~illuknit.design.tiles.phases.align_phases` does), and compiling lays every tile at the
piece's global row phase, so a unit row is one yarn from edge to edge in every design of this bank.
Seen from either end, each tile shows 1/4, 1/2 or 3/4 dark, in any combination for A and B:
3 brightness levels a side, enough for pictures of up to 3 colours each. Head-on it shows half
and half, so a stripe design shows even stripes head-on.

Why this stripe and no other:

* Two rows a colour (``01``) cannot show two views. With yarns ``C = (0, 1)`` and bumps
  ``R0, R1``, view A shows ``VA[0] = 1 if R1 else 0`` and ``VA[1] = 0 if R0 else 1``; view B
  shows ``VB[0] = C[1] if R1 else C[0]``, the same yarn, and ``VB[1] = C[0] if R0 else C[1]``,
  again the same yarn. A and B always see the same fill.
* Longer runs make coarser stripes, which read worse. On the three bundled pairs whose hand
  design is a stripe design (illusion-knitting-small, illusion-knitting, coffee-chelsea-3),
  the worse side's correlation was 0.60 / 0.88 / 0.79 with ``0011``; 0.58 / 0.88 with
  ``0001`` (coffee-chelsea-3 then kept a design with unknittable rows); 0.47 / 0.75 / 0.62 with
  ``00011``; 0.29 / 0.56 / 0.47 with ``000111``; 0.02 / 0.21 / 0.21 with ``00001111``
  (``benchmarks/hand_designs.py --small --stripe S``, 20 designs searched).
* A 3-yarn stripe (``001122``) reads worse on coffee-chelsea-3 (0.59) than its two yarns of
  most contrast in ``0011`` (0.79). So a stripe design uses two yarns, the darkest and the lightest
  (:func:`stripe_yarns`), and shows a 3-colour picture with its 3 levels.

>>> from illuknit.core.pattern import Yarn
>>> bank = stripe_bank([Yarn("dark", (30, 30, 30)), Yarn("light", (240, 240, 240))])
>>> len(bank), bank.phase_locked, sorted({t.rows()[0][0] + t.rows()[2][0] for t in bank.tiles})
(16, True, ['01'])
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from typing import Any

import numpy as np

from illuknit.core.colors import luminance
from illuknit.core.errors import TileAssignmentError, TileBankError, YarnSpecError
from illuknit.core.pattern import Yarn, check_yarns
from illuknit.design.tiles.assignment import TileAssignment
from illuknit.design.tiles.bank import TileBank, ViewPair
from illuknit.design.tiles.tile import Tile

__all__ = ["STRIPE", "STRIPE_BANK_NAME", "search_stripes", "stripe_bank", "stripe_yarns"]

#: The yarn of each unit row of every tile: 0 the darker yarn, 1 the lighter, bottom row first.
STRIPE: tuple[int, ...] = (0, 0, 1, 1)
#: The name :func:`stripe_bank` gives its banks (shown where a design names its bank).
STRIPE_BANK_NAME = "shared stripes"


def stripe_yarns(yarns: Sequence[Yarn]) -> tuple[Yarn, Yarn]:
    """The two yarns a stripe design knits with: the darkest and the lightest (by relative
    luminance; the first of equals). Raises :class:`YarnSpecError` on fewer than two yarns or
    when all are equally light (no contrast to show a picture with)."""
    ys = check_yarns(yarns)
    if len(ys) < 2:
        raise YarnSpecError(f"a stripe design needs two yarns, got {len(ys)}")
    lum = luminance(np.array([y.rgb for y in ys], dtype=np.float64))
    dark, light = int(np.argmin(lum)), int(np.argmax(lum))
    if lum[dark] == lum[light]:
        raise YarnSpecError("a stripe design needs two yarns of different lightness")
    return ys[dark], ys[light]


def stripe_bank(yarns: Sequence[Yarn], *, stripe: Sequence[int] = STRIPE) -> TileBank:
    """The shared-stripe bank over ``yarns`` (two for :data:`STRIPE`, darker first;
    :func:`stripe_yarns` picks them from more): every bump pattern over ``stripe`` (the yarn of
    each unit row, each yarn at least once, at most 8 rows), fewest bumps first, ``phase_locked``.
    """
    ys = check_yarns(yarns)
    rows = tuple(stripe)
    if not 2 <= len(rows) <= 8 or not all(isinstance(y, int) for y in rows):
        raise TileBankError(f"`stripe` must be 2 to 8 yarn numbers, got {stripe!r}")
    if sorted(set(rows)) != list(range(len(ys))):
        raise TileBankError(
            f"`stripe` must use each of the {len(ys)} yarns (0 to {len(ys) - 1}), got {stripe!r}"
        )
    h = len(rows)
    tiles = [
        Tile.from_rows([f"{rows[k]}{'^' if bumps[k] else ''}" for k in range(h)])
        for bumps in itertools.product((False, True), repeat=h)
    ]
    tiles.sort(key=lambda t: (int(t.raised.sum()), t.code()))
    return TileBank(ys, tuple(tiles), name=STRIPE_BANK_NAME, phase_locked=True)


def search_stripes(
    qa: Any, qb: Any, *, yarns: Sequence[Yarn], views: ViewPair = ("A", "B"), **kw: Any
) -> list[TileAssignment]:
    """The double-view assignments of the shared-stripe bank over the darkest and lightest of
    ``yarns`` (``kw``: :func:`~illuknit.design.tiles.assign.assign_tiles`'s options), or none
    when the bank cannot serve the pictures: a head-on design (every stripe tile is half and
    half head-on), pictures of more than 3 colours a side, or fills whose brightness order
    cannot follow the pictures'."""
    from illuknit.design.tiles.assign import assign_tiles

    if tuple(views) != ("A", "B"):
        return []
    try:
        bank = stripe_bank(stripe_yarns(yarns))
        return assign_tiles(qa, qb, bank=bank, views=views, explain=False, **kw)
    except (TileAssignmentError, YarnSpecError):
        return []
