"""The objective of the knit-aware model (b) and its exact block updates, for the block descent.

:func:`pattern_cost` evaluates a pattern; :func:`update_wales` and :func:`update_rows`
re-optimise every other wale or unit row exactly while the rest stays fixed (each a chain solved
by a shortest path), and :func:`descend` sweeps them until nothing improves. Why a wale and a
row are chains given their neighbours is told in :mod:`illuknit.design.models.backends.descent`, which searches
with these moves.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from illuknit.design.models.illusion_problem import (
    IllusionProblem,
    pass_events,
    raised_cost,
    row_passes,
)

__all__ = ["descend", "pattern_cost", "update_rows", "update_units", "update_wales"]

_INF = np.int64(1) << np.int64(40)


# -- the objective --------------------------------------------------------------------------


def _unit_costs(problem: IllusionProblem) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """(bump cost per unit (N, M), pinned-yarn penalty (N, M, K)) of ``problem``."""
    n, m = problem.shape
    k = problem.n_yarns
    bump = raised_cost(n, m, problem.transfer_weight)
    pin = np.zeros((n, m, k), dtype=np.int64)
    if problem.pinned is not None:
        p = problem.pinned.astype(np.int64)
        pin[(p[:, :, None] >= 0) & (np.arange(k)[None, None, :] != p[:, :, None])] = _INF
    return bump, pin


def pattern_cost(
    problem: IllusionProblem, yarn: NDArray[np.integer], raised: NDArray[np.bool_]
) -> int:
    """Objective of model (b) (or (a)/(c)) for a (yarn, raised) grid, without the hard caps.

    Equals ``build_model(problem).evaluate(values)`` for every pattern that satisfies the hard
    constraints (a pinned unit in another yarn costs ``2**40``).
    """
    c = np.asarray(yarn, dtype=np.int64)
    r = np.asarray(raised, dtype=bool)
    a = problem.target_a
    b = problem.target_b
    va = c.copy()
    va[1:] = np.where(r[:-1], c[:-1], c[1:])
    vb = c.copy()
    vb[:-1] = np.where(r[1:], c[1:], c[:-1])
    bump, pin = _unit_costs(problem)
    n, m = c.shape
    ii, jj = np.indices((n, m))
    cost = problem.view_weight * (int((va != a).sum()) + int((vb != b).sum()))
    cost += int(bump[r].sum()) + int(pin[ii, jj, c].sum())
    cost += problem.color_weight * int((c[:, 1:] != c[:, :-1]).sum())
    if problem.pass_weight:
        passes = row_passes(c, r, problem.n_yarns, problem.weights.float_gap)
        cost += problem.pass_weight * int(passes.sum())
    return int(cost)


# -- exact block updates --------------------------------------------------------------------


def _chain_argmin(
    unary: NDArray[np.int64],
    pair: NDArray[np.int64] | None,
    pair_fn: Callable[[int], NDArray[np.int64]] | None = None,
) -> NDArray[np.int64]:
    """Min-cost state sequence of L independent chains.

    Parameters
    ----------
    unary : ndarray of shape (L, T, S)
    pair : ndarray broadcastable to (L, S', S), the same for every step, or None with
        ``pair_fn(t) -> (L, S', S)`` the cost between steps t-1 and t.

    Returns
    -------
    ndarray of shape (L, T), int64 — the states.
    """
    lc, tc, sc = unary.shape
    back = np.zeros((tc, lc, sc), dtype=np.int64)
    v = unary[:, 0].copy()
    for t in range(1, tc):
        p = pair_fn(t) if pair_fn is not None else pair
        assert p is not None
        tot = v[:, :, None] + p  # (L, S', S)
        back[t] = tot.argmin(axis=1)
        v = tot.min(axis=1) + unary[:, t]
    states = np.empty((lc, tc), dtype=np.int64)
    states[:, tc - 1] = v.argmin(axis=1)
    rows = np.arange(lc)
    for t in range(tc - 1, 0, -1):
        states[:, t - 1] = back[t][rows, states[:, t]]
    return states


def _state_parts(k: int) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    s = np.arange(2 * k)
    return s // 2, (s % 2).astype(bool)


def update_wales(
    problem: IllusionProblem,
    yarn: NDArray[np.int64],
    raised: NDArray[np.bool_],
    cols: NDArray[np.int64],
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """Re-optimise the wales ``cols`` exactly, all other wales fixed.

    ``cols`` must hold no two neighbouring wales (e.g. all even ones): their updates are then
    independent. Returns new (yarn, raised) arrays; the objective never increases.
    """
    n, m = problem.shape
    k = problem.n_yarns
    cs, rs = _state_parts(k)
    wv = problem.view_weight
    wc = problem.color_weight
    a = problem.target_a.astype(np.int64)[:, cols]  # (N, L)
    b = problem.target_b.astype(np.int64)[:, cols]
    bump, pin = _unit_costs(problem)
    u = np.zeros((len(cols), n, 2 * k), dtype=np.int64)
    u += bump[:, cols].T[:, :, None] * rs[None, None, :]
    u += pin[:, cols][:, :, cs].transpose(1, 0, 2)
    u[:, 0] += wv * (cs[None, :] != a[0][:, None])
    u[:, n - 1] += wv * (cs[None, :] != b[n - 1][:, None])
    if wc:
        for side in (-1, 1):
            nb = cols + side
            ok = (nb >= 0) & (nb < m)
            if ok.any():
                other = yarn[:, nb[ok]].T  # (L', N)
                u[ok] += wc * (cs[None, None, :] != other[:, :, None])
    if problem.pass_weight:
        u += _row_terms_outside(problem, yarn, raised, cols)
    seen_a = np.where(rs[:, None], cs[:, None], cs[None, :])  # (S', S)
    seen_b = np.where(rs[None, :], cs[None, :], cs[:, None])

    def pair(t: int) -> NDArray[np.int64]:
        return wv * (
            (seen_a[None] != a[t][:, None, None]).astype(np.int64)
            + (seen_b[None] != b[t - 1][:, None, None])
        )

    st = _chain_argmin(u, None, pair)  # (L, N)
    y = yarn.copy()
    r = raised.copy()
    y[:, cols] = (st // 2).T
    r[:, cols] = (st % 2).astype(bool).T
    return y, r


def _row_terms_outside(
    problem: IllusionProblem, yarn: NDArray[np.int64], raised: NDArray[np.bool_], cols: Any
) -> NDArray[np.int64]:
    """Unary costs (L, N, S) of the pass terms for the wales ``cols`` (a yarn new to the row, a
    first bump and the segments it turns into bump-row segments), judged against the rest of
    each row (the other updated wales left out). Not exact when
    several updated wales are a row's only users of a yarn; :func:`descend` keeps an update
    only if the whole objective does not increase. Extra carriers are left to that check."""
    n, m = problem.shape
    k = problem.n_yarns
    cs, rs = _state_parts(k)
    p = problem.pass_weight
    rest = np.ones(m, dtype=bool)
    rest[cols] = False
    c = np.asarray(yarn)[:, rest]
    used = np.stack([(c == y).any(axis=1) for y in range(k)], axis=1)  # (N, K)
    bumped: NDArray[np.bool_] = np.asarray(np.asarray(raised)[:, rest].any(axis=1), dtype=bool)
    _, _, extra = pass_events(yarn, raised, k, problem.weights.float_gap)
    segments = used.sum(axis=1) + extra  # (N,), the rest's segments (extras of the whole row)
    new_yarn = ~used[:, cs]  # (N, S)
    new_bump = rs[None, :] & ~bumped[:, None]
    u = (2 * p) * new_yarn + p * (new_yarn & (bumped[:, None] | rs[None, :]))
    u = u + p * new_bump * (1 + segments[:, None])
    return np.broadcast_to(u[None], (len(cols), n, 2 * k))


def _row_unary(
    problem: IllusionProblem,
    c_all: NDArray[np.int64],
    r_all: NDArray[np.bool_],
    rows: NDArray[np.int64],
) -> NDArray[np.int64]:
    """Unary costs (L, M, S) of every unit of ``rows`` in each state, the other rows fixed: the
    view cells that see the unit, its bump's bed changes and its pin."""
    n = problem.shape[0]
    k = problem.n_yarns
    cs, rs = _state_parts(k)
    wv = problem.view_weight
    a = problem.target_a.astype(np.int64)
    b = problem.target_b.astype(np.int64)
    bump, pin = _unit_costs(problem)
    u = bump[rows][:, :, None] * rs[None, None, :] + pin[rows][:, :, cs]  # (L, M, S)
    c = cs[None, None, :]
    r = rs[None, None, :]
    up = rows - 1
    dn = rows + 1
    has_up = up >= 0
    has_dn = dn < n
    upc = np.clip(up, 0, n - 1)
    dnc = np.clip(dn, 0, n - 1)
    cu, ru = c_all[upc][:, :, None], r_all[upc][:, :, None]  # row above (L, M, 1)
    cd, rd = c_all[dnc][:, :, None], r_all[dnc][:, :, None]  # row below
    ai, bi = a[rows][:, :, None], b[rows][:, :, None]
    bu = b[upc][:, :, None]  # view B of the row above
    ad = a[dnc][:, :, None]  # view A of the row below
    hu = has_up[:, None, None]
    hd = has_dn[:, None, None]
    mis = np.zeros(u.shape, dtype=np.int64)
    # view A at this row: row 0 sees itself; else the row above if raised, else this unit
    mis += np.where(hu, np.where(ru, cu != ai, c != ai), c != ai)
    # view A at the row below sees this unit if raised, else the row below's own colour
    mis += hd & np.where(r, c != ad, cd != ad)
    # view B at this row: the last row sees itself; else the row below if raised, else this unit
    mis += np.where(hd, np.where(rd, cd != bi, c != bi), c != bi)
    # view B at the row above sees this unit if raised, else the row above's own colour
    mis += hu & np.where(r, c != bu, cu != bu)
    u = u + wv * mis
    return u


def update_rows(
    problem: IllusionProblem,
    yarn: NDArray[np.int64],
    raised: NDArray[np.bool_],
    rows: NDArray[np.int64],
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """Re-optimise the unit rows ``rows`` exactly, all other rows fixed.

    ``rows`` must hold no two neighbouring rows. Returns new (yarn, raised); the objective never
    increases.
    """
    k = problem.n_yarns
    cs, _ = _state_parts(k)
    wc = problem.color_weight
    c_all = np.asarray(yarn, dtype=np.int64)
    r_all = np.asarray(raised, dtype=bool)
    u = _row_unary(problem, c_all, r_all, rows)
    pair = (wc * (cs[:, None] != cs[None, :])).astype(np.int64)[None]  # (1, S', S)
    st = _best_row_states(problem, u, pair) if problem.pass_weight else _chain_argmin(u, pair)
    y = c_all.copy()
    rr = r_all.copy()
    y[rows] = st // 2
    rr[rows] = (st % 2).astype(bool)
    return y, rr


def _best_row_states(
    problem: IllusionProblem, u: NDArray[np.int64], pair: NDArray[np.int64]
) -> NDArray[np.int64]:
    """Row chains with the yarn-used and bump-row terms, exactly: one chain per nonempty set of
    allowed yarns and per bumps allowed or not, each charged its pass terms; the cheapest wins
    per row. (Extra carriers are left to :func:`descend`'s check.)"""
    k = problem.n_yarns
    cs, rs = _state_parts(k)
    p = problem.pass_weight
    best_cost: NDArray[np.int64] | None = None
    best: NDArray[np.int64] | None = None
    for mask in range(1, 2**k):
        allowed = np.array([(mask >> y) & 1 for y in range(k)], dtype=bool)
        for bumps in (False, True):
            ok = allowed[cs] & (rs <= bumps)
            uu = np.where(ok[None, None, :], u, _INF)
            st = _chain_argmin(uu, pair)
            cost = np.take_along_axis(uu, st[:, :, None], axis=2)[:, :, 0].sum(axis=1)
            cost = cost + pair[0][st[:, :-1], st[:, 1:]].sum(axis=1)
            used = int(allowed.sum())
            cost = cost + p * (2 * used + int(bumps) * (used + 1))
            if best_cost is None or best is None:
                best_cost, best = cost, st
            else:
                better = cost < best_cost
                best_cost = np.where(better, cost, best_cost)
                best[better] = st[better]
    assert best is not None
    return best


def _neighbours(c: NDArray[np.int64], y: int) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Per unit of the rows ``c`` (L, M): column of the previous and of the next unit in yarn
    ``y`` (-1 and M where there is none), the unit itself left out."""
    m = c.shape[1]
    cols = np.arange(m)
    prev = np.maximum.accumulate(np.where(c == y, cols, -1), axis=1)
    nxt = np.minimum.accumulate(np.where(c == y, cols, m)[:, ::-1], axis=1)[:, ::-1]
    before = np.full_like(prev, -1)
    before[:, 1:] = prev[:, :-1]
    after = np.full_like(nxt, m)
    after[:, :-1] = nxt[:, 1:]
    return before, after


def _segments_added(
    p: NDArray[np.int64], q: NDArray[np.int64], m: int, g: int
) -> NDArray[np.int64]:
    """Carrier segments a yarn gains when column j joins it, with ``p``/``q`` its previous and
    next column in the yarn (-1 / m: none): the gaps on either side of j replace the gap p..q.
    """
    j = np.arange(m)
    has_p, has_q = p >= 0, q < m
    left = (j - p - 1 > g) & has_p
    right = (q - j - 1 > g) & has_q
    joined = (q - p - 1 > g) & has_p & has_q
    lone = ~has_p & ~has_q
    return np.where(lone, 1, left.astype(np.int64) + right - joined)


def update_units(
    problem: IllusionProblem,
    yarn: NDArray[np.int64],
    raised: NDArray[np.bool_],
    rows: NDArray[np.int64],
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """In each of ``rows``, the single unit change (any column, any state) that lowers the
    objective most, exactly -- extra carriers included, which the row and wale blocks leave
    to :func:`descend`'s check -- applied when it lowers it at all.

    ``rows`` must hold no two neighbouring rows (a row's units share view cells only with the
    rows next to it). Returns new (yarn, raised); the objective never increases.
    """
    m = problem.shape[1]
    k = problem.n_yarns
    cs, rs = _state_parts(k)
    c_all = np.asarray(yarn, dtype=np.int64)
    r_all = np.asarray(raised, dtype=bool)
    if len(rows) == 0:
        return c_all.copy(), r_all.copy()
    c, r = c_all[rows], r_all[rows]  # (L, M)
    u = _row_unary(problem, c_all, r_all, rows)  # (L, M, S)
    now = c * 2 + r
    delta = u - np.take_along_axis(u, now[:, :, None], axis=2)
    wc = problem.color_weight
    if wc and m > 1:
        for side in (-1, 1):
            nb = np.full_like(c, -1)
            if side < 0:
                nb[:, 1:] = c[:, :-1]
            else:
                nb[:, :-1] = c[:, 1:]
            ok = (nb >= 0)[:, :, None]
            delta += (
                wc
                * ok
                * ((cs[None, None, :] != nb[:, :, None]).astype(np.int64) - (c != nb)[:, :, None])
            )
    p = problem.pass_weight
    if p:
        g = problem.weights.float_gap
        gained = np.zeros((len(rows), m, k), dtype=np.int64)
        for y in range(k):
            gained[:, :, y] = _segments_added(*_neighbours(c, y), m, g)
        _, _, extra = pass_events(c, r, k, g)
        seg = np.stack([(c == y).any(axis=1) for y in range(k)], axis=1).sum(axis=1) + extra
        own = np.take_along_axis(gained, c[:, :, None], axis=2)  # the unit's yarn loses it
        seg_new = seg[:, None, None] + np.where(
            cs[None, None, :] == c[:, :, None], 0, gained[:, :, cs] - own
        )  # (L, M, S)
        others = (r.sum(axis=1)[:, None] - r) > 0  # (L, M): a bump elsewhere in the row
        bump_new = others[:, :, None] | rs[None, None, :]
        bump_old = np.asarray(r.any(axis=1), dtype=bool)[:, None, None]
        passes_new = 2 * seg_new + bump_new * (seg_new + 1)
        passes_old = 2 * seg[:, None, None] + bump_old * (seg[:, None, None] + 1)
        delta += p * (passes_new - passes_old)
    flat = delta.reshape(len(rows), -1)
    best = flat.argmin(axis=1)
    go = flat[np.arange(len(rows)), best] < 0
    y2, r2 = c_all.copy(), r_all.copy()
    j, st = best // (2 * k), best % (2 * k)
    y2[rows[go], j[go]] = cs[st[go]]
    r2[rows[go], j[go]] = rs[st[go]]
    return y2, r2


def descend(
    problem: IllusionProblem,
    yarn: NDArray[np.integer],
    raised: NDArray[np.bool_],
    *,
    max_sweeps: int = 200,
    deadline: float | None = None,
) -> tuple[NDArray[np.int64], NDArray[np.bool_], int, int]:
    """Block coordinate descent from (yarn, raised) to a local optimum.

    One sweep updates even wales, odd wales, even rows, odd rows (each exactly), then makes the
    best single-unit change of each even and each odd row (:func:`update_units`). Stops when a
    sweep improves nothing, after ``max_sweeps``, or at ``deadline`` (``time.perf_counter()``).

    Returns
    -------
    yarn : ndarray of shape (N, M), int64
    raised : ndarray of shape (N, M), bool
    cost : int
    sweeps : int
    """
    n, m = problem.shape
    y = np.asarray(yarn, dtype=np.int64).copy()
    r = np.asarray(raised, dtype=bool).copy()
    cost = pattern_cost(problem, y, r)
    blocks = [
        ("wales", np.arange(0, m, 2)),
        ("wales", np.arange(1, m, 2)),
        ("rows", np.arange(0, n, 2)),
        ("rows", np.arange(1, n, 2)),
        ("units", np.arange(0, n, 2)),
        ("units", np.arange(1, n, 2)),
    ]
    sweeps = 0
    for sweeps in range(1, max_sweeps + 1):  # noqa: B007 - the count is returned
        before = cost
        for kind, idx in blocks:
            if idx.size == 0:
                continue
            fn = {"wales": update_wales, "rows": update_rows, "units": update_units}[kind]
            y2, r2 = fn(problem, y, r, idx)
            c2 = pattern_cost(problem, y2, r2)
            if c2 <= cost:  # always true for an exact block update; kept as a guard
                y, r, cost = y2, r2, c2
        if cost >= before or (deadline is not None and time.perf_counter() >= deadline):
            break
    return y, r, cost, sweeps
