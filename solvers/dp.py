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

Ties prefer flat units and lower yarn indices. The backend reads ``model.problem`` (an
:class:`illuknit.illusion_models.IllusionProblem`) and refuses any other model.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from illuknit.solvers.base import ProgressCallback, ProgressEvent, Solution, Status

if TYPE_CHECKING:
    from illuknit.illusion_models import IllusionProblem
    from illuknit.model import Model

__all__ = ["DPBackend", "hint_values", "solve_dp"]

_INF = np.int64(1) << np.int64(40)


def solve_dp(problem: IllusionProblem) -> tuple[NDArray[np.int16], NDArray[np.bool_], int]:
    """Optimal (yarn, raised, cost) of the per-wale part of ``problem``.

    Colour-change terms of the knit-aware model are ignored (they couple wales); for problems
    with ``problem.per_wale`` the result is the exact optimum of the whole model.

    Returns
    -------
    yarn : ndarray of shape (N, M), int16
    raised : ndarray of shape (N, M), bool
    cost : int
        Objective value (weighted mismatched view cells + bump costs).
    """
    from illuknit.illusion_models import _raised_cost

    a = problem.target_a.astype(np.int64)
    b = problem.target_b.astype(np.int64)
    n, m = problem.shape
    k = problem.n_yarns
    wv = problem.view_weight
    s_count = 2 * k
    cs = np.arange(s_count) // 2
    rs = (np.arange(s_count) % 2).astype(bool)

    # unary costs (N, M, S)
    u = np.zeros((n, m, s_count), dtype=np.int64)
    u[0] += wv * (cs[None, :] != a[0][:, None])
    u[n - 1] += wv * (cs[None, :] != b[n - 1][:, None])
    wt = problem.transfer_weight
    if wt:
        u += _raised_cost(n, m, wt)[:, :, None] * rs[None, None, :]
    if problem.pinned is not None:
        p = problem.pinned.astype(np.int64)
        bad = (p[:, :, None] >= 0) & (cs[None, None, :] != p[:, :, None])
        u[bad] += _INF

    seen_a = np.where(rs[:, None], cs[:, None], cs[None, :])  # (S', S)
    seen_b = np.where(rs[None, :], cs[None, :], cs[:, None])  # (S', S)
    back = np.zeros((n, m, s_count), dtype=np.int8)
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
    return (states // 2).astype(np.int16), (states % 2).astype(bool), cost


def hint_values(problem: IllusionProblem, model: Model) -> NDArray[np.bool_]:
    """A full assignment of ``model`` from the DP optimum of its per-wale part (a warm start)."""
    yarn, raised, _ = solve_dp(problem)
    return values_from_pattern(model, yarn, raised)


def values_from_pattern(
    model: Model, yarn: NDArray[np.integer], raised: NDArray[np.bool_]
) -> NDArray[np.bool_]:
    """Bool values by variable id for a (yarn, raised) grid, including ``change`` variables."""
    vals = np.zeros(model.pool.top + 1, dtype=bool)
    x = model.pool.block_ids("yarn")
    n, m, _ = x.shape
    ii, jj = np.indices((n, m))
    vals[x[ii, jj, yarn.astype(np.int64)]] = True
    vals[model.pool.block_ids("raised")] = raised
    if "change" in model.pool.blocks:
        vals[model.pool.block_ids("change")] = yarn[:, 1:] != yarn[:, :-1]
    return vals


class DPBackend:
    """Exact per-wale dynamic programming (illusion models without cross-wale terms)."""

    name = "dp"
    extra: str | None = None
    exact = True

    def handles(self, model: Model) -> bool:
        from illuknit.illusion_models import IllusionProblem

        p = model.problem
        return isinstance(p, IllusionProblem) and p.per_wale

    def why_not(self, model: Model) -> str:
        from illuknit.illusion_models import IllusionProblem

        if not isinstance(model.problem, IllusionProblem):
            return (
                "the DP solves only illusion models built by illuknit.illusion_models.build_model"
            )
        return (
            "colour-change terms couple the wales; use --solver cpsat or rc2 for the knit-aware "
            "model (or set color_change=0 and no cap)"
        )

    def is_available(self) -> bool:
        return True

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
        problem = model.problem
        yarn, raised, cost = solve_dp(problem)
        if cost >= _INF:
            wall = time.perf_counter() - t0
            return Solution(Status.INFEASIBLE, None, None, None, wall, {}, self.name, model.pool)
        vals = values_from_pattern(model, yarn, raised)
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
