"""The hand knitter's term of the tile assignment model: few colour changes a row (issue #37).

A hand knitter works a row at a time; every colour change along a row is a yarn to pick up, a
float to carry or a bobbin to hang (:mod:`illuknit.design.hand_cost`). The assignment fixes a
tile for every overlap pair ``p = (a, b)``, and the rows of a design change colour in two places:

* **inside** a region: a tile whose hand rows (two a unit row: a bump's ``yarn`` course, then
  its ``upper`` course) hold more than one yarn changes colour :func:`internal_changes` times a
  unit of width (cyclically, as the tile repeats), so the region's share of a row times that;
* **between** regions: where ``p`` meets ``p'`` along a row, the rows of their tiles differ in
  the yarns they hold a share :func:`row_mismatch` of the rows (the classic shadow-knitting
  design, every row in one yarn and the tiles differing only in which rows are ridges, never
  changes colour at all).

With ``AssignmentWeights.row_change_penalty`` ``w > 0`` the model gets, per overlap pair, a
variable ``("rowsig", p, s)`` for the row signature ``s`` of its tile (exactly one, forced by the
chosen fills), and soft clauses costing ``w`` ΔE per expected colour change a row (averaged over
the rows): ``sig[p, s]`` alone costs its inside changes, ``sig[p, s] & sig[p', s']`` the boundary
changes of the ``(p, p')`` meetings. ``w = 0`` (the default, the machine design) adds nothing.

>>> from illuknit.design.tiles.tile import Tile
>>> internal_changes(Tile.from_rows(["0 1"])), internal_changes(Tile.from_rows(["0", "1"]))
(1.0, 0.0)
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from illuknit.design.tiles.assignment import AssignmentWeights
from illuknit.design.tiles.tile import Tile

__all__ = [
    "HAND_ROW_CHANGE_PENALTY",
    "HandTerm",
    "hand_term",
    "hand_weights",
    "internal_changes",
    "row_mismatch",
    "row_signature",
    "with_hand_candidates",
]

#: The ΔE a colour change a hand-knitted row costs in a design made for hands
#: (``made_for="hands"``; benchmarks/hand_designs.py measures it).
HAND_ROW_CHANGE_PENALTY = 6.0

Signature = tuple[tuple[int, ...], ...]


def hand_weights(row_change_penalty: float = HAND_ROW_CHANGE_PENALTY) -> AssignmentWeights:
    """The assignment weights of a design made for hands: the defaults with the row term on."""
    return AssignmentWeights(row_change_penalty=row_change_penalty)


def with_hand_candidates(found: Sequence[Any], hand: Sequence[Any]) -> list[Any]:
    """The assignments of the ordinary search, then those the row term (or another bank, the
    shared stripes) found that it did not (the same fills of one bank once): a design made for
    hands is chosen from both, never from fewer than a machine design is (the term's model is
    larger, so its search finds fewer in the same time)."""
    seen = {(a.bank.name, a.fills_a, a.fills_b) for a in found}
    new = [a for a in hand if (a.bank.name, a.fills_a, a.fills_b) not in seen]
    return [*found, *(replace(a, rank=len(found) + k + 1) for k, a in enumerate(new))]


def row_signature(tile: Tile) -> Signature:
    """The tile's hand rows, bottom of the tile first as stored: each unit row's ``yarn``
    course, then its ``upper`` course (the same yarns without split bumps)."""
    yarn = np.asarray(tile.yarn)
    upper = yarn if tile.upper is None else np.asarray(tile.upper)
    rows: list[tuple[int, ...]] = []
    for k in range(yarn.shape[0]):
        rows.append(tuple(int(v) for v in yarn[k]))
        rows.append(tuple(int(v) for v in upper[k]))
    return tuple(rows)


def _sig_changes(sig: Signature) -> float:
    """Colour changes a unit of width, averaged over the rows (cyclic: the tile repeats)."""
    w = len(sig[0])
    per_row = [sum(r[i] != r[(i + 1) % w] for i in range(w)) if w > 1 else 0 for r in sig]
    return float(np.mean(per_row)) / w


def internal_changes(tile: Tile) -> float:
    """Colour changes a unit of width inside a region of ``tile``, averaged over its hand rows."""
    return _sig_changes(row_signature(tile))


def row_mismatch(s: Signature, t: Signature) -> float:
    """The share of rows in which two tiles side by side hold different yarns (over the least
    common multiple of their heights): a colour change where their regions meet."""
    n = math.lcm(len(s), len(t))
    differ = sum(
        set(s[k % len(s)]) != set(t[k % len(t)]) or len(set(s[k % len(s)])) > 1 for k in range(n)
    )
    return differ / n


@dataclass(frozen=True)
class HandTerm:
    """What the model needs of the term (:func:`hand_term`)."""

    weight: float  # ΔE (times SCALE) per colour change a row
    sigs: tuple[Signature, ...]
    sig_of: dict[tuple[int, int], int]  # (fill in A, fill in B) -> signature number
    inside: NDArray[np.float64]  # (len(sigs),) changes a unit of width
    mismatch: NDArray[np.float64]  # (len(sigs), len(sigs))
    area: dict[tuple[int, int], float]  # overlap pair -> units a row, on average
    meets: dict[tuple[tuple[int, int], tuple[int, int]], float]  # pair meetings a row

    def pair_cost(self, p: tuple[int, int], s: int) -> int:
        return round(self.weight * self.area[p] * self.inside[s])

    def meet_cost(self, pq: tuple[tuple[int, int], tuple[int, int]], s: int, t: int) -> int:
        return round(self.weight * self.meets[pq] * self.mismatch[s, t])

    def cost(self, ca: Mapping[int, int], cb: Mapping[int, int]) -> int:
        """The integer cost of a choice of fills (for :func:`~.assign_model._cost`)."""
        sig = {(a, b): self.sig_of[ca[a], cb[b]] for a, b in self.area}
        total = sum(self.pair_cost(p, sig[p]) for p in self.area)
        return total + sum(self.meet_cost(pq, sig[pq[0]], sig[pq[1]]) for pq in self.meets)


def _meetings(
    ia: NDArray[Any], ib: NDArray[Any]
) -> dict[tuple[tuple[int, int], tuple[int, int]], float]:
    """Horizontal meetings of two different overlap pairs, counted a row on average."""
    n = ia.shape[0]
    left = (ia[:, :-1], ib[:, :-1])
    right = (ia[:, 1:], ib[:, 1:])
    diff = (left[0] != right[0]) | (left[1] != right[1])
    out: dict[tuple[tuple[int, int], tuple[int, int]], float] = {}
    for a, b, c, d in zip(
        left[0][diff], left[1][diff], right[0][diff], right[1][diff], strict=True
    ):
        p, q = sorted(((int(a), int(b)), (int(c), int(d))))
        out[p, q] = out.get((p, q), 0.0) + 1.0 / n
    return out


def hand_term(
    bank: Any, views: Any, fills: tuple[Any, Any], compat: NDArray[np.bool_],
    indices: tuple[NDArray[Any], NDArray[Any]], pairs: Mapping[tuple[int, int], int],
    weight: float,
) -> HandTerm:  # fmt: skip
    """The term for a problem (``weight`` already in model units: ΔE times SCALE): the fills of
    the two views, their compatibility, the two region maps and the overlap pairs."""
    fa, fb = fills
    ia, ib = indices
    sigs: dict[Signature, int] = {}
    sig_of: dict[tuple[int, int], int] = {}
    for f, g in zip(*np.nonzero(compat), strict=True):
        tile = bank.tile_for(fa[int(f)], fb[int(g)], views=views)
        s = row_signature(tile)
        sig_of[int(f), int(g)] = sigs.setdefault(s, len(sigs))
    order = tuple(sigs)
    inside = np.array([_sig_changes(s) for s in order])
    mismatch = np.array([[row_mismatch(s, t) for t in order] for s in order])
    n = ia.shape[0]
    area = {p: cnt / n for p, cnt in pairs.items()}
    return HandTerm(weight, order, sig_of, inside, mismatch, area, _meetings(ia, ib))
