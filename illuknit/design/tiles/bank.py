"""The tile bank: which tiles exist, and which pair of fills each one shows (paper section 6.1).

:func:`canonical_bank` generates the bank for any set of yarns by enumerating *every* one-unit-wide
tile up to height 4 (each unit: any yarn, flat or bump), computing its fills with ``can_see`` on
the periodic extension (vectorised: all tiles of one height are the columns of one array), dropping
tiles with a fill of more than three yarns, and keeping, for every distinct pair of fills
(fill A, fill B), the preferred tile: the shortest, then the one with the fewest colour changes,
then the fewest bumps. The result contains the solids, the 1-, 2- and 3-colour stripes, and the
stripe-one-side / solid-other-side family (e.g. ``0/1/0^``: a 0/1 stripe from A, solid 0 from B),
with every stripe proportion a tile of height <= 4 can make (1/4, 1/3, 1/2, 2/3, 3/4).

With ``split_bumps=True`` the units also include split bumps (a bump whose second course is
another yarn, ``1^0``; ``docs/split-bumps.md``) in tiles up to :data:`MAX_SPLIT_HEIGHT` units
tall. Their fills count a split bump's far course with the weight ``1 - split_share``
(:func:`~illuknit.design.tiles.tile.tile_fills`): at the default 3/4, ``1^0`` alone shows
0 3/4 + 1 1/4 from A and 1 3/4 + 0 1/4 from B.

Custom banks are JSON (format ``illuknit-tile-bank`` version 1, see ``docs/tiles.md``)::

    {"format": "illuknit-tile-bank", "version": 1,
     "extends": "canonical",                                  # optional
     "yarns": [{"name": "black", "rgb": "#1b1b1b"}, ...],     # optional when yarns are given
     "tiles": [{"name": "my stripe", "rows": ["0", "1", "0^"],
                "fills": {"A": {"0": "1/2", "1": "1/2"}, "B": {"0": "1"}}}]}

A declared fill is checked against ``can_see``; a contradiction is a :class:`TileBankError`.
"""

from __future__ import annotations

import functools
import itertools
import json
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

from illuknit.core.arguments import (
    check_bool,
    check_instance,
    check_int,
    check_number,
    check_path,
    check_views,
    got,
)
from illuknit.core.colors import parse_color
from illuknit.core.errors import TileBankError, YarnSpecError
from illuknit.core.files import atomic_write_text
from illuknit.core.pattern import Yarn, check_yarns
from illuknit.core.views import DEFAULT_SPLIT_SHARE, can_see, seen_courses
from illuknit.design.tiles.tile import (
    FILL_VIEWS,
    MAX_FILL_COLORS,
    Fill,
    FillView,
    Tile,
    fill_from_parts,
    share_fraction,
    tile_fills,
)

__all__ = [
    "BANK_FORMAT",
    "BANK_VERSION",
    "MAX_BANK_YARNS",
    "MAX_SPLIT_HEIGHT",
    "TileBank",
    "bank_from_json",
    "bank_to_json",
    "canonical_bank",
    "extend_bank",
    "load_bank",
    "save_bank",
]

BANK_FORMAT = "illuknit-tile-bank"
BANK_VERSION = 1
#: Enumeration grows as (2 * yarns) ** height; beyond this many yarns it is not worth it.
MAX_BANK_YARNS = 8
#: Tiles with split bumps are enumerated up to this height (taller ones only make fills of
#: finer proportions, 13/16 and the like, that read as noise and multiply the bank).
MAX_SPLIT_HEIGHT = 2
ViewPair = tuple[FillView, FillView]


def _tile_preference(tile: Tile) -> tuple[int, int, int, str]:
    return (tile.height, tile.color_changes(), int(tile.raised.sum()), tile.code())


@dataclass(frozen=True, eq=False)
class TileBank:
    """A set of tiles over a palette of yarns, with their fills computed.

    Parameters
    ----------
    yarns : tuple of Yarn
        The yarns that tile yarn indices refer to.
    tiles : tuple of Tile
        In order of preference: when several tiles show the same pair of fills, the earlier one
        is used by default.
    name : str
        ``"canonical"``, a file name, ...
    split_share : float
        How much of a split bump's near course its fills count (only tiles with split bumps).
    phase_locked : bool
        Every tile is laid at the piece's global row phase as it is written: the assignment does
        not shift a tile's rows to line its stripes up with its neighbours'
        (:func:`~illuknit.design.tiles.phases.align_phases`). A bank whose tiles share one
        stripe of yarns (:func:`~illuknit.design.tiles.stripes.stripe_bank`) keeps every row of
        the piece in one yarn this way.

    Attributes
    ----------
    fills : tuple of dict
        ``fills[k]`` is :func:`~illuknit.design.tiles.tile.tile_fills` of ``tiles[k]``.
    """

    yarns: tuple[Yarn, ...]
    tiles: tuple[Tile, ...]
    name: str = "custom"
    split_share: float = DEFAULT_SPLIT_SHARE
    phase_locked: bool = False
    fills: tuple[dict[FillView, Fill | None], ...] = field(init=False, repr=False)
    _index: dict[ViewPair, dict[tuple[Fill, Fill], tuple[int, ...]]] = field(
        init=False, repr=False, default_factory=dict
    )

    def __post_init__(self) -> None:
        yarns = check_yarns(self.yarns)
        check_instance(self.name, str, "name", error=TileBankError)
        check_instance(self.phase_locked, bool, "phase_locked", error=TileBankError)
        check_number(
            self.split_share, "split_share", min=0.5, max=1, min_open=True, error=TileBankError
        )
        if not isinstance(self.tiles, (tuple, list)) or not all(
            isinstance(t, Tile) for t in self.tiles
        ):
            raise TileBankError(f"`tiles` must be a sequence of Tile, got {got(self.tiles)}")
        tiles = tuple(self.tiles)
        if not tiles:
            raise TileBankError("`tiles` must hold at least one tile")
        object.__setattr__(self, "yarns", yarns)
        object.__setattr__(self, "tiles", tiles)
        object.__setattr__(
            self,
            "fills",
            tuple(tile_fills(t, yarns, split_share=self.split_share) for t in tiles),
        )

    def __len__(self) -> int:
        return len(self.tiles)

    def index(self, views: ViewPair = ("A", "B")) -> dict[tuple[Fill, Fill], tuple[int, ...]]:
        """``{(fill in views[0], fill in views[1]): tile numbers, preferred first}``.

        Tiles whose fill in either view is undefined (``"side"`` of a tile whose two side views
        differ) or has more than three yarns are left out.
        """
        for v in views:
            if v not in FILL_VIEWS:
                raise TileBankError(f"`views` must name two of {FILL_VIEWS}, got {views!r}")
        cached = self._index.get(views)
        if cached is not None:
            return cached
        out: dict[tuple[Fill, Fill], list[int]] = {}
        for k, f in enumerate(self.fills):
            f0, f1 = f[views[0]], f[views[1]]
            if f0 is None or f1 is None:
                continue
            if max(f0.n_colors, f1.n_colors) > MAX_FILL_COLORS:
                continue
            out.setdefault((f0, f1), []).append(k)
        frozen = {key: tuple(v) for key, v in out.items()}
        self._index[views] = frozen
        return frozen

    def view_fills(self, view: FillView, *, views: ViewPair = ("A", "B")) -> tuple[Fill, ...]:
        """The distinct fills the bank can show in ``view`` (one of ``views``), darkest first."""
        pos = views.index(view)
        found = {key[pos] for key in self.index(views)}
        return tuple(sorted(found, key=lambda f: (f.brightness, f.parts)))

    def tile_for(self, f0: Fill, f1: Fill, *, views: ViewPair = ("A", "B")) -> Tile | None:
        """The preferred tile showing ``f0`` in ``views[0]`` and ``f1`` in ``views[1]``, or None."""
        ks = self.index(views).get((f0, f1))
        return self.tiles[ks[0]] if ks else None

    def fills_of(self, tile: Tile) -> dict[FillView, Fill | None]:
        """Fills of any tile over this bank's yarns (the tile need not be in the bank)."""
        for k, t in enumerate(self.tiles):
            if t == tile:
                return self.fills[k]
        return tile_fills(tile, self.yarns, split_share=self.split_share)


def _check_yarns(yarns: Sequence[Yarn] | Iterable[Yarn]) -> tuple[Yarn, ...]:
    ys = tuple(yarns)
    if not ys or not all(isinstance(y, Yarn) for y in ys):
        raise YarnSpecError("`yarns` must be a non-empty sequence of Yarn")
    if len(ys) > MAX_BANK_YARNS:
        raise YarnSpecError(f"a tile bank supports at most {MAX_BANK_YARNS} yarns, got {len(ys)}")
    if len({y.rgb for y in ys}) != len(ys):
        raise YarnSpecError("`yarns` must have distinct colours")
    return ys


def _counts_to_keys(seen: np.ndarray, n_yarns: int) -> np.ndarray:
    """(h, T) seen yarns -> (T, n_yarns) counts."""
    t = seen.shape[1]
    flat = (np.arange(t)[None, :] * n_yarns + seen).ravel()
    return np.bincount(flat, minlength=t * n_yarns).reshape(t, n_yarns)


def _weighted_counts(
    yarn: np.ndarray,
    raised: np.ndarray,
    upper: np.ndarray,
    view: Any,
    h: int,
    n_yarns: int,
    share: Fraction,
) -> np.ndarray:
    """(T, n_yarns) integer weights of what each tile (a column of the 3-copy arrays) shows from
    ``view``: ``q = 2 * share.denominator`` per cell, split between a split bump's near and far
    courses as ``share`` (half and half head-on), as :func:`~illuknit.design.tiles.tile.tile_fills`
    counts them."""
    near, far = seen_courses(yarn, raised, upper, view)
    near, far = near[h : 2 * h], far[h : 2 * h]
    q = 2 * share.denominator  # a cell's weight; a split bump's near course has share * q
    split_part = q // 2 if view == "headon" else 2 * share.numerator
    part = np.where(near == far, q, split_part)
    t = near.shape[1]
    idx = np.arange(t)[None, :] * n_yarns
    out = np.bincount((idx + near).ravel(), weights=part.ravel(), minlength=t * n_yarns)
    out += np.bincount((idx + far).ravel(), weights=(q - part).ravel(), minlength=t * n_yarns)
    return np.rint(out).astype(np.int64).reshape(t, n_yarns)


def canonical_bank(
    yarns: Sequence[Yarn],
    *,
    max_height: int = 4,
    views: ViewPair = ("A", "B"),
    one_sided_stripes: bool = False,
    split_bumps: bool = False,
    split_share: float = DEFAULT_SPLIT_SHARE,
) -> TileBank:
    """Generate the canonical bank for ``yarns``.

    Parameters
    ----------
    yarns : sequence of Yarn
        1 to 8 yarns.
    max_height : int, default 4
        Tallest tile enumerated (1..6).
    views : pair of {"A", "B", "headon", "side"}, default ("A", "B")
        The fills that tiles are deduplicated by. The head-on variant uses ``("headon", "side")``.
    one_sided_stripes : bool, default False
        Keep only tiles that are solid in at least one of ``views`` (the paper's tiles).
    split_bumps : bool, default False
        Also enumerate split bumps, in tiles up to :data:`MAX_SPLIT_HEIGHT` units tall (see
        the module docstring).
    split_share : float
        The share of a split bump's near course in its fills (``RenderParams.split_share``).

    Returns
    -------
    TileBank
        One tile per distinct pair of fills: the shortest, then fewest colour changes, then
        fewest bumps.
    """
    check_yarns(yarns)
    check_int(max_height, "max_height", min=1, max=6, error=TileBankError)
    check_views(views, error=TileBankError)
    check_bool(one_sided_stripes, "one_sided_stripes")
    check_bool(split_bumps, "split_bumps")
    ys = _check_yarns(yarns)
    if not isinstance(max_height, int) or not 1 <= max_height <= 6:
        raise TileBankError(f"`max_height` must be an integer in 1..6, got {max_height!r}")
    for v in views:
        if v not in FILL_VIEWS:
            raise TileBankError(f"`views` must name two of {FILL_VIEWS}, got {views!r}")
    # Banks are immutable and cheap to share; interactive use regenerates the same one often.
    if isinstance(split_share, bool) or not isinstance(split_share, int | float):
        raise TileBankError(f"`split_share` must be a number in (0.5, 1], got {split_share!r}")
    if not 0.5 < split_share <= 1:
        raise TileBankError(f"`split_share` must lie in (0.5, 1], got {split_share!r}")
    share = share_fraction(split_share)
    return _canonical_bank(
        ys, max_height, tuple(views), bool(one_sided_stripes), bool(split_bumps), share
    )


@functools.lru_cache(maxsize=32)
def _canonical_bank(
    ys: tuple[Yarn, ...],
    max_height: int,
    views: ViewPair,
    one_sided_stripes: bool,
    split_bumps: bool = False,
    split_share: Fraction = Fraction(3, 4),
) -> TileBank:
    n_y = len(ys)
    best: dict[tuple[Any, Any], Tile] = {}
    plain = [(y, r, y) for r in (False, True) for y in range(n_y)]
    split = [(y, True, u) for y in range(n_y) for u in range(n_y) if u != y]
    for h in range(1, max_height + 1):
        units = plain + split if split_bumps and h <= MAX_SPLIT_HEIGHT else plain
        combos = np.array(list(itertools.product(range(len(units)), repeat=h)), dtype=np.int64)
        yarn = np.array([u[0] for u in units])[combos].T  # (h, T): one tile per column
        raised = np.array([u[1] for u in units])[combos].T
        upper = np.array([u[2] for u in units])[combos].T
        ext_y, ext_r = np.tile(yarn, (3, 1)), np.tile(raised, (3, 1))
        ext_u = np.tile(upper, (3, 1))
        if split_bumps:
            counts = {
                v: _weighted_counts(ext_y, ext_r, ext_u, v, h, n_y, split_share)
                for v in ("A", "B", "headon")
            }
        else:
            counts = {
                v: _counts_to_keys(np.asarray(can_see(ext_y, v, ext_r))[h : 2 * h], n_y)
                for v in ("A", "B", "headon")
            }
        counts["side"] = np.where(
            np.all(counts["A"] == counts["B"], axis=1)[:, None], counts["A"], -1
        )
        c0, c1 = counts[views[0]], counts[views[1]]
        ok = (c0 >= 0).all(axis=1) & (c1 >= 0).all(axis=1)
        ok &= ((c0 > 0).sum(axis=1) <= MAX_FILL_COLORS) & ((c1 > 0).sum(axis=1) <= MAX_FILL_COLORS)
        if one_sided_stripes:
            ok &= ((c0 > 0).sum(axis=1) == 1) | ((c1 > 0).sum(axis=1) == 1)
        # proportions, not counts, identify a fill: reduce each count vector by its gcd
        r0 = c0 // np.maximum(np.gcd.reduce(c0, axis=1), 1)[:, None]
        r1 = c1 // np.maximum(np.gcd.reduce(c1, axis=1), 1)[:, None]
        # the preference without building a Tile per candidate: colour changes, then bumps
        # (Tile.color_changes along the wale; one-unit-wide tiles have no changes across)
        changes = (yarn != upper).sum(axis=0)
        if h > 1:
            changes = changes + (upper != np.roll(yarn, -1, axis=0)).sum(axis=0)
        rank = changes * (h + 1) + raised.sum(axis=0)
        cand: dict[tuple[bytes, bytes], list[int]] = {}
        low: dict[tuple[bytes, bytes], int] = {}
        for t in np.flatnonzero(ok):
            key = (r0[t].tobytes(), r1[t].tobytes())
            if key in best:  # a shorter tile already shows this pair
                continue
            lo = low.get(key)
            if lo is None or rank[t] < lo:
                low[key], cand[key] = int(rank[t]), [int(t)]
            elif rank[t] == lo:
                cand[key].append(int(t))
        for key, ts in cand.items():
            tiles_h = [Tile(yarn[:, t], raised[:, t], upper=upper[:, t]) for t in ts]
            best[key] = min(tiles_h, key=_tile_preference)
    tiles = sorted(best.values(), key=_tile_preference)
    if split_bumps:
        return TileBank(ys, tuple(tiles), name="canonical", split_share=float(split_share))
    return TileBank(ys, tuple(tiles), name="canonical")


def extend_bank(bank: TileBank, tiles: Iterable[Tile], *, prefer_new: bool = True) -> TileBank:
    """A new bank with ``tiles`` added (first, so they are preferred, unless ``prefer_new=False``).

    Tiles already in the bank are not duplicated.
    """
    new = [t for t in tiles if isinstance(t, Tile)]
    for t in new:
        if int(t.yarn.max()) >= len(bank.yarns):
            raise TileBankError(
                f"tile {t.name!r} uses yarn {int(t.yarn.max())}, but the bank has {len(bank.yarns)} yarn(s)"
            )
    old = [t for t in bank.tiles if t not in new]
    ordered = [*new, *old] if prefer_new else [*old, *(t for t in new if t not in old)]
    return TileBank(bank.yarns, tuple(ordered), name=f"{bank.name}+custom")


# -- JSON format ------------------------------------------------------------------------------


def _parse_fill(doc: Any, where: str) -> dict[int, Fraction]:
    if not isinstance(doc, dict) or not doc:
        raise TileBankError(f"{where}: a fill must be an object {{yarn: proportion}}, got {doc!r}")
    out: dict[int, Fraction] = {}
    for k, v in doc.items():
        try:
            out[int(k, 36) if isinstance(k, str) else int(k)] = Fraction(str(v))
        except (ValueError, ZeroDivisionError):
            raise TileBankError(
                f'{where}: bad fill entry {k!r}: {v!r} (expected e.g. "0": "1/2")'
            ) from None
    if sum(out.values()) != 1 or any(q <= 0 for q in out.values()):
        raise TileBankError(f"{where}: fill proportions must be positive and sum to 1, got {doc!r}")
    return out


def bank_from_json(
    doc: Any, *, yarns: Sequence[Yarn] | None = None, source: str = "bank"
) -> TileBank:
    """Build a bank from its JSON document (see the module docstring and ``docs/tiles.md``).

    ``yarns`` replaces the file's yarns (by position) when given; one of the two is required.
    Raises :class:`TileBankError` on anything malformed, and when a declared fill disagrees with
    ``can_see``.
    """
    if not isinstance(doc, dict):
        raise TileBankError(f"{source}: a tile bank must be a JSON object")
    if doc.get("format") != BANK_FORMAT:
        raise TileBankError(
            f"{source}: not a tile bank (format is {doc.get('format')!r}, expected {BANK_FORMAT!r})"
        )
    if doc.get("version") != BANK_VERSION:
        raise TileBankError(
            f"{source}: tile bank version {doc.get('version')!r} is not supported (expected {BANK_VERSION})"
        )
    file_yarns: tuple[Yarn, ...] | None = None
    if "yarns" in doc:
        try:
            file_yarns = tuple(
                Yarn(str(y["name"]), parse_color(str(y["rgb"]))) for y in doc["yarns"]
            )
        except (KeyError, TypeError, YarnSpecError) as e:
            raise TileBankError(f"{source}: bad `yarns` entry: {e}") from None
    if yarns is not None:
        ys = _check_yarns(yarns)
        if file_yarns is not None and len(file_yarns) != len(ys):
            raise TileBankError(
                f"{source}: the bank is written for {len(file_yarns)} yarn(s) but {len(ys)} were given"
            )
    elif file_yarns is not None:
        ys = _check_yarns(file_yarns)
    else:
        raise TileBankError(f"{source}: the bank lists no `yarns`; pass the yarns to use it with")
    tiles_doc = doc.get("tiles")
    if not isinstance(tiles_doc, list):
        raise TileBankError(f"{source}: `tiles` must be a list")
    tiles: list[Tile] = []
    for k, td in enumerate(tiles_doc):
        where = f"{source}: tile {k}"
        if not isinstance(td, dict) or not isinstance(td.get("rows"), list) or not td["rows"]:
            raise TileBankError(f"{where}: expected an object with a non-empty `rows` list")
        if not all(isinstance(r, str) for r in td["rows"]):
            raise TileBankError(f'{where}: `rows` must be strings like "0" or "1^"')
        name = str(td.get("name", ""))
        where = f"{source}: tile {name or k}"
        try:
            tile = Tile.from_rows(td["rows"], name=name)
        except TileBankError as e:
            raise TileBankError(f"{where}: {e}") from None
        if int(tile.yarn.max()) >= len(ys):
            raise TileBankError(
                f"{where}: uses yarn {int(tile.yarn.max())}, but there are {len(ys)} yarn(s)"
            )
        declared = td.get("fills", {})
        if not isinstance(declared, dict):
            raise TileBankError(f"{where}: `fills` must be an object keyed by view")
        computed = tile_fills(tile, ys)
        for view, fd in declared.items():
            if view not in FILL_VIEWS:
                raise TileBankError(
                    f"{where}: unknown view {view!r} in `fills` (valid: {', '.join(FILL_VIEWS)})"
                )
            want = fill_from_parts(sorted(_parse_fill(fd, f"{where} fill {view}").items()), ys)
            got = computed[view]
            if got != want:
                shown = got.label(ys) if got is not None else "different fills from A and B"
                raise TileBankError(
                    f"{where}: declares fill {view} = {want.label(ys)}, but can_see gives {shown}"
                )
        tiles.append(tile)
    extends = doc.get("extends")
    if extends not in (None, "canonical"):
        raise TileBankError(f'{source}: `extends` must be "canonical" or absent, got {extends!r}')
    locked = doc.get("phase_locked", False)
    if not isinstance(locked, bool):
        raise TileBankError(f"{source}: `phase_locked` must be true or false, got {locked!r}")
    if extends == "canonical":
        if locked:
            raise TileBankError(
                f"{source}: a bank that extends the canonical one cannot be `phase_locked` "
                "(the canonical tiles' stripes are lined up by shifting them)"
            )
        return extend_bank(canonical_bank(ys), tiles)
    if not tiles:
        raise TileBankError(f"{source}: the bank has no tiles")
    return TileBank(ys, tuple(tiles), name=Path(source).name, phase_locked=locked)


def bank_to_json(
    bank: TileBank, *, views: Sequence[FillView] = ("A", "B", "headon")
) -> dict[str, Any]:
    """The bank as a JSON-ready dict, with each tile's computed fills declared (so an edited copy
    is checked when loaded back)."""
    tiles = []
    for t, f in zip(bank.tiles, bank.fills, strict=True):
        entry: dict[str, Any] = {"name": t.name, "rows": t.rows()}
        entry["fills"] = {v: f[v].to_json() for v in views if f[v] is not None}  # type: ignore[union-attr]
        tiles.append(entry)
    return {
        "format": BANK_FORMAT,
        "version": BANK_VERSION,
        "yarns": [{"name": y.name, "rgb": y.hex} for y in bank.yarns],
        "tiles": tiles,
        **({"phase_locked": True} if bank.phase_locked else {}),
    }


def save_bank(bank: TileBank, path: str | os.PathLike[str]) -> None:
    """Write a bank as JSON (atomically)."""
    atomic_write_text(path, json.dumps(bank_to_json(bank), indent=1) + "\n")


def load_bank(path: str | os.PathLike[str], *, yarns: Sequence[Yarn] | None = None) -> TileBank:
    """Read a bank file; raises :class:`TileBankError` when it is missing, malformed or wrong."""
    check_path(path, "path")
    if yarns is not None:
        check_yarns(yarns)
    from illuknit.core.documents import read_json_file

    doc = read_json_file(path, error=TileBankError, what="tile bank")
    return bank_from_json(doc, yarns=yarns, source=str(path))
