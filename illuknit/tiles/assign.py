"""Tile assignment: repaint each input colour with a fill the tile bank can realise (section 6.2).

The two quantised inputs are overlaid; every pixel then belongs to an *overlap pair* ``(a, b)``
(colour ``a`` of input A over colour ``b`` of input B). We choose one fill for each colour of A
and one for each colour of B such that every occurring pair can be tiled, i.e. the bank has a
tile showing ``fill(a)`` in view A and ``fill(b)`` in view B. The head-on variant uses the same
model with the views ``("headon", "side")``.

Model (solver-neutral :class:`illuknit.model.Model`, solved by any backend: CP-SAT by default,
MaxSAT (``rc2``) selectable)
---------------------------------------------------------------------------------------------
Variables
    ``("fa", a, f)``: colour ``a`` of input A gets fill number ``f`` of the bank's view-A fills;
    ``("fb", b, g)`` likewise for input B; ``("use", r, y)``: yarn ``y`` is seen somewhere in the
    rows of *row class* ``r`` (rows with the same set of colours present are one class).
Hard constraints
    * exactly one fill per occurring colour (``family "one fill per colour"``);
    * realisability: for every occurring pair ``(a, b)`` and fill ``f``:
      ``fa[a,f] -> OR { fb[b,g] : the bank has a tile for (f, g) }``;
    * brightness order (unless ``brightness="soft"``): for consecutive colours ``a < a'`` in
      order of luminance of their picture colours, ``fa[a,f] -> OR { fa[a',f'] : f' brighter }``;
      colours of equal luminance get different fills;
    * ``fa[a,f] -> use[r,y]`` for each yarn ``y`` of ``f`` and each row class ``r`` holding ``a``.
Objective (minimised; integer weights are tenths of CIELAB ΔE units)
    * closeness: ΔE between a colour and the average colour (linear-light mix) of its fill;
    * ``stripe_penalty`` ΔE per extra yarn in a fill (solids preferred over stripes);
    * ``yarn_penalty`` ΔE per yarn seen in a course, averaged over the courses (few yarns per
      course means few carrier changes);
    * with ``brightness="soft"``: ``order_penalty`` ΔE per pair of colours out of order.
Candidates
    The optimum is found, a blocking clause forbids exactly that choice of fills, and the model is
    solved again, ``candidates`` times: the result is the top-N distinct assignments by score.

When no assignment exists, :func:`explain_infeasible` finds a minimal set of overlap pairs that
cannot be realised together and tries the fixes a designer has: merging two colours, allowing
stripes on both sides, adding a yarn, relaxing the brightness order.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.colors import hex_color, lab_from_rgb, luminance
from illuknit.errors import ImageInputError, TileAssignmentError
from illuknit.pattern import Yarn
from illuknit.tiles.bank import TileBank, ViewPair, canonical_bank
from illuknit.tiles.tile import Fill, Tile, tile_seen

SeenView = Literal["A", "B", "headon"]

__all__ = [
    "AssignmentWeights",
    "TileAssignment",
    "assign_tiles",
    "brute_force_assignments",
    "explain_infeasible",
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
    """Accept a :class:`~illuknit.images.QuantisedImage` (``.indices``, ``.colors``) or a pair
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

    def fill_key(self) -> tuple[tuple[Fill | None, ...], tuple[Fill | None, ...]]:
        return (self.fills_a, self.fills_b)

    def with_tile(self, pair: tuple[int, int], tile: Tile | str) -> TileAssignment:
        """A copy whose overlap ``pair`` uses ``tile`` (a :class:`Tile` or rows like ``"0/1/0^"``).

        The tile need not show the assigned fills (a designer may want a deliberate effect);
        :func:`~illuknit.tiles.compile.compile_tiles` reports where it does not.
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


# -- the problem, independent of any solver ---------------------------------------------------


@dataclass
class _Problem:
    """Everything the model, the brute force and the explanation share."""

    bank: TileBank
    views: ViewPair
    ra: Regions
    rb: Regions
    pairs: dict[tuple[int, int], int]
    cols_a: list[int]  # occurring colours
    cols_b: list[int]
    fa: tuple[Fill, ...]  # candidate fills per view
    fb: tuple[Fill, ...]
    compat: NDArray[np.bool_]  # (len(fa), len(fb))
    close_a: NDArray[np.int64]  # (Ka, len(fa)) integer cost
    close_b: NDArray[np.int64]
    stripe_a: NDArray[np.int64]  # (len(fa),)
    stripe_b: NDArray[np.int64]
    row_classes: list[tuple[frozenset[int], frozenset[int], int]]  # (A colours, B colours, weight)
    brightness: str
    weights: AssignmentWeights


def _lum(colors: NDArray[np.uint8]) -> NDArray[np.float64]:
    return np.asarray(luminance(np.asarray(colors, dtype=np.float64)))


def _build_problem(
    ra: Regions,
    rb: Regions,
    bank: TileBank,
    views: ViewPair,
    brightness: str,
    weights: AssignmentWeights,
) -> _Problem:
    pairs = overlap_pairs(ra.indices, rb.indices)
    cols_a = sorted({a for a, _ in pairs})
    cols_b = sorted({b for _, b in pairs})
    index = bank.index(views)
    fa = bank.view_fills(views[0], views=views)
    fb = bank.view_fills(views[1], views=views)
    pos_a = {f: i for i, f in enumerate(fa)}
    pos_b = {f: i for i, f in enumerate(fb)}
    compat = np.zeros((len(fa), len(fb)), dtype=bool)
    for f, g in index:
        compat[pos_a[f], pos_b[g]] = True

    def closeness(colors: NDArray[np.uint8], fills: Sequence[Fill]) -> NDArray[np.int64]:
        lab_c = lab_from_rgb(np.asarray(colors, dtype=np.float64))
        lab_f = lab_from_rgb(np.array([f.rgb for f in fills]))
        d = np.sqrt(((lab_c[:, None, :] - lab_f[None, :, :]) ** 2).sum(-1))
        return np.round(d * SCALE).astype(np.int64)

    def stripes(fills: Sequence[Fill]) -> NDArray[np.int64]:
        return np.array(
            [round((f.n_colors - 1) * weights.stripe_penalty * SCALE) for f in fills],
            dtype=np.int64,
        )

    n = ra.indices.shape[0]
    classes: dict[tuple[frozenset[int], frozenset[int]], int] = {}
    for r in range(n):
        key = (
            frozenset(np.unique(ra.indices[r]).tolist()),
            frozenset(np.unique(rb.indices[r]).tolist()),
        )
        classes[key] = classes.get(key, 0) + 1
    row_classes = [
        (ka, kb, round(weights.yarn_penalty * SCALE * cnt / n)) for (ka, kb), cnt in classes.items()
    ]
    return _Problem(
        bank, views, ra, rb, pairs, cols_a, cols_b, fa, fb, compat,
        closeness(ra.colors, fa), closeness(rb.colors, fb), stripes(fa), stripes(fb),
        row_classes, brightness, weights,
    )  # fmt: skip


def _order_pairs(
    cols: list[int], colors: NDArray[np.uint8]
) -> tuple[list[tuple[int, int]], list[tuple[int, int]]]:
    """(consecutive strictly-increasing pairs, equal-luminance pairs) among occurring colours."""
    lum = _lum(colors)
    srt = sorted(cols, key=lambda c: (lum[c], c))
    inc, eq = [], []
    for lo, hi in itertools.pairwise(srt):
        if lum[hi] - lum[lo] > 1e-9:
            inc.append((lo, hi))
        else:
            eq.append((lo, hi))
    return inc, eq


def _all_order_pairs(cols: list[int], colors: NDArray[np.uint8]) -> list[tuple[int, int]]:
    lum = _lum(colors)
    return [(p, q) for p in cols for q in cols if lum[q] - lum[p] > 1e-9]


_EPS = 1e-9


def _pad(rows: list[list[int]]) -> NDArray[np.int64]:
    width = max(len(r) for r in rows)
    out = np.zeros((len(rows), width), dtype=np.int64)
    for k, r in enumerate(rows):
        out[k, : len(r)] = r
    return out


def _encode(prob: _Problem):
    """Build the Model; returns (model, decode) with decode(solution) -> (choice_a, choice_b)."""
    from illuknit.model import Model

    m = Model("tile-assignment")
    # Clauses are collected and added as padded blocks: far faster than one call per clause.
    hard_by_family: dict[str, list[list[int]]] = {}
    soft_rows: list[list[int]] = []
    soft_weights: list[int] = []

    def hard(clause: Sequence[int], *, family: str) -> None:
        hard_by_family.setdefault(family, []).append(list(clause))

    def soft(clause: Sequence[int], weight: int) -> None:
        soft_rows.append(list(clause))
        soft_weights.append(int(weight))

    fa, fb = prob.fa, prob.fb
    xa = {(a, f): m.var(("fa", a, f)) for a in prob.cols_a for f in range(len(fa))}
    xb = {(b, g): m.var(("fb", b, g)) for b in prob.cols_b for g in range(len(fb))}
    for a in prob.cols_a:
        m.add_exactly_one([xa[a, f] for f in range(len(fa))], family="one fill per colour")
    for b in prob.cols_b:
        m.add_exactly_one([xb[b, g] for g in range(len(fb))], family="one fill per colour")
    # realisability of every occurring overlap pair
    for a, b in prob.pairs:
        for f in range(len(fa)):
            ok = np.flatnonzero(prob.compat[f])
            hard([-xa[a, f], *(xb[b, int(g)] for g in ok)], family=f"overlap pair ({a},{b})")
    # brightness order
    for side, cols, colors, fills, x in (
        ("A", prob.cols_a, prob.ra.colors, fa, xa),
        ("B", prob.cols_b, prob.rb.colors, fb, xb),
    ):
        bright = np.array([f.brightness for f in fills])
        if prob.brightness == "hard":
            inc, eq = _order_pairs(cols, colors)
            for lo, hi in inc:
                for f in range(len(fills)):
                    up = np.flatnonzero(bright > bright[f] + _EPS)
                    hard(
                        [-x[lo, f], *(x[hi, int(g)] for g in up)], family=f"brightness order {side}"
                    )
            for p, q in eq:
                for f in range(len(fills)):
                    hard([-x[p, f], -x[q, f]], family=f"distinct fills {side}")
        else:
            w = max(1, round(prob.weights.order_penalty * SCALE))
            for lo, hi in _all_order_pairs(cols, colors):
                for f in range(len(fills)):
                    for dim in np.flatnonzero(bright <= bright[f] + _EPS).tolist():
                        soft([-x[lo, f], -x[hi, dim]], w)
    # objective: closeness + stripes
    for a in prob.cols_a:
        for f in range(len(fa)):
            w = int(prob.close_a[a, f] + prob.stripe_a[f])
            if w > 0:
                soft([-xa[a, f]], w)
    for b in prob.cols_b:
        for g in range(len(fb)):
            w = int(prob.close_b[b, g] + prob.stripe_b[g])
            if w > 0:
                soft([-xb[b, g]], w)
    # few yarns per course
    for r, (ka, kb, w) in enumerate(prob.row_classes):
        if w <= 0:
            continue
        for y in range(len(prob.bank.yarns)):
            u = m.var(("use", r, y))
            soft([-u], w)
            for a in ka:
                for f in range(len(fa)):
                    if y in fa[f].yarn_indices:
                        hard([-xa[a, f], u], family="yarns per course")
            for b in kb:
                for g in range(len(fb)):
                    if y in fb[g].yarn_indices:
                        hard([-xb[b, g], u], family="yarns per course")
    for family, rows in hard_by_family.items():
        m.add_hard_block(_pad(rows), family=family)
    if soft_rows:
        m.add_soft_block(_pad(soft_rows), np.array(soft_weights, dtype=np.int64))

    def block(ca: Mapping[int, int], cb: Mapping[int, int]) -> None:
        """Forbid exactly this choice of fills (the next solve finds the next candidate)."""
        m.add_hard(
            [*(-xa[a, f] for a, f in ca.items()), *(-xb[b, g] for b, g in cb.items())],
            family="distinct candidates",
        )

    def decode(sol: Any) -> tuple[dict[int, int], dict[int, int]]:
        v = sol.values
        ca = {a: next(f for f in range(len(fa)) if v[xa[a, f]]) for a in prob.cols_a}
        cb = {b: next(g for g in range(len(fb)) if v[xb[b, g]]) for b in prob.cols_b}
        return ca, cb

    return m, decode, block


def _cost(prob: _Problem, ca: Mapping[int, int], cb: Mapping[int, int]) -> dict[str, int] | None:
    """Integer cost parts of a choice, or None when it breaks a hard constraint."""
    for a, b in prob.pairs:
        if not prob.compat[ca[a], cb[b]]:
            return None
    order = 0
    for cols, colors, fills, c in (
        (prob.cols_a, prob.ra.colors, prob.fa, ca),
        (prob.cols_b, prob.rb.colors, prob.fb, cb),
    ):
        if prob.brightness == "hard":
            inc, eq = _order_pairs(cols, colors)
            if any(fills[c[hi]].brightness <= fills[c[lo]].brightness + _EPS for lo, hi in inc):
                return None
            if any(c[p] == c[q] for p, q in eq):
                return None
        else:
            bad = sum(
                fills[c[hi]].brightness <= fills[c[lo]].brightness + _EPS
                for lo, hi in _all_order_pairs(cols, colors)
            )
            order += bad * max(1, round(prob.weights.order_penalty * SCALE))
    close = sum(int(prob.close_a[a, f]) for a, f in ca.items()) + sum(
        int(prob.close_b[b, g]) for b, g in cb.items()
    )
    stripe = sum(int(prob.stripe_a[f]) for f in ca.values()) + sum(
        int(prob.stripe_b[g]) for g in cb.values()
    )
    yarns = 0
    for ka, kb, w in prob.row_classes:
        used: set[int] = set()
        for a in ka:
            used.update(prob.fa[ca[a]].yarn_indices)
        for b in kb:
            used.update(prob.fb[cb[b]].yarn_indices)
        yarns += w * len(used)
    return {
        "closeness": close,
        "stripes": stripe,
        "yarns_per_course": yarns,
        "brightness_order": order,
    }


def _make_assignment(
    prob: _Problem, ca: Mapping[int, int], cb: Mapping[int, int], rank: int, solver: str
) -> TileAssignment:
    parts = _cost(prob, ca, cb)
    assert parts is not None  # the solver returned a feasible choice
    fills_a = tuple(prob.fa[ca[a]] if a in ca else None for a in range(len(prob.ra.colors)))
    fills_b = tuple(prob.fb[cb[b]] if b in cb else None for b in range(len(prob.rb.colors)))
    tiles = {}
    for a, b in prob.pairs:
        t = prob.bank.tile_for(prob.fa[ca[a]], prob.fb[cb[b]], views=prob.views)
        assert t is not None
        tiles[a, b] = t
    tiles = align_phases(tiles, prob.pairs, prob.views)
    cost = {k: v / SCALE for k, v in parts.items()}
    return TileAssignment(
        prob.bank, prob.views, prob.ra.indices, prob.rb.indices, prob.ra.colors, prob.rb.colors,
        fills_a, fills_b, tiles, sum(cost.values()), cost, rank, (), solver,
    )  # fmt: skip


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
            rt = (
                t
                if s == 0
                else Tile(np.roll(t.yarn, s, axis=0), np.roll(t.raised, s, axis=0), name=t.name)
            )
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


def _check_inputs(ra: Regions, rb: Regions, bank: TileBank, views: ViewPair) -> None:
    if ra.indices.shape != rb.indices.shape:
        raise ImageInputError(
            f"the two inputs must have the same size in units, got {ra.indices.shape[1]} x {ra.indices.shape[0]} "
            f"and {rb.indices.shape[1]} x {rb.indices.shape[0]} (resize one, or use --resize)"
        )
    for name, r, view in (("A", ra, views[0]), ("B", rb, views[1])):
        used = np.unique(r.indices)
        levels = {round(f.brightness, 9) for f in bank.view_fills(view, views=views)}
        if len(used) > len(levels):
            raise TileAssignmentError(
                f"input {name} has {len(used)} colours, but the tile bank shows only {len(levels)} "
                f"distinct brightness level(s) from view {view}: use fewer colours (--colors) or more yarns"
            )


def assign_tiles(
    qa: Any,
    qb: Any,
    *,
    bank: TileBank | None = None,
    yarns: Sequence[Yarn] | None = None,
    candidates: int = 5,
    brightness: Literal["hard", "soft"] = "hard",
    solver: str = "cpsat",
    time_limit: float | None = 10.0,
    weights: AssignmentWeights | None = None,
    views: ViewPair = ("A", "B"),
    explain: bool = True,
) -> list[TileAssignment]:
    """The top ``candidates`` tile assignments for a pair of quantised inputs, best first.

    Parameters
    ----------
    qa, qb : QuantisedImage or (indices (N, M), colors (K, 3))
        The inputs seen from ``views[0]`` and ``views[1]`` (A from above, B from below).
    bank : TileBank, optional
        Defaults to :func:`canonical_bank` of ``yarns`` (or of ``qa.yarns`` + ``qb.yarns``).
    candidates : int
        How many distinct assignments to return (fewer when fewer exist).
    brightness : {"hard", "soft"}
        Keep each input's brightness order strictly, or only prefer to.
    solver : str
        A backend name of :mod:`illuknit.solvers` ("cpsat", "rc2", ...).
    time_limit : float, optional
        Seconds per solve.
    weights : AssignmentWeights, optional
    views : pair of str
        ``("A", "B")`` for double view; ``("headon", "side")`` for the head-on variant.

    Returns
    -------
    list of TileAssignment
        Ranked by score (rank 1 first).

    Raises
    ------
    ImageInputError
        The inputs have different sizes.
    TileAssignmentError
        An input has more colours than the bank can serve, or no assignment exists (the message
        explains which overlap pairs cannot be realised and what would fix it).
    """
    ra, rb = regions_of(qa, name="qa"), regions_of(qb, name="qb")
    if bank is None:
        bank = canonical_bank(_default_yarns(qa, qb, yarns), views=views)
    if not isinstance(candidates, int) or candidates < 1:
        raise TileAssignmentError(f"`candidates` must be a positive integer, got {candidates!r}")
    if brightness not in ("hard", "soft"):
        raise TileAssignmentError(f"`brightness` must be 'hard' or 'soft', got {brightness!r}")
    _check_inputs(ra, rb, bank, views)
    prob = _build_problem(ra, rb, bank, views, brightness, weights or AssignmentWeights())
    return _solve_candidates(prob, candidates, solver, time_limit, explain=explain)


def _yarns_of(*inputs: Any) -> tuple[Yarn, ...]:
    """The yarns the inputs carry (``.yarns`` of a QuantisedImage), each colour once, in order."""
    found: list[Yarn] = []
    for q in inputs:
        for y in getattr(q, "yarns", ()):
            if all(y.rgb != z.rgb for z in found):
                found.append(y)
    return tuple(found)


def _default_yarns(qa: Any, qb: Any, yarns: Sequence[Yarn] | None) -> tuple[Yarn, ...]:
    if yarns is not None:
        return tuple(yarns)
    found = _yarns_of(qa, qb)
    if not found:
        raise TileAssignmentError("pass `bank` or `yarns` (the inputs carry no yarns)")
    return found


def _solve_candidates(
    prob: _Problem, candidates: int, solver: str, time_limit: float | None, *, explain: bool
) -> list[TileAssignment]:
    from illuknit.solvers import Status, solve

    out: list[TileAssignment] = []
    blocked: list[tuple[dict[int, int], dict[int, int]]] = []
    m, decode, block = _encode(prob)
    for rank in range(1, candidates + 1):
        if blocked:
            block(*blocked[-1])
        sol = solve(m, solver=solver, time_limit=time_limit)
        if sol.status is Status.INFEASIBLE or not sol.has_values:
            break
        if sol.status is Status.ERROR:  # pragma: no cover - backend failure
            from illuknit.errors import SolverError

            raise SolverError(f"solver {solver!r} failed: {sol.stats.get('message', '')}")
        ca, cb = decode(sol)
        blocked.append((ca, cb))
        out.append(_make_assignment(prob, ca, cb, rank, sol.backend or solver))
    if not out:
        msg = "no tile assignment exists for these inputs"
        if explain:
            msg = explain_infeasible(prob, solver=solver)
        raise TileAssignmentError(msg)
    # Solves are exact, but a timed-out solve may come back out of order: rank by score.
    out.sort(key=lambda t: t.score)
    return [replace(t, rank=k + 1) for k, t in enumerate(out)]


# -- when nothing fits -------------------------------------------------------------------------


def _restricted(prob: _Problem, pairs: Sequence[tuple[int, int]]) -> _Problem:
    keep = dict.fromkeys(pairs, 1)
    cols_a = sorted({a for a, _ in keep})
    cols_b = sorted({b for _, b in keep})
    return _Problem(**{**prob.__dict__, "pairs": keep, "cols_a": cols_a, "cols_b": cols_b})


def _name(side: str, k: int, colors: NDArray[np.uint8]) -> str:
    return f"{side}{k} ({hex_color(colors[k])})"


def explain_infeasible(prob: _Problem, *, solver: str = "cpsat") -> str:
    """Why no assignment exists, and which changes would make one exist (one paragraph).

    Finds a minimal set of overlap pairs that cannot be realised together (deletion-based core
    over the pairs), then tries: relaxing the brightness order, merging two colours of one input,
    allowing stripes on both sides (canonical bank), and adding a yarn of a picture colour.
    """
    lines = []
    if prob.brightness == "hard":
        soft = _Problem(**{**prob.__dict__, "brightness": "soft"})
        if _feasible_real(soft, solver):
            lines.append(
                "the fills that fit cannot keep the brightness order of the inputs; "
                "allow it to change (--soft-brightness / brightness='soft') or merge colours"
            )
    core = list(prob.pairs)
    if not _feasible_real(_restricted(prob, core), solver):
        for pair in list(core):
            kept = [q for q in core if q != pair]
            if kept and not _feasible_real(_restricted(prob, kept), solver):
                core = kept
    names = ", ".join(
        f"{_name('A', a, prob.ra.colors)} over {_name('B', b, prob.rb.colors)}" for a, b in core
    )
    lines.insert(
        0, f"no tile assignment exists: the overlap pairs {names} cannot all be realised together"
    )
    fixes = []
    # merging two colours of one input
    for side in ("A", "B"):
        r = prob.ra if side == "A" else prob.rb
        cols = prob.cols_a if side == "A" else prob.cols_b
        for p, q in itertools.combinations(cols, 2):
            idx = np.where(r.indices == q, p, r.indices).astype(np.int16)
            merged = Regions(idx, r.colors)
            ra, rb = (merged, prob.rb) if side == "A" else (prob.ra, merged)
            trial = _build_problem(ra, rb, prob.bank, prob.views, prob.brightness, prob.weights)
            if _feasible_real(trial, solver):
                fixes.append(
                    f"merge colours {_name(side, p, r.colors)} and {_name(side, q, r.colors)} of input {side}"
                )
    # stripes on both sides
    full = canonical_bank(prob.bank.yarns, views=prob.views)
    if len(full) > len(prob.bank) or prob.bank.name != "canonical":
        trial = _build_problem(prob.ra, prob.rb, full, prob.views, prob.brightness, prob.weights)
        if _feasible_real(trial, solver):
            fixes.append("allow stripes on both sides (use the full canonical bank)")
    # one more yarn
    # (only for a canonical bank: a custom bank says nothing about tiles with another yarn)
    if len(prob.bank.yarns) < 8 and prob.bank.name == "canonical":
        tried: set[tuple[int, int, int]] = set()
        ylab = lab_from_rgb(np.array([y.rgb for y in prob.bank.yarns], dtype=np.float64))
        for side, k, colors in [("A", a, prob.ra.colors) for a, _ in core] + [
            ("B", b, prob.rb.colors) for _, b in core
        ]:
            rgb = tuple(int(v) for v in colors[k])
            lab = lab_from_rgb(np.array([rgb], dtype=np.float64))[0]
            if rgb in tried or np.sqrt(((ylab - lab) ** 2).sum(axis=1)).min() < 10:
                continue  # as good as a yarn we already have
            tried.add(rgb)  # type: ignore[arg-type]
            more = canonical_bank(
                (*prob.bank.yarns, Yarn("extra", (rgb[0], rgb[1], rgb[2]))), views=prob.views
            )
            trial = _build_problem(
                prob.ra, prob.rb, more, prob.views, prob.brightness, prob.weights
            )
            if _feasible_real(trial, solver):
                fixes.append(f"add a yarn of colour {hex_color(rgb)} (like {side}{k})")
                break
    text = "; ".join(lines)
    if fixes:
        text += ". Would fix it: " + "; or ".join(fixes)
    else:
        text += ". Try another yarn set, fewer colours, or editing the inputs so these regions do not overlap"
    return text


def _feasible_real(prob: _Problem, solver: str) -> bool:
    """Whether the hard constraints of ``prob`` can hold (objective ignored)."""
    from illuknit.solvers import solve

    if _check_levels(prob) is False:
        return False
    m, _, _ = _encode(_Problem(**{**prob.__dict__, "row_classes": []}))
    # soft clauses do not matter for feasibility, but the encoder adds them; they are cheap
    return solve(m, solver=solver, time_limit=10.0).has_values


def _check_levels(prob: _Problem) -> bool:
    if prob.brightness != "hard":
        return True
    la = {round(f.brightness, 9) for f in prob.fa}
    lb = {round(f.brightness, 9) for f in prob.fb}
    return len(prob.cols_a) <= len(la) and len(prob.cols_b) <= len(lb)


# -- brute force (tests, tiny problems) --------------------------------------------------------


def brute_force_assignments(
    qa: Any,
    qb: Any,
    *,
    bank: TileBank,
    brightness: Literal["hard", "soft"] = "hard",
    weights: AssignmentWeights | None = None,
    views: ViewPair = ("A", "B"),
) -> list[tuple[float, tuple[Fill | None, ...], tuple[Fill | None, ...]]]:
    """Every feasible choice of fills with its score, best first, by plain enumeration.

    Exponential: for checking the model on a handful of colours and fills only.
    """
    ra, rb = regions_of(qa, name="qa"), regions_of(qb, name="qb")
    prob = _build_problem(ra, rb, bank, views, brightness, weights or AssignmentWeights())
    out = []
    for choice_a in itertools.product(range(len(prob.fa)), repeat=len(prob.cols_a)):
        ca = dict(zip(prob.cols_a, choice_a, strict=True))
        for choice_b in itertools.product(range(len(prob.fb)), repeat=len(prob.cols_b)):
            cb = dict(zip(prob.cols_b, choice_b, strict=True))
            parts = _cost(prob, ca, cb)
            if parts is None:
                continue
            fa = tuple(prob.fa[ca[a]] if a in ca else None for a in range(len(ra.colors)))
            fb = tuple(prob.fb[cb[b]] if b in cb else None for b in range(len(rb.colors)))
            out.append((sum(parts.values()) / SCALE, fa, fb))
    out.sort(key=lambda t: t[0])
    return out
