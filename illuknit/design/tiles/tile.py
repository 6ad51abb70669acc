"""Tiles and fills (paper section 4.2, end, and section 6.1).

A :class:`Tile` is a small block of logical units (``h`` rows by ``w`` columns) that repeats
periodically over a region. What a viewer sees of a large region tiled with it is called its
*fill* in that view. Fills are never declared by hand: :func:`tile_fills` tiles the block three
times vertically, runs :func:`illuknit.core.views.can_see` on that periodic extension and reads the
middle copy, so the first row of the block sees the last row of the copy above it exactly as it
would inside a large region.

A :class:`Fill` is the multiset of yarns seen over one period: *solid* (one yarn) or a *stripe*
of two or three yarns with their proportions (a 1/3 stripe and a 1/2 stripe of the same yarns are
different fills). Its average colour mixes the yarn colours **in linear light** with
:func:`illuknit.core.colors.mix_rgb` (light from thin stripes adds up in the eye), and its brightness is
the relative luminance of that mixture (:func:`illuknit.core.colors.luminance`). Two fills are equal
when their yarns and proportions are equal; colour and brightness are derived.

Example from the paper: the 3 x 1 tile (c1 flat, c2 flat, c1 bump) shows a c1/c2 stripe from one
side and solid c1 from the other.

A tile may hold *split bumps* (``upper``, as in :class:`~illuknit.core.pattern.LogicalPattern`),
written ``1^0`` in rows: a bump whose first course is yarn 1 and whose second is yarn 0. Which
unit each cell sees follows the extended ``can_see`` (:func:`tile_seen`); a split bump shows its
near course with weight ``split_share`` and its far course with the rest
(:func:`illuknit.core.views.seen_courses`), and the fill counts both, so the one-unit tile ``1^0``
shows 0 3/4 + 1 1/4 from A and 1 3/4 + 0 1/4 from B at the default share 3/4. A fill is what the
eye mixes, and a split bump's far course is part of the mix; without split bumps nothing changes.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.colors import hex_color, luminance, mix_rgb
from illuknit.core.errors import TileBankError
from illuknit.core.pattern import Yarn
from illuknit.core.views import DEFAULT_SPLIT_SHARE, can_see, seen_courses

__all__ = [
    "FILL_VIEWS",
    "MAX_FILL_COLORS",
    "Fill",
    "FillView",
    "Tile",
    "fill_from_seen",
    "share_fraction",
    "tile_fills",
    "tile_seen",
    "tile_weights",
]

#: The views a tile has a fill in. "side" is the fill seen from *both* angles when views A and B
#: agree (used by the head-on variant); it is undefined (None) when they differ.
FillView = Literal["A", "B", "headon", "side"]
FILL_VIEWS: tuple[FillView, ...] = ("A", "B", "headon", "side")
#: Fills with more yarns than this are not used (they read as noise, not as a colour).
MAX_FILL_COLORS = 3


@dataclass(frozen=True)
class Fill:
    """What a large region of one tile looks like from one view.

    Parameters
    ----------
    parts : tuple of (yarn index, Fraction)
        Yarns seen and their proportions, sorted by yarn index; proportions are > 0 and sum to 1.
    rgb : tuple of 3 floats
        Average sRGB colour (0..255), mixed in linear light. Not part of equality.
    brightness : float
        Relative luminance of ``rgb`` in [0, 1]. Not part of equality.
    """

    parts: tuple[tuple[int, Fraction], ...]
    rgb: tuple[float, float, float] = field(compare=False, default=(0.0, 0.0, 0.0))
    brightness: float = field(compare=False, default=0.0)

    def __post_init__(self) -> None:
        if not self.parts:
            raise TileBankError("a fill needs at least one yarn")
        idx = [p[0] for p in self.parts]
        if idx != sorted(set(idx)):
            raise TileBankError(f"fill yarns must be distinct and sorted, got {idx}")
        if any(p[1] <= 0 for p in self.parts) or sum(p[1] for p in self.parts) != 1:
            raise TileBankError(f"fill proportions must be positive and sum to 1, got {self.parts}")

    @property
    def yarn_indices(self) -> tuple[int, ...]:
        return tuple(p[0] for p in self.parts)

    @property
    def n_colors(self) -> int:
        return len(self.parts)

    @property
    def is_solid(self) -> bool:
        return len(self.parts) == 1

    @property
    def kind(self) -> str:
        """``"solid"``, ``"stripe2"`` or ``"stripe3"``."""
        return "solid" if self.is_solid else f"stripe{len(self.parts)}"

    @property
    def hex(self) -> str:
        return hex_color([round(v) for v in self.rgb])

    def proportion(self, yarn: int) -> Fraction:
        return dict(self.parts).get(yarn, Fraction(0))

    def label(self, yarns: Sequence[Yarn] | None = None) -> str:
        """Human-readable: ``"black"`` or ``"black 2/3 + white 1/3"``."""

        def name(i: int) -> str:
            return yarns[i].name if yarns is not None else f"y{i}"

        if self.is_solid:
            return name(self.parts[0][0])
        return " + ".join(f"{name(i)} {q}" for i, q in self.parts)

    def key(self) -> str:
        """A compact stable string, e.g. ``"0:2/3,1:1/3"`` (used in JSON and summaries)."""
        return ",".join(f"{i}:{q}" for i, q in self.parts)

    def to_json(self) -> dict[str, str]:
        return {str(i): str(q) for i, q in self.parts}


def fill_from_parts(parts: Sequence[tuple[int, Fraction]], yarns: Sequence[Yarn]) -> Fill:
    """A :class:`Fill` with its colour and brightness computed from ``yarns``."""
    parts = tuple(sorted((int(i), Fraction(q)) for i, q in parts))
    for i, _ in parts:
        if not 0 <= i < len(yarns):
            raise TileBankError(f"fill uses yarn {i}, but there are {len(yarns)} yarn(s)")
    cols = np.array([yarns[i].rgb for i, _ in parts], dtype=np.float64)
    w = np.array([float(q) for _, q in parts])
    rgb = mix_rgb(cols, w)
    return Fill(
        parts, rgb=(float(rgb[0]), float(rgb[1]), float(rgb[2])), brightness=float(luminance(rgb))
    )


def fill_from_seen(seen: ArrayLike, yarns: Sequence[Yarn]) -> Fill:
    """The fill made of the yarn indices in ``seen`` (any shape), in their proportions."""
    counts = Counter(int(v) for v in np.asarray(seen).ravel())
    total = sum(counts.values())
    return fill_from_parts([(i, Fraction(n, total)) for i, n in counts.items()], yarns)


def _readonly(a: ArrayLike, dtype: type) -> NDArray[Any]:
    arr: NDArray[Any] = np.array(a, dtype=dtype, copy=True)
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class Tile:
    """A periodic block of logical units.

    Parameters
    ----------
    yarn : ndarray of shape (h, w), integer
        Yarn index of each unit (into the bank's yarns).
    raised : ndarray of shape (h, w), bool
        True where the unit is a bump.
    name : str, optional
        A label for listings; generated from the contents when empty.
    upper : ndarray of shape (h, w), integer, optional
        Split bumps: the yarn of each bump's second course (equal to ``yarn`` on flat units);
        None, or equal to ``yarn`` everywhere (then stored as None), for a tile without them.

    The fills are not stored here: compute them with :func:`tile_fills` (a :class:`TileBank`
    caches them). Row 0 is the top row, as in every illuknit array.

    Examples
    --------
    >>> t = Tile.from_rows(["0", "1", "0^"])   # c1 flat, c2 flat, c1 bump
    >>> t.shape
    (3, 1)
    """

    yarn: NDArray[np.int16]
    raised: NDArray[np.bool_]
    name: str = ""
    upper: NDArray[np.int16] | None = None

    def __post_init__(self) -> None:
        y = np.asarray(self.yarn)
        r = np.asarray(self.raised)
        if y.ndim == 1:
            y = y[:, None]
        if r.ndim == 1:
            r = r[:, None]
        if y.ndim != 2 or y.size == 0:
            raise TileBankError(
                f"tile `yarn` must be a non-empty (h, w) array, got shape {y.shape}"
            )
        if r.shape != y.shape:
            raise TileBankError(
                f"tile `raised` must have the shape of `yarn` {y.shape}, got {r.shape}"
            )
        if not np.issubdtype(y.dtype, np.integer) or int(y.min()) < 0:
            raise TileBankError("tile `yarn` must hold non-negative integers")
        if r.dtype != np.bool_ and not np.all(np.isin(r, (0, 1))):
            raise TileBankError("tile `raised` must hold booleans (or 0/1)")
        object.__setattr__(self, "yarn", _readonly(y, np.int16))
        object.__setattr__(self, "raised", _readonly(r, np.bool_))
        object.__setattr__(self, "upper", self._check_upper(self.upper))
        if not isinstance(self.name, str):
            raise TileBankError(f"tile `name` must be a string, got {self.name!r}"[:120])
        if not self.name:
            object.__setattr__(self, "name", self.code())

    def _check_upper(self, upper: ArrayLike | None) -> NDArray[np.int16] | None:
        if upper is None:
            return None
        u = np.asarray(upper)
        if u.ndim == 1:
            u = u[:, None]
        if u.shape != self.yarn.shape:
            raise TileBankError(f"tile `upper` must have shape {self.yarn.shape}, got {u.shape}")
        if not np.issubdtype(u.dtype, np.integer) or int(u.min()) < 0:
            raise TileBankError("tile `upper` must hold non-negative integers")
        if (~self.raised & (u != self.yarn)).any():
            raise TileBankError("tile `upper` must equal `yarn` on flat units")
        return None if np.array_equal(u, self.yarn) else _readonly(u, np.int16)

    @classmethod
    def from_rows(cls, rows: Sequence[str], *, name: str = "") -> Tile:
        """Parse rows of tokens: a yarn digit (0-9, a-z), followed by ``^`` for a bump, and for
        a split bump by the digit of its second course's yarn (``1^0``).

        Units in a row are separated by spaces when the tile is wider than one unit:
        ``["0 1^", "1 0"]``.
        """
        yarn, raised, upper = [], [], []
        for k, row in enumerate(rows):
            toks = row.split() if " " in row.strip() else [row.strip()]
            yr, rr, ur = [], [], []
            for tok in toks:
                digit, bump, second = tok.partition("^")
                second = second or digit
                if not all(len(d) == 1 and d.isalnum() and d.isascii() for d in (digit, second)):
                    raise TileBankError(
                        f"tile row {k}: bad unit {tok!r} (expected e.g. '0', '1^' or '1^0')"
                    )
                yr.append(int(digit, 36))
                rr.append(bool(bump))
                ur.append(int(second, 36))
            yarn.append(yr)
            raised.append(rr)
            upper.append(ur)
        if not yarn or len({len(r) for r in yarn}) != 1:
            raise TileBankError(
                f"tile rows must be non-empty and of equal width, got {list(rows)!r}"
            )
        return cls(np.array(yarn), np.array(raised), name=name, upper=np.array(upper))

    @property
    def upper_yarn(self) -> NDArray[np.int16]:
        """The yarn of every unit's second course (``upper``, or ``yarn`` without split bumps)."""
        return self.yarn if self.upper is None else self.upper

    def rolled(self, shift: int) -> Tile:
        """The tile with its rows shifted cyclically by ``shift`` (``np.roll``), same name."""
        up = None if self.upper is None else np.roll(self.upper, shift, axis=0)
        return Tile(
            np.roll(self.yarn, shift, axis=0),
            np.roll(self.raised, shift, axis=0),
            name=self.name,
            upper=up,
        )

    @property
    def shape(self) -> tuple[int, int]:
        return (int(self.yarn.shape[0]), int(self.yarn.shape[1]))

    @property
    def height(self) -> int:
        return self.shape[0]

    @property
    def width(self) -> int:
        return self.shape[1]

    def rows(self) -> list[str]:
        """The inverse of :meth:`from_rows`."""
        digits = "0123456789abcdefghijklmnopqrstuvwxyz"

        def unit(y: int, r: bool, u: int) -> str:
            return digits[y] + ("^" if r else "") + (digits[u] if u != y else "")

        return [
            " ".join(unit(int(y), bool(r), int(u)) for y, r, u in zip(yr, rr, ur, strict=True))
            for yr, rr, ur in zip(self.yarn, self.raised, self.upper_yarn, strict=True)
        ]

    def code(self) -> str:
        """A compact identifier, rows joined by ``/``, e.g. ``"0/1/0^"``."""
        return "/".join(r.replace(" ", "") for r in self.rows())

    @property
    def yarns_used(self) -> tuple[int, ...]:
        return tuple(
            sorted({int(v) for v in self.yarn.ravel()} | set(self.upper_yarn.ravel().tolist()))
        )

    def color_changes(self) -> int:
        """Yarn changes between consecutive units, cyclically, along courses and along wales.

        Changes within a course cost carrier moves; changes from course to course cost carrier
        swaps. The canonical bank prefers tiles with fewer of both.
        """
        y = self.yarn
        # along a wale the courses run yarn[i] (first), upper[i] (second), then the row above
        inside = int((y != self.upper_yarn).sum())
        down = int((self.upper_yarn != np.roll(y, -1, axis=0)).sum()) if self.height > 1 else 0
        across = int((y != np.roll(y, -1, axis=1)).sum()) if self.width > 1 else 0
        return inside + down + across

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Tile):
            return NotImplemented
        return (
            np.array_equal(self.yarn, other.yarn)
            and np.array_equal(self.raised, other.raised)
            and np.array_equal(self.upper_yarn, other.upper_yarn)
        )

    def __hash__(self) -> int:
        up = b"" if self.upper is None else self.upper.tobytes()
        return hash((self.yarn.tobytes(), self.raised.tobytes(), up, self.yarn.shape))

    def __repr__(self) -> str:
        return f"Tile({self.code()!r})"


def tile_seen(tile: Tile, view: Literal["A", "B", "headon"]) -> NDArray[np.int16]:
    """ndarray of shape (h, w): the yarn seen at each unit of the tile inside a large region.

    Computed with :func:`~illuknit.core.views.can_see` on three vertical copies of the tile (the
    periodic extension) and read from the middle copy, so boundary rows see their periodic
    neighbours.
    """
    h = tile.height
    ext_y = np.tile(tile.yarn, (3, 1))
    ext_r = np.tile(tile.raised, (3, 1))
    ext_u = None if tile.upper is None else np.tile(tile.upper, (3, 1))
    return can_see(ext_y, view, ext_r, upper=ext_u)[h : 2 * h]


def share_fraction(share: float) -> Fraction:
    """A split share as the fraction fills are counted in (denominator at most 20)."""
    return Fraction(share).limit_denominator(20)


def tile_weights(
    tile: Tile, view: Literal["A", "B", "headon"], share: Fraction
) -> dict[int, Fraction]:
    """Yarn -> weight of what the tile shows from ``view`` in a large region, summing to the
    tile's height times its width: a cell counts 1 for its unit's near course, except at a split
    bump, ``share`` for the near course and ``1 - share`` for the far one (1/2 each head-on;
    :func:`illuknit.core.views.seen_courses`)."""
    h = tile.height
    ext_u = None if tile.upper is None else np.tile(tile.upper, (3, 1))
    near, far = seen_courses(np.tile(tile.yarn, (3, 1)), np.tile(tile.raised, (3, 1)), ext_u, view)
    q = Fraction(1, 2) if view == "headon" else share
    out: dict[int, Fraction] = {}
    for y, f in zip(near[h : 2 * h].ravel().tolist(), far[h : 2 * h].ravel().tolist(), strict=True):
        w = Fraction(1) if y == f else q
        out[y] = out.get(y, Fraction(0)) + w
        if w != 1:
            out[f] = out.get(f, Fraction(0)) + 1 - w
    return out


def tile_fills(
    tile: Tile, yarns: Sequence[Yarn], *, split_share: float = DEFAULT_SPLIT_SHARE
) -> dict[FillView, Fill | None]:
    """The tile's fills in every view: ``{"A": Fill, "B": Fill, "headon": Fill, "side": Fill|None}``.

    ``"side"`` is the common fill of views A and B when they are equal, else None. Split bumps
    count with ``split_share`` (see the module docstring).
    """
    if max(tile.yarns_used) >= len(yarns):
        raise TileBankError(
            f"tile {tile.code()} uses yarn {max(tile.yarns_used)}, but there are {len(yarns)} yarn(s)"
        )
    if tile.upper is None:
        out: dict[FillView, Fill | None] = {
            v: fill_from_seen(tile_seen(tile, v), yarns) for v in ("A", "B", "headon")
        }
    else:
        share = share_fraction(split_share)
        out = {}
        for v in ("A", "B", "headon"):
            weights = tile_weights(tile, v, share)
            total = sum(weights.values())
            out[v] = fill_from_parts([(y, q / total) for y, q in weights.items() if q], yarns)
    out["side"] = out["A"] if out["A"] == out["B"] else None
    return out
