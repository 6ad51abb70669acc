"""The tile assignment IR: regions of the two inputs and the chosen fills and tiles.

:class:`Regions` is one quantised input as colour regions; :func:`regions_of` accepts a
:class:`~illuknit.pictures.images.QuantisedImage` or ``(indices, colors)``; :class:`TileAssignment` is
what :func:`illuknit.design.tiles.assign.assign_tiles` returns: a fill for every colour of both inputs
and a tile for every overlap pair, with its score broken down.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.colors import hex_color
from illuknit.core.errors import ImageInputError, TileAssignmentError
from illuknit.core.pattern import Yarn
from illuknit.design.tiles.bank import TileBank, ViewPair
from illuknit.design.tiles.tile import Fill, Tile

SeenView = Literal["A", "B", "headon"]

__all__ = [
    "SCALE",
    "AssignmentWeights",
    "Regions",
    "SeenView",
    "TileAssignment",
    "overlap_pairs",
    "regions_of",
]


#: Weights are stored in the model as integers: tenths of a ΔE unit.
SCALE = 10


@dataclass(frozen=True)
class AssignmentWeights:
    """Objective weights, in CIELAB ΔE units (see the module docstring)."""

    stripe_penalty: float = 8.0
    yarn_penalty: float = 3.0
    order_penalty: float = 50.0

    def __post_init__(self) -> None:
        for k in ("stripe_penalty", "yarn_penalty", "order_penalty"):
            if not getattr(self, k) >= 0:
                raise TileAssignmentError(f"`{k}` must be >= 0, got {getattr(self, k)!r}")


@dataclass(frozen=True)
class Regions:
    """One input as region colours: indices (N, M) into colors (K, 3) uint8."""

    indices: NDArray[np.int16]
    colors: NDArray[np.uint8]


def regions_of(q: Any, *, name: str = "image") -> Regions:
    """Accept a :class:`~illuknit.pictures.images.QuantisedImage` (``.indices``, ``.colors``) or a pair
    ``(indices (N, M), colors (K, 3))``."""
    if isinstance(q, Regions):
        return q
    if isinstance(q, tuple) and len(q) == 2:
        idx, cols = q
    else:
        idx = getattr(q, "indices", None)
        cols = getattr(q, "colors", None)
        if cols is None:
            cols = getattr(q, "palette", None)
    if idx is None or cols is None:
        raise ImageInputError(
            f"`{name}` must be a QuantisedImage or (indices, colors), got {type(q).__name__}"
        )
    idx = np.asarray(idx)
    cols = np.asarray(cols)
    if idx.ndim != 2 or not np.issubdtype(idx.dtype, np.integer):
        raise ImageInputError(
            f"`{name}` indices must be a 2-D integer array, got shape {idx.shape}"
        )
    if cols.ndim != 2 or cols.shape[1] != 3:
        raise ImageInputError(f"`{name}` colors must have shape (K, 3), got {cols.shape}")
    if idx.size == 0 or idx.min() < 0 or idx.max() >= len(cols):
        raise ImageInputError(f"`{name}` indices must lie in 0..{len(cols) - 1}")
    idx = np.array(idx, dtype=np.int16)
    idx.setflags(write=False)
    cols = np.array(np.round(cols), dtype=np.uint8) if cols.dtype != np.uint8 else np.array(cols)
    cols.setflags(write=False)
    return Regions(idx, cols)


def overlap_pairs(ia: ArrayLike, ib: ArrayLike) -> dict[tuple[int, int], int]:
    """``{(a, b): pixel count}`` for every overlap pair that occurs."""
    a = np.asarray(ia).ravel().astype(np.int64)
    b = np.asarray(ib).ravel().astype(np.int64)
    kb = int(b.max()) + 1
    codes, counts = np.unique(a * kb + b, return_counts=True)
    return {(int(c // kb), int(c % kb)): int(n) for c, n in zip(codes, counts, strict=True)}


@dataclass(frozen=True, eq=False)
class TileAssignment:
    """A chosen fill for every colour of both inputs, and the tile of every overlap pair.

    Attributes
    ----------
    bank : TileBank
    views : (str, str)
        The views the two inputs are seen from: ``("A", "B")``, or ``("headon", "side")``.
    indices_a, indices_b : ndarray of shape (N, M)
        Region colour of each pixel in input A (first view) and B (second view).
    colors_a, colors_b : ndarray of shape (K, 3), uint8
        The picture colour of each region colour.
    fills_a, fills_b : tuple of Fill or None
        The fill chosen for each colour (None for a colour that does not occur).
    tiles : mapping (a, b) -> Tile
        The tile used for every occurring overlap pair (a designer may override some).
    score : float
        Total cost in ΔE units (lower is better); ``cost`` breaks it down.
    rank : int
        1 for the best candidate.
    overridden : tuple of (a, b)
        Pairs whose tile was set by hand.
    promised : mapping (a, b) -> Tile
        The tiles the assignment chose, before any override: the repainted images are what
        these show.
    """

    bank: TileBank
    views: ViewPair
    indices_a: NDArray[np.int16]
    indices_b: NDArray[np.int16]
    colors_a: NDArray[np.uint8]
    colors_b: NDArray[np.uint8]
    fills_a: tuple[Fill | None, ...]
    fills_b: tuple[Fill | None, ...]
    tiles: Mapping[tuple[int, int], Tile]
    score: float = 0.0
    cost: Mapping[str, float] = field(default_factory=dict)
    rank: int = 1
    overridden: tuple[tuple[int, int], ...] = ()
    solver: str = ""
    promised: Mapping[tuple[int, int], Tile] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.indices_a.shape != self.indices_b.shape:
            raise TileAssignmentError(
                f"the two inputs must have the same shape, got {self.indices_a.shape} and {self.indices_b.shape}"
            )
        if len(self.fills_a) != len(self.colors_a) or len(self.fills_b) != len(self.colors_b):
            raise TileAssignmentError("one fill per colour is expected")
        missing = [p for p in overlap_pairs(self.indices_a, self.indices_b) if p not in self.tiles]
        if missing:
            raise TileAssignmentError(f"no tile for overlap pair(s) {missing}")
        object.__setattr__(self, "tiles", MappingProxyType(dict(self.tiles)))
        object.__setattr__(self, "promised", MappingProxyType(dict(self.promised or self.tiles)))
        object.__setattr__(self, "cost", MappingProxyType(dict(self.cost)))

    @property
    def shape(self) -> tuple[int, int]:
        return (int(self.indices_a.shape[0]), int(self.indices_a.shape[1]))

    @property
    def yarns(self) -> tuple[Yarn, ...]:
        return self.bank.yarns

    @property
    def pairs(self) -> tuple[tuple[int, int], ...]:
        return tuple(sorted(self.tiles))

    def with_tile(self, pair: tuple[int, int], tile: Tile | str) -> TileAssignment:
        """A copy whose overlap ``pair`` uses ``tile`` (a :class:`Tile` or rows like ``"0/1/0^"``).

        The tile need not show the assigned fills (a designer may want a deliberate effect);
        :func:`~illuknit.design.tiles.compile.compile_tiles` reports where it does not.
        """
        pair = (int(pair[0]), int(pair[1]))
        if pair not in self.tiles:
            raise TileAssignmentError(
                f"overlap pair {pair} does not occur; occurring pairs: {self.pairs}"
            )
        if isinstance(tile, str):
            tile = Tile.from_rows(tile.split("/"))
        if int(tile.yarn.max()) >= len(self.bank.yarns):
            raise TileAssignmentError(
                f"override tile {tile.code()} uses yarn {int(tile.yarn.max())}, but there are {len(self.bank.yarns)} yarn(s)"
            )
        tiles = dict(self.tiles)
        tiles[pair] = tile
        over = tuple(sorted({*self.overridden, pair}))
        return replace(self, tiles=tiles, overridden=over)

    def describe(self) -> list[dict[str, Any]]:
        """One row per colour of each input: picture colour, fill, fill colour."""
        rows = []
        for side, cols, fills in (
            ("A", self.colors_a, self.fills_a),
            ("B", self.colors_b, self.fills_b),
        ):
            for k, f in enumerate(fills):
                if f is None:
                    continue
                rows.append(
                    {
                        "input": side,
                        "colour": k,
                        "image_color": hex_color(cols[k]),
                        "fill": f.label(self.yarns),
                        "fill_key": f.key(),
                        "fill_color": f.hex,
                        "kind": f.kind,
                    }
                )
        return rows

    def to_json(self) -> dict[str, Any]:
        """JSON-ready summary: fills per colour, tile per pair, score."""
        return {
            "rank": self.rank,
            "score": round(self.score, 3),
            "cost": {k: round(v, 3) for k, v in self.cost.items()},
            "views": list(self.views),
            "yarns": [{"name": y.name, "rgb": y.hex} for y in self.yarns],
            "fills": self.describe(),
            "tiles": [
                {"a": a, "b": b, "tile": t.code(), "overridden": (a, b) in self.overridden}
                for (a, b), t in sorted(self.tiles.items())
            ],
            "solver": self.solver,
        }
