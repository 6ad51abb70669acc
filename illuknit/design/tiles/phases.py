"""Stripe phases of the assigned tiles: rotate each pair's tile so stripes line up across regions."""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from illuknit.design.tiles.assignment import SeenView
from illuknit.design.tiles.bank import ViewPair
from illuknit.design.tiles.tile import Tile, tile_seen

__all__ = ["align_phases"]


def _expand(view: str) -> tuple[SeenView, ...]:
    return ("A", "B") if view == "side" else (view,)  # type: ignore[return-value]


def _agreement(s1: NDArray[np.int16], s2: NDArray[np.int16]) -> int:
    """Units over a common period where two periodic seen-yarn blocks agree."""
    h, w = math.lcm(s1.shape[0], s2.shape[0]), math.lcm(s1.shape[1], s2.shape[1])
    a = np.tile(s1, (h // s1.shape[0], w // s1.shape[1]))
    b = np.tile(s2, (h // s2.shape[0], w // s2.shape[1]))
    return int((a == b).sum() * (12 // math.gcd(12, h)))  # per 12 rows, so periods compare fairly


def align_phases(
    tiles: Mapping[tuple[int, int], Tile],
    counts: Mapping[tuple[int, int], int],
    views: ViewPair = ("A", "B"),
) -> dict[tuple[int, int], Tile]:
    """Rotate each pair's tile (a cyclic shift of its rows keeps its fills) so that the stripes
    of one colour line up across the overlap pairs it belongs to.

    Without this, a colour of A whose region crosses several colours of B would show its stripe
    in a different phase over each of them, and B's outlines would ghost into view A. Pairs are
    handled largest first; the first pair of each colour fixes that colour's stripe phase, and
    every later pair takes the rotation that agrees best with the phases already fixed for its
    two colours (it cannot always agree with both).
    """
    refs: tuple[
        dict[int, dict[str, NDArray[np.int16]]], dict[int, dict[str, NDArray[np.int16]]]
    ] = ({}, {})
    out: dict[tuple[int, int], Tile] = {}
    for pair in sorted(tiles, key=lambda p: (-counts.get(p, 0), p)):
        t = tiles[pair]
        best, best_score = t, -1
        for s in range(t.height):
            rt = t if s == 0 else t.rolled(s)
            score = 0
            for side in (0, 1):
                ref = refs[side].get(pair[side])
                if ref is not None:
                    score += sum(_agreement(tile_seen(rt, v), ref[v]) for v in _expand(views[side]))
            if score > best_score:
                best, best_score = rt, score
        out[pair] = best
        for side in (0, 1):
            refs[side].setdefault(pair[side], {v: tile_seen(best, v) for v in _expand(views[side])})
    return out
