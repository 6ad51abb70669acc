"""Exact dynamic programming for the per-wale illusion models.

With only the section 4.2 constraints (models (a) logical and (c) single-view, and the knit-aware
model (b) without colour-change terms), every wale (column) is an independent chain: view A at
row i depends on units i-1 and i, view B at row i on units i and i+1, and the transfer cost of a
bump on the unit alone. So the optimum is a shortest path per wale over the 2K states
``(yarn, raised)`` of each unit:

    V[0][s]  = U[0][s]
    V[i][s]  = U[i][s] + min_{s'} (V[i-1][s'] + P[i][s', s])

where ``P[i][(c', r'), (c, r)]`` counts view A at row i (sees ``c'`` if ``r'`` else ``c``) and view
B at row i-1 (sees ``c`` if ``r`` else ``c'``) against their targets, and ``U`` holds the boundary
rows (A at row 0, B at row N-1), the bump cost and pinned units. Cost O(N (2K)^2) per wale,
vectorised across all wales with numpy (a loop over the N rows only).

**Split bumps** (``problem.split_bumps``, :mod:`illuknit.core.views`): a unit's state gains the
yarn ``u`` of its second course, which view A sees where view B sees the first course's ``c``; a
flat unit has ``u == c``, so the states are the 2K plain ones plus the ``K (K - 1)`` split bumps
``(c, raised, u != c)``, and in ``P`` view A reads ``u'`` (raised) or ``u``. Still exact per wale,
O(N (K + K^2)^2).

Ties prefer flat units and lower yarn indices. The backend reads ``model.problem`` (an
:class:`illuknit.design.models.illusion_models.IllusionProblem`) and refuses any other model.

**The single-view model (c)** ties every unit row to one yarn ``c_i``, which couples the wales,
but only through the row colours. Given the row colours, each raised bit ``R[i, j]`` decides two
view cells and nothing else — view A at row i+1 (``c_i`` if raised, else ``c_{i+1}``) and view B
at row i-1 (``c_i`` if raised, else ``c_{i-1}``) — so it is chosen per unit in closed form, and
the cost of row i is a function ``g_i(c_{i-1}, c_i, c_{i+1})`` (O(M K^3) per row). The optimum is
then a shortest path over consecutive pairs of row colours:

    F_0[c_0, c_1]     = g_0(., c_0, c_1)
    F_i[c_i, c_{i+1}] = min_{c_{i-1}} F_{i-1}[c_{i-1}, c_i] + g_i(c_{i-1}, c_i, c_{i+1})

with the last row closing it; O(N K^3) on top of computing ``g``. With ``alternate_rows``,
pairs of equal colours are forbidden. Exact, like the per-wale DP.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from illuknit.design.models.illusion_problem import (
    HANDS_SOLVERS,
    IllusionProblem,
    problem_of,
    raised_cost,
)
from illuknit.solvers.base import (
    BackendBase,
    BackendKind,
    ProgressCallback,
    ProgressEvent,
    Solution,
    Status,
)

if TYPE_CHECKING:
    from illuknit.solvers.model import Model

__all__ = ["DPBackend", "hint_values", "solve_dp", "solve_dp_split"]

_INF = np.int64(1) << np.int64(40)


def solve_dp(problem: IllusionProblem) -> tuple[NDArray[np.int16], NDArray[np.bool_], int]:
    """Optimal (yarn, raised, cost) of the per-wale part of ``problem``.

    Colour-change terms of the knit-aware model are ignored (they couple wales); for problems
    with ``problem.per_wale`` the result is the exact optimum of the whole model. For the
    single-view model (``problem.rows_tied``) it is the exact optimum with one yarn per row
    (:func:`solve_single_rows`); infeasible pins or alternation give a cost >= 2**40.

    Returns
    -------
    yarn : ndarray of shape (N, M), int16
    raised : ndarray of shape (N, M), bool
    cost : int
        Objective value (weighted mismatched view cells + bump costs).
    """
    if problem.rows_tied:
        return solve_single_rows(problem)
    yarn, raised, _, cost = solve_dp_split(problem)
    return yarn, raised, cost


def _states(k: int, split: bool) -> tuple[NDArray[np.int64], NDArray[np.bool_], NDArray[np.int64]]:
    """(first-course yarn, raised, second-course yarn) of every unit state: ``2 c + r`` for the
    plain states (so ties prefer flat units and lower yarns, as without split bumps), then the
    split bumps ``(c, True, u)`` with ``u != c``."""
    s = np.arange(2 * k)
    cs, rs, us = s // 2, (s % 2).astype(bool), s // 2
    if split:
        c2, u2 = np.nonzero(~np.eye(k, dtype=bool))
        cs = np.concatenate([cs, c2])
        rs = np.concatenate([rs, np.ones(c2.size, dtype=bool)])
        us = np.concatenate([us, u2])
    return cs, rs, us


def solve_dp_split(
    problem: IllusionProblem,
) -> tuple[NDArray[np.int16], NDArray[np.bool_], NDArray[np.int16], int]:
    """Optimal (yarn, raised, upper, cost) of the per-wale part of ``problem`` (not the
    single-view model); ``upper`` is the second course's yarn (equal to ``yarn`` unless
    ``problem.split_bumps`` let a bump split)."""
    a = problem.target_a.astype(np.int64)
    b = problem.target_b.astype(np.int64)
    n, m = problem.shape
    k = problem.n_yarns
    wv = problem.view_weight
    cs, rs, us = _states(k, problem.split_bumps)
    s_count = cs.size

    # unary costs (N, M, S)
    u = np.zeros((n, m, s_count), dtype=np.int64)
    u[0] += wv * (us[None, :] != a[0][:, None])
    u[n - 1] += wv * (cs[None, :] != b[n - 1][:, None])
    wt = problem.transfer_weight
    if wt:
        u += raised_cost(n, m, wt)[:, :, None] * rs[None, None, :]
    if problem.pinned is not None:
        p = problem.pinned.astype(np.int64)
        bad = (p[:, :, None] >= 0) & (cs[None, None, :] != p[:, :, None])
        u[bad] += _INF

    seen_a = np.where(rs[:, None], us[:, None], us[None, :])  # (S', S)
    seen_b = np.where(rs[None, :], cs[None, :], cs[:, None])  # (S', S)
    back = np.zeros((n, m, s_count), dtype=np.int8 if s_count < 128 else np.int16)
    v = u[0].copy()
    cols = np.arange(m)
    for i in range(1, n):
        pair = wv * (
            (seen_a[None] != a[i][:, None, None]).astype(np.int64)
            + (seen_b[None] != b[i - 1][:, None, None])
        )
        tot = v[:, :, None] + pair  # (M, S', S)
        arg = tot.argmin(axis=1)
        back[i] = arg
        v = np.take_along_axis(tot, arg[:, None, :], axis=1)[:, 0, :] + u[i]
    states = np.empty((n, m), dtype=np.int64)
    states[n - 1] = v.argmin(axis=1)
    cost = int(v[cols, states[n - 1]].sum())
    for i in range(n - 1, 0, -1):
        states[i - 1] = back[i][cols, states[i]]
    return cs[states].astype(np.int16), rs[states], us[states].astype(np.int16), cost


def solve_single_rows(
    problem: IllusionProblem,
) -> tuple[NDArray[np.int16], NDArray[np.bool_], int]:
    """Exact optimum with one yarn per unit row (see the module docstring).

    Returns (yarn (N, M) int16, raised (N, M) bool, cost); cost >= 2**40 when no row colouring
    satisfies the pins and the alternation.
    """
    a = problem.target_a.astype(np.int64)
    b = problem.target_b.astype(np.int64)
    n, m = problem.shape
    k = problem.n_yarns
    wv = problem.view_weight
    wt = problem.transfer_weight
    bump = raised_cost(n, m, wt)
    col = np.arange(k)
    # g[i, p, c, q]: cost of row i in colour c between rows of colours p (above) and q (below);
    # keep[i, p, c, q, j]: whether unit (i, j) is raised in that case
    g = np.zeros((n, k, k, k), dtype=np.int64)
    keep = np.zeros((n, k, k, k, m), dtype=bool)
    for i in range(n):
        up = np.zeros((k, m), dtype=np.int64)  # view B at row i-1, by the colour it sees
        dn = np.zeros((k, m), dtype=np.int64)  # view A at row i+1, by the colour it sees
        if i > 0:
            up = (col[:, None] != b[i - 1][None, :]).astype(np.int64)
        if i < n - 1:
            dn = (col[:, None] != a[i + 1][None, :]).astype(np.int64)
        # raised: both cells see this row's colour c; flat: they see p (above) and q (below)
        on = wv * (up + dn) + bump[i][None, :]  # (c, M)
        off = wv * (up[:, None, :] + dn[None, :, :])  # (p, q, M)
        raise_it = on[None, :, None, :] < off[:, None, :, :]  # (p, c, q, M); ties: flat
        g[i] = np.where(raise_it, on[None, :, None, :], off[:, None, :, :]).sum(axis=-1)
        keep[i] = raise_it
        own = np.zeros(k, dtype=np.int64)
        if i == 0:
            own += wv * (col[:, None] != a[0][None, :]).sum(axis=1)
        if i == n - 1:
            own += wv * (col[:, None] != b[n - 1][None, :]).sum(axis=1)
        if problem.pinned is not None:
            pr = problem.pinned[i].astype(np.int64)
            pr = pr[pr >= 0]
            own += _INF * (pr[None, :] != col[:, None]).any(axis=1)
        g[i] += own[None, :, None]
    same = _INF * (col[:, None] == col[None, :]) if problem.alternate_rows else 0
    rows = np.empty(n, dtype=np.int64)
    if n == 1:
        rows[0] = int(g[0, 0, :, 0].argmin())
        cost = int(g[0, 0, rows[0], 0])
    else:
        f = g[0, 0] + same  # [c_0, c_1]
        back = np.zeros((n, k, k), dtype=np.int64)
        for i in range(1, n - 1):
            tot = f[:, :, None] + g[i]  # [c_{i-1}, c_i, c_{i+1}]
            back[i] = tot.argmin(axis=0)
            f = tot.min(axis=0) + same
        last = f + g[n - 1][:, :, 0]  # [c_{n-2}, c_{n-1}]
        p_, c_ = np.unravel_index(int(last.argmin()), last.shape)
        cost = int(last[p_, c_])
        rows[n - 2], rows[n - 1] = p_, c_
        for i in range(n - 2, 0, -1):
            rows[i - 1] = back[i][rows[i], rows[i + 1]]
    cost = min(cost, int(_INF) * n)  # keep infeasible costs from overflowing anything later
    yarn = np.repeat(rows[:, None], m, axis=1)
    raised = np.zeros((n, m), dtype=bool)
    for i in range(n):
        p = rows[i - 1] if i > 0 else 0
        q = rows[i + 1] if i < n - 1 else 0
        raised[i] = keep[i, p, rows[i], q]
    return yarn.astype(np.int16), raised, cost


def hint_values(problem: IllusionProblem, model: Model) -> NDArray[np.bool_]:
    """A full assignment of ``model`` from the DP optimum of its per-wale part (a warm start)."""
    if problem.split_bumps:
        yarn, raised, upper, _ = solve_dp_split(problem)
        return values_from_pattern(model, yarn, raised, upper)
    yarn, raised, _ = solve_dp(problem)
    return values_from_pattern(model, yarn, raised)


def values_from_pattern(
    model: Model,
    yarn: NDArray[np.integer],
    raised: NDArray[np.bool_],
    upper: NDArray[np.integer] | None = None,
) -> NDArray[np.bool_]:
    """Bool values by variable id for a (yarn, raised) grid, including ``change`` variables
    and, for a model with split bumps, ``upper`` (the second courses' yarns, default ``yarn``)."""
    vals = np.zeros(model.pool.top + 1, dtype=bool)
    x = model.pool.block_ids("yarn")
    n, m, _ = x.shape
    ii, jj = np.indices((n, m))
    vals[x[ii, jj, yarn.astype(np.int64)]] = True
    vals[model.pool.block_ids("raised")] = raised
    if "upper" in model.pool.blocks:
        up = yarn if upper is None else upper
        vals[model.pool.block_ids("upper")[ii, jj, np.asarray(up, dtype=np.int64)]] = True
    if "change" in model.pool.blocks:
        vals[model.pool.block_ids("change")] = yarn[:, 1:] != yarn[:, :-1]
    if "stranded" in model.pool.blocks:  # made for hands: how each row is worked
        _hand_values(vals, model, np.asarray(yarn, dtype=np.int64))
    if "yarn used" in model.pool.blocks:
        k = x.shape[2]
        onehot = yarn[:, :, None] == np.arange(k)[None, None, :]
        vals[model.pool.block_ids("yarn used")] = onehot.any(axis=1)
        bump_row: NDArray[np.bool_] = np.asarray(np.asarray(raised, dtype=bool).any(axis=1))
        vals[model.pool.block_ids("bump row")] = bump_row
        vals[model.pool.block_ids("bump segment")] = onehot.any(axis=1) & bump_row[:, None]
        if "yarn so far" in model.pool.blocks:
            so_far = np.cumsum(onehot, axis=1) > 0
            vals[model.pool.block_ids("yarn so far")] = so_far
            ex = model.pool.block_ids("extra carrier")
            g = m - ex.shape[1] - 2
            window = np.zeros_like(onehot)
            for d in range(1, g + 2):
                window[:, d:] |= onehot[:, :-d]
            start = onehot & ~window
            extra = start[:, g + 2 :] & so_far[:, : m - g - 2]
            vals[ex] = extra
            vals[model.pool.block_ids("bump extra")] = extra & bump_row[:, None, None]
    return vals


def _hand_values(vals: NDArray[np.bool_], model: Model, yarn: NDArray[np.int64]) -> None:
    """The made-for-hands auxiliaries of a yarn grid: a row is worked stranded when it has
    more colour blocks than intarsia allows; which yarns a row uses, and right of each unit."""
    from illuknit.design.hand_cost import MAX_HAND_BLOCKS

    k = model.pool.block_ids("yarn").shape[2]
    onehot = yarn[:, :, None] == np.arange(k)[None, None, :]
    changes = (yarn[:, 1:] != yarn[:, :-1]).sum(axis=1)
    vals[model.pool.block_ids("stranded")] = changes > MAX_HAND_BLOCKS - 1
    if "row yarn" in model.pool.blocks:
        vals[model.pool.block_ids("row yarn")] = onehot.any(axis=1)
    if "yarn after" in model.pool.blocks:
        vals[model.pool.block_ids("yarn after")] = np.cumsum(onehot[:, ::-1], axis=1)[:, ::-1] > 0


class DPBackend(BackendBase):
    """Exact dynamic programming: per wale, or over row colours for the single-view model."""

    name = "dp"
    kind = BackendKind.DOMAIN
    #: the DP is what the warm starts run
    accepts_warm_start = False

    def why_not(self, model: Model) -> str | None:
        p = model.problem
        if not isinstance(p, IllusionProblem):
            return "the DP solves only illusion models built by illuknit.design.models.illusion_models.build_model"
        if p.for_hands:
            return HANDS_SOLVERS
        if p.per_wale or p.rows_tied:
            return None
        return (
            "machine-pass and colour-change terms couple the wales; use --solver descent, cpsat "
            "or rc2 for the knit-aware model (or set machine_pass=0, color_change=0 and no cap)"
        )

    def solve(
        self,
        model: Model,
        *,
        time_limit: float | None = None,
        seed: int = 0,
        progress: ProgressCallback | None = None,
    ) -> Solution:
        # The DP takes well under a second at the largest supported sizes; time_limit is moot.
        t0 = time.perf_counter()
        problem = problem_of(model)
        upper = None
        if problem.split_bumps:
            yarn, raised, upper, cost = solve_dp_split(problem)
        else:
            yarn, raised, cost = solve_dp(problem)
        if cost >= _INF:
            wall = time.perf_counter() - t0
            return Solution(Status.INFEASIBLE, None, None, None, wall, {}, self.name, model.pool)
        vals = values_from_pattern(model, yarn, raised, upper)
        ok, evaluated = model.evaluate(vals)
        wall = time.perf_counter() - t0
        if not ok or evaluated != cost:
            stats = {
                "message": f"DP cost {cost} disagrees with the model ({evaluated}, feasible={ok})"
            }
            return Solution(Status.ERROR, vals, evaluated, None, wall, stats, self.name, model.pool)
        if progress:
            progress(ProgressEvent(wall, cost, cost))
        return Solution(Status.OPTIMAL, vals, cost, float(cost), wall, {}, self.name, model.pool)
