"""The tile assignment model: repaint each input colour with a fill the tile bank can realise (section 6.2).

The two quantised inputs are overlaid; every pixel then belongs to an *overlap pair* ``(a, b)``
(colour ``a`` of input A over colour ``b`` of input B). We choose one fill for each colour of A
and one for each colour of B such that every occurring pair can be tiled, i.e. the bank has a
tile showing ``fill(a)`` in view A and ``fill(b)`` in view B. The head-on variant uses the same
model with the views ``("headon", "side")``.

Model (solver-neutral :class:`illuknit.solvers.model.Model`, solved by any backend: CP-SAT by default,
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

This module builds the problem and its model; :mod:`illuknit.design.tiles.assign` solves it for the
candidates. When no assignment exists, :func:`illuknit.design.tiles.explain.explain_infeasible` finds a minimal set of overlap pairs that
cannot be realised together and tries the fixes a designer has: merging two colours, allowing
stripes on both sides, adding a yarn, relaxing the brightness order.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from illuknit.core.colors import lab_from_rgb, luminance
from illuknit.design.tiles.assignment import (
    SCALE,
    AssignmentWeights,
    Regions,
    TileAssignment,
    overlap_pairs,
)
from illuknit.design.tiles.bank import TileBank, ViewPair
from illuknit.design.tiles.phases import align_phases
from illuknit.design.tiles.tile import Fill

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


class _Clauses:
    """Clauses collected per family and added as padded blocks: far faster than one call per
    clause."""

    def __init__(self) -> None:
        self.hard_by_family: dict[str, list[list[int]]] = {}
        self.soft_rows: list[list[int]] = []
        self.soft_weights: list[int] = []

    def hard(self, clause: Sequence[int], *, family: str) -> None:
        self.hard_by_family.setdefault(family, []).append(list(clause))

    def soft(self, clause: Sequence[int], weight: int) -> None:
        self.soft_rows.append(list(clause))
        self.soft_weights.append(int(weight))

    def add_to(self, m: Any) -> None:
        for family, rows in self.hard_by_family.items():
            m.add_hard_block(_pad(rows), family=family)
        if self.soft_rows:
            m.add_soft_block(_pad(self.soft_rows), np.array(self.soft_weights, dtype=np.int64))


def _encode(prob: _Problem):
    """Build the Model; returns (model, decode) with decode(solution) -> (choice_a, choice_b)."""
    from illuknit.solvers.model import Model

    m = Model("tile-assignment")
    cl = _Clauses()
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
            cl.hard([-xa[a, f], *(xb[b, int(g)] for g in ok)], family=f"overlap pair ({a},{b})")
    _brightness_order(cl, prob, xa, xb)
    # objective: closeness + stripes
    for a in prob.cols_a:
        for f in range(len(fa)):
            w = int(prob.close_a[a, f] + prob.stripe_a[f])
            if w > 0:
                cl.soft([-xa[a, f]], w)
    for b in prob.cols_b:
        for g in range(len(fb)):
            w = int(prob.close_b[b, g] + prob.stripe_b[g])
            if w > 0:
                cl.soft([-xb[b, g]], w)
    _yarns_per_course(cl, m, prob, xa, xb)
    cl.add_to(m)

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


def _brightness_order(
    cl: _Clauses, prob: _Problem, xa: dict[tuple[int, int], int], xb: dict[tuple[int, int], int]
) -> None:
    """Each picture's brightness order: kept (hard), or its breaches penalised (soft)."""
    for side, cols, colors, fills, x in (
        ("A", prob.cols_a, prob.ra.colors, prob.fa, xa),
        ("B", prob.cols_b, prob.rb.colors, prob.fb, xb),
    ):
        bright = np.array([f.brightness for f in fills])
        if prob.brightness == "hard":
            inc, eq = _order_pairs(cols, colors)
            for lo, hi in inc:
                for f in range(len(fills)):
                    up = np.flatnonzero(bright > bright[f] + _EPS)
                    cl.hard(
                        [-x[lo, f], *(x[hi, int(g)] for g in up)], family=f"brightness order {side}"
                    )
            for p, q in eq:
                for f in range(len(fills)):
                    cl.hard([-x[p, f], -x[q, f]], family=f"distinct fills {side}")
        else:
            w = max(1, round(prob.weights.order_penalty * SCALE))
            for lo, hi in _all_order_pairs(cols, colors):
                for f in range(len(fills)):
                    for dim in np.flatnonzero(bright <= bright[f] + _EPS).tolist():
                        cl.soft([-x[lo, f], -x[hi, dim]], w)


def _yarns_per_course(
    cl: _Clauses,
    m: Any,
    prob: _Problem,
    xa: dict[tuple[int, int], int],
    xb: dict[tuple[int, int], int],
) -> None:
    """Few yarns per course: a ``use`` variable per row class and yarn, each use penalised."""
    fa, fb = prob.fa, prob.fb
    for r, (ka, kb, w) in enumerate(prob.row_classes):
        if w <= 0:
            continue
        for y in range(len(prob.bank.yarns)):
            u = m.var(("use", r, y))
            cl.soft([-u], w)
            for a in ka:
                for f in range(len(fa)):
                    if y in fa[f].yarn_indices:
                        cl.hard([-xa[a, f], u], family="yarns per course")
            for b in kb:
                for g in range(len(fb)):
                    if y in fb[g].yarn_indices:
                        cl.hard([-xb[b, g], u], family="yarns per course")


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
    parts = {
        "closeness": close,
        "stripes": stripe,
        "yarns_per_course": yarns,
        "brightness_order": order,
    }
    return parts


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
    if not prob.bank.phase_locked:  # a shared stripe stays in the piece's one phase
        tiles = align_phases(tiles, prob.pairs, prob.views)
    cost = {k: v / SCALE for k, v in parts.items()}
    return TileAssignment(
        prob.bank, prob.views, prob.ra.indices, prob.rb.indices, prob.ra.colors, prob.rb.colors,
        fills_a, fills_b, tiles, sum(cost.values()), cost, rank, (), solver,
    )  # fmt: skip
